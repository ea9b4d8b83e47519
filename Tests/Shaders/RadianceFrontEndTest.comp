// Evaluates the radiance + hit distance helpers of NRD.glsl (and the private de-normalization of
// Common.glsl) on a list of cases, for RadianceFrontEndTests.cpp.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Common.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

// Per case, 16 floats: hitDist, viewZ, roughness, sanitize (0 / 1), hitDistParams (4),
// radiance.rgb + normHitDist to pack (4), bounceIndex, roughnessAlongPath, importance, unused.
layout(set = 0, binding = 0, std430) readonly buffer Cases { float gCases[]; };
// Per case, 12 floats: normHitDist, its de-normalization, corrected hit distance, unused,
// the packed texel (4), the unpacked texel (4) of the 4 floats at case offset 8.
layout(set = 0, binding = 1, std430) buffer Results { float gResults[]; };
layout(push_constant) uniform Push { uint gCaseNum; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= gCaseNum)
        return;
    uint c = i * 16u;
    float hitDist = gCases[c + 0u];
    float viewZ = gCases[c + 1u];
    float roughness = gCases[c + 2u];
    bool sanitize = gCases[c + 3u] != 0.0;
    vec4 params = vec4(gCases[c + 4u], gCases[c + 5u], gCases[c + 6u], gCases[c + 7u]);
    vec4 texel = vec4(gCases[c + 8u], gCases[c + 9u], gCases[c + 10u], gCases[c + 11u]);

    float normHitDist = REBLUR_FrontEnd_GetNormHitDist(hitDist, viewZ, params, roughness);
    vec4 packed = REBLUR_FrontEnd_PackRadianceAndNormHitDist(texel.xyz, texel.w, sanitize);
    vec4 unpacked = REBLUR_BackEnd_UnpackRadianceAndNormHitDist(texel);

    uint r = i * 12u;
    gResults[r + 0u] = normHitDist;
    gResults[r + 1u] = _NRD_GetHitDist(normHitDist, viewZ, params, roughness);
    gResults[r + 2u] = NRD_GetCorrectedHitDist(hitDist, gCases[c + 12u], gCases[c + 13u], gCases[c + 14u]);
    gResults[r + 3u] = 0.0;
    for (uint k = 0u; k < 4u; k++)
    {
        gResults[r + 4u + k] = packed[k];
        gResults[r + 8u + k] = unpacked[k];
    }
}
