// LabShaders.h - SPIR-V of the lab's shader variants, compiled from Shaders/*.comp at build time
// (CMakeLists.txt lists the variants) and embedded as arrays generated in the build directory.
#pragma once

#include <cstdint>

namespace nrdlab
{

struct LabShaderBlob
{
    const char* name;     // e.g. "LabTruth_Diffuse_b1d1"
    const uint32_t* words;
    uint32_t size;        // Bytes.
};

// Every variant; static storage.
const LabShaderBlob* GetLabShaders(uint32_t& count);

} // namespace nrdlab
