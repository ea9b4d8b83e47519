// Evaluates _NRD_Fp16Converge (Shaders/Include/Common.glsl) for Fp16ConvergeTests.cpp: one call per
// case, and a history blended towards a constant target frame after frame, stored in fp16, with and
// without it; and _NRD_NearestFp16 of the case's x.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Common.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

// Per case, 4 floats: x, history, target, the blend weight of the history (for the sequences).
layout(set = 0, binding = 0, std430) readonly buffer Cases { float gCases[]; };
// Per case, 5 floats: _NRD_Fp16Converge(x, history, target); the history after 1024 frames of
// mix(target, history, weight) stored in fp16 through _NRD_Fp16Converge, and without it; the first
// frame at which the former equals the target (1024 if none); _NRD_NearestFp16(x).
layout(set = 0, binding = 1, std430) buffer Results { float gResults[]; };
layout(push_constant) uniform Push { uint gCaseNum; };

float StoreFp16(float x) { return unpackHalf2x16(packHalf2x16(vec2(x, 0.0))).x; }

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= gCaseNum)
        return;
    float x = gCases[i * 4u + 0u], history = gCases[i * 4u + 1u], target = gCases[i * 4u + 2u], weight = gCases[i * 4u + 3u];
    float converged = StoreFp16(history), plain = StoreFp16(history);
    float reached = 1024.0;
    for (int frame = 0; frame < 1024; frame++)
    {
        converged = StoreFp16(_NRD_Fp16Converge(mix(target, converged, weight), converged, target));
        plain = StoreFp16(mix(target, plain, weight));
        if (converged == target && reached == 1024.0)
            reached = float(frame);
    }
    gResults[i * 5u + 0u] = _NRD_Fp16Converge(x, history, target);
    gResults[i * 5u + 1u] = converged;
    gResults[i * 5u + 2u] = plain;
    gResults[i * 5u + 3u] = reached;
    gResults[i * 5u + 4u] = _NRD_NearestFp16(x);
}
