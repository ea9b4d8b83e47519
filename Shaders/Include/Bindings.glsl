// GLSL side of the per-pass resource declarations (<Pass>.resources.h). The same declaration file
// is read by the C++ description builder through Source/PassDecl.h, so binding order and the
// constant block cannot drift apart.
//
// A declaration file lists, in this order:
//   NRD_PASS_BEGIN(Name, groupSizeX, groupSizeY)
//   NRD_CONSTANTS_BEGIN ... NRD_CONSTANT(type, gName) ... NRD_CONSTANTS_END   (or NRD_NO_CONSTANTS)
//   NRD_INPUT(binding, gIn_X) / NRD_INPUT_UINT / NRD_INOUT(binding, gX, format) / NRD_INOUT_UINT /
//   NRD_OUTPUT(binding, gOut_X) / NRD_BUFFER(binding, gX, type) / NRD_RW_BUFFER(binding, gX, type)
//   NRD_PASS_END
// Constant types: float, int, uint, vec2, ivec2, uvec2, vec4, ivec4, uvec4, mat4 (std140, no vec3
// and no arrays, so the C++ mirror has the same offsets).
#ifndef NRD_BINDINGS_GLSL
#define NRD_BINDINGS_GLSL

#include "CommonConstants.h"

#define NRD_RESOURCES_SET 0
#define NRD_CONSTANTS_SET 1

#define NRD_PASS_BEGIN(name, groupX, groupY) layout(local_size_x = groupX, local_size_y = groupY, local_size_z = 1) in;
#define NRD_PASS_END

#define NRD_CONSTANTS_BEGIN layout(set = NRD_CONSTANTS_SET, binding = 0, std140) uniform NrdConstants {
#define NRD_CONSTANT(type, name) type name;
#define NRD_CONSTANTS_END };
#define NRD_NO_CONSTANTS

// Sampled textures (read-only).
#define NRD_INPUT(index, name) layout(set = NRD_RESOURCES_SET, binding = index) uniform texture2D name;
#define NRD_INPUT_UINT(index, name) layout(set = NRD_RESOURCES_SET, binding = index) uniform utexture2D name;

// Storage images. Outputs of the application are written without a format qualifier (any format).
#define NRD_OUTPUT(index, name) layout(set = NRD_RESOURCES_SET, binding = index) uniform writeonly image2D name;
#define NRD_INOUT(index, name, fmt) layout(set = NRD_RESOURCES_SET, binding = index, fmt) uniform image2D name;
#define NRD_INOUT_UINT(index, name, fmt) layout(set = NRD_RESOURCES_SET, binding = index, fmt) uniform uimage2D name;

// Storage buffers.
#define NRD_BUFFER(index, name, type) layout(set = NRD_RESOURCES_SET, binding = index, std430) readonly buffer name##_Block { type name[]; };
#define NRD_RW_BUFFER(index, name, type) layout(set = NRD_RESOURCES_SET, binding = index, std430) buffer name##_Block { type name[]; };

// Static samplers, DenoiserDesc::samplers order (nrd::Sampler).
layout(set = NRD_CONSTANTS_SET, binding = 1) uniform sampler gNearestClamp;
layout(set = NRD_CONSTANTS_SET, binding = 2) uniform sampler gLinearClamp;

#endif
