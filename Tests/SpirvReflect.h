// Minimal SPIR-V reflection for tests: descriptor bindings and uniform block sizes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace nrdtest
{

enum class SpirvDescriptor
{
    SAMPLED_IMAGE,
    STORAGE_IMAGE,
    SAMPLER,
    UNIFORM_BUFFER,
    STORAGE_BUFFER,
    READONLY_STORAGE_BUFFER,
    OTHER,
};

struct SpirvBinding
{
    uint32_t set = 0;
    uint32_t binding = 0;
    SpirvDescriptor type = SpirvDescriptor::OTHER;
    uint32_t blockSize = 0; // Uniform blocks: std140 size rounded up to 16.
    std::string name;
};

struct SpirvModule
{
    std::vector<SpirvBinding> bindings; // Only variables used by the entry point are not filtered.
    uint32_t localSize[3] = {0, 0, 0};
};

// Parses 'words'; returns false (with 'error') on a malformed module.
bool ReflectSpirv(const uint32_t* words, size_t wordCount, SpirvModule& out, std::string& error);

} // namespace nrdtest
