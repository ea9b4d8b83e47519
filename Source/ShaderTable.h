// Embedded SPIR-V of every pass, generated at build time (Shaders/CMakeLists.txt).
#pragma once

#include <cstdint>

namespace nrd
{

struct ShaderBytecode
{
    const char* name;
    const uint32_t* words;
    uint32_t size; // Bytes.
};

const ShaderBytecode* GetShaderTable(uint32_t& count);

} // namespace nrd
