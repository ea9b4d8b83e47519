// Evaluates Shaders/Include/Reprojection.glsl on a list of cases (Tests/ReprojectionTests.cpp
// compares every output with a CPU evaluation of the same formulas).
//
// gCases: a header of 5 vec4 (worldToClipPrev columns, then cameraPos.xyz, history size), then
// CASE_INPUTS vec4 per case:
//   0: uvPrev.xy, expectedViewZ, viewZ      1: NoV, threshold, projectY, linearRoughness
//   2: previous viewZ of the 4 footprint taps   3: X.xyz, hitDist   4: surfaceMotion.xyz, packed length
// gResults: CASE_OUTPUTS vec4 per case (see main). The outer taps of Catmull-Rom are tested against
// gPrevViewZ (the footprint's own taps against the case's 4 values).
#version 450
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform texture2D gHistory;
layout(set = 0, binding = 1) uniform texture2D gPrevViewZ;
layout(set = 0, binding = 2, std430) readonly buffer Cases { vec4 gCases[]; };
layout(set = 0, binding = 3, std430) buffer Results { vec4 gResults[]; };
layout(set = 1, binding = 0) uniform sampler gNearestClamp;
layout(push_constant) uniform Push { uint gCaseNum; };

#include "Reprojection.glsl"

#define HEADER 5
#define CASE_INPUTS 5
#define CASE_OUTPUTS 8

void main()
{
    uint c = gl_GlobalInvocationID.x;
    if (c >= gCaseNum)
        return;
    mat4 worldToClipPrev = mat4(gCases[0], gCases[1], gCases[2], gCases[3]);
    vec3 cameraPos = gCases[4].xyz;
    ivec2 size = ivec2(int(gCases[4].w));
    uint base = HEADER + c * CASE_INPUTS;
    vec4 in0 = gCases[base + 0], in1 = gCases[base + 1], prevViewZ = gCases[base + 2];
    vec4 in3 = gCases[base + 3], in4 = gCases[base + 4];

    float tolerance = _NRD_DisocclusionTolerance(in0.w, in0.z, in1.x, in1.y, in1.z);
    NrdReprojection r = _NRD_Reprojection(in0.xy, size, prevViewZ, in0.z, tolerance);
    vec2 uvVirtual = _NRD_VirtualPreviousUv(in3.xyz, in4.xyz, cameraPos, in3.w, in1.w, worldToClipPrev);
    vec2 uvSurface = _NRD_ProjectPrev(in3.xyz + in4.xyz, worldToClipPrev);

    uint o = c * CASE_OUTPUTS;
    gResults[o + 0] = r.weights;
    gResults[o + 1] = vec4(r.footprintWeight, r.isCatmullRomAllowed ? 1.0 : 0.0, tolerance, float(r.footprint.origin.x));
    gResults[o + 2] = _NRD_BilinearHistory(gHistory, r);
    uint outerTaps = _NRD_CatmullRomOuterTaps(gPrevViewZ, r.footprint, size, in0.z, tolerance);
    gResults[o + 3] = r.isCatmullRomAllowed ? _NRD_CatmullRomHistory(gHistory, r.footprint, size, outerTaps) : vec4(0.0);
    gResults[o + 4] = vec4(uvVirtual, _NRD_SpecularDominantFactor(in1.w), _NRD_ParallaxInPixels(uvSurface, uvVirtual, vec2(size)));
    gResults[o + 5] = _NRD_CatmullRomWeights(r.footprint.f.x);
    vec4 gathered = _NRD_GatherFootprint(gPrevViewZ, r.footprint.origin, size);
    gResults[o + 6] = mix(gathered, vec4(-1.0), isnan(gathered)); // Outside the image: -1.
    gResults[o + 7] = vec4(_NRD_UnpackHistoryLength(in4.w), _NRD_PackHistoryLength(in4.w * 300.0), float(r.footprint.origin.y),
                           float(outerTaps));
}
