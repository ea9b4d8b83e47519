// C++ side of the per-pass resource declarations (Shaders/<Method>/<Pass>.resources.h); the GLSL
// side is Shaders/Include/Bindings.glsl. Including a declaration file after this header defines
//   struct <Pass> { kName, kGroupX, kGroupY, Constants (std140 mirror), kHasConstants, kBindings[] }.
#pragma once

#include "NRD.h"
#include "../Shaders/Include/CommonConstants.h"

#include <cstddef>
#include <cstdint>

namespace nrd
{

// std140 mirrors of the GLSL types allowed in a constant block (no vec3, no arrays).
namespace glsl
{
typedef uint32_t uint;
struct alignas(8) vec2 { float x, y; };
struct alignas(8) ivec2 { int32_t x, y; };
struct alignas(8) uvec2 { uint32_t x, y; };
struct alignas(16) vec4 { float x, y, z, w; };
struct alignas(16) ivec4 { int32_t x, y, z, w; };
struct alignas(16) uvec4 { uint32_t x, y, z, w; };
struct alignas(16) mat4 { float m[16]; }; // Column-major.
} // namespace glsl

struct BindingDecl
{
    DescriptorType descriptorType;
    uint32_t binding;
    const char* name;
    bool isUint; // Integer texture / image.
};

template <size_t N>
constexpr bool BindingsAreSequential(const BindingDecl (&bindings)[N])
{
    for (size_t i = 0; i < N; i++)
    {
        if (bindings[i].binding != i)
            return false;
    }
    return true;
}

} // namespace nrd

#define NRD_PASS_BEGIN(name, groupX, groupY)          \
    struct name                                       \
    {                                                 \
        static constexpr const char* kName = #name;   \
        static constexpr uint16_t kGroupX = groupX;   \
        static constexpr uint16_t kGroupY = groupY;
#define NRD_CONSTANTS_BEGIN struct alignas(16) Constants {
#define NRD_CONSTANT(type, name) type name;
#define NRD_CONSTANTS_END                              \
        };                                             \
        static constexpr bool kHasConstants = true;    \
        static constexpr BindingDecl kBindings[] = {
#define NRD_NO_CONSTANTS                               \
        struct Constants { };                          \
        static constexpr bool kHasConstants = false;   \
        static constexpr BindingDecl kBindings[] = {
#define NRD_INPUT(index, name) {DescriptorType::TEXTURE, index, #name, false},
#define NRD_INPUT_UINT(index, name) {DescriptorType::TEXTURE, index, #name, true},
#define NRD_OUTPUT(index, name) {DescriptorType::STORAGE_TEXTURE, index, #name, false},
#define NRD_INOUT(index, name, fmt) {DescriptorType::STORAGE_TEXTURE, index, #name, false},
#define NRD_INOUT_UINT(index, name, fmt) {DescriptorType::STORAGE_TEXTURE, index, #name, true},
#define NRD_BUFFER(index, name, type) {DescriptorType::BUFFER, index, #name, false},
#define NRD_RW_BUFFER(index, name, type) {DescriptorType::STORAGE_BUFFER, index, #name, false},
#define NRD_PASS_END                                                                              \
        };                                                                                        \
        static constexpr uint32_t kBindingsNum = uint32_t(sizeof(kBindings) / sizeof(kBindings[0])); \
    };

// Opens the namespace in which declaration files are included:
//   namespace nrd { namespace passes { NRD_PASS_TYPES #include "..." } }
#define NRD_PASS_TYPES using namespace ::nrd::glsl;
