// Evaluates _NRD_DiskFractionBeyondChord (Shaders/Include/Common.glsl) on a list of chord offsets,
// for DiskFractionTests.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Common.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

// Per case, 1 float: the chord's signed distance from the disk's centre, in radii.
layout(set = 0, binding = 0, std430) readonly buffer Cases { float gCases[]; };
// Per case, 1 float: the fraction of the disk beyond the chord.
layout(set = 0, binding = 1, std430) buffer Results { float gResults[]; };
layout(push_constant) uniform Push { uint gCaseNum; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= gCaseNum)
        return;
    gResults[i] = _NRD_DiskFractionBeyondChord(gCases[i]);
}
