// LabShaders.h - SPIR-V of the lab's passes, compiled from Shaders/*.comp at build time and
// embedded by EmbedSpirv.cmake (the generated sources live in the build directory).
#pragma once

#include <cstdint>

namespace nrdlab
{

extern const uint32_t g_LabPrimary[];
extern const uint32_t g_LabPrimary_size; // Bytes.
extern const uint32_t g_LabTruth[];
extern const uint32_t g_LabTruth_size;
extern const uint32_t g_LabGradients[];
extern const uint32_t g_LabGradients_size;

} // namespace nrdlab
