// LabTruth.comp - ground truth: adds samples [first, first + count) of every requested signal to
// per-pixel sums, for the same primary hit as the noisy input. The host runs it in chunks (each
// dispatch a few samples, so a CPU implementation never stalls for long) and divides at the end.
// Sample s uses sample index 1 + s: the noisy input (index 0) is not part of its own truth.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "LabScene.glsl"

layout(local_size_x = LAB_GROUP_X, local_size_y = LAB_GROUP_Y, local_size_z = 1) in;

layout(push_constant) uniform LabTruthChunkBlock
{
    LabTruthChunk chunk;
};

layout(set = 0, binding = LAB_BINDING_ACC_SHADOW, rgba32f) uniform image2D gAcc_Shadow;
layout(set = 0, binding = LAB_BINDING_ACC_TRANSLUCENCY, rgba32f) uniform image2D gAcc_Translucency;
layout(set = 0, binding = LAB_BINDING_ACC_DIFFUSE, rgba32f) uniform image2D gAcc_Diffuse;
layout(set = 0, binding = LAB_BINDING_ACC_SPECULAR, rgba32f) uniform image2D gAcc_Specular;
layout(set = 0, binding = LAB_BINDING_ACC_COUNT, rgba32f) uniform image2D gAcc_Count;

void main()
{
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, c.gSize.xy)))
        return;
    ivec2 ip = ivec2(pixel);
    uint signals = c.gCounts.w;
    uint frame = c.gSize.z;
    uint seed = c.gSize.w;
    uint first = chunk.gChunk.x;
    uint count = chunk.gChunk.y;
    bool restart = first == 0u;

    vec4 accShadow = restart ? vec4(0.0) : imageLoad(gAcc_Shadow, ip);
    vec4 accTranslucency = restart ? vec4(0.0) : imageLoad(gAcc_Translucency, ip);
    vec4 accDiffuse = restart ? vec4(0.0) : imageLoad(gAcc_Diffuse, ip);
    vec4 accSpecular = restart ? vec4(0.0) : imageLoad(gAcc_Specular, ip);
    vec4 accCount = restart ? vec4(0.0) : imageLoad(gAcc_Count, ip);

    vec3 origin, dir;
    PrimaryRay(pixel, 0u, origin, dir);
    Hit h = TraceClosest(origin, dir, LAB_NO_HIT, 0u);
    if (h.object >= 0)
    {
        Surface s = GetSurface(h);
        vec3 V = -dir;
        for (uint k = 0u; k < count; k++)
        {
            uint sampleIndex = 1u + first + k;
            if ((signals & LAB_SIGNAL_SHADOW) != 0u)
            {
                uint rng = InitRng(pixel, frame, sampleIndex, seed, LAB_STREAM_SHADOW);
                LightSample ls = SampleLight(c.gCounts.z, 0u, h.pos, s.N, Next2(rng));
                accShadow.x += Visibility(ls, h.pos, s.N, 0u);
            }
            if ((signals & LAB_SIGNAL_TRANSLUCENCY) != 0u)
            {
                uint rng = InitRng(pixel, frame, sampleIndex, seed, LAB_STREAM_TRANSLUCENCY);
                float visibleNum = 0.0;
                for (uint li = 0u; li < c.gCounts.y; li++)
                {
                    LightSample ls = SampleLight(li, 0u, h.pos, s.N, Next2(rng));
                    float v = Visibility(ls, h.pos, s.N, 0u);
                    accShadow.yzw += ls.E * v;
                    accTranslucency.xyz += ls.E;
                    visibleNum += v;
                }
                accTranslucency.w += c.gCounts.y > 0u ? visibleNum / float(c.gCounts.y) : 1.0;
            }
            if ((signals & LAB_SIGNAL_DIFFUSE) != 0u)
            {
                uint rng = InitRng(pixel, frame, sampleIndex, seed, LAB_STREAM_DIFFUSE);
                vec4 v = DiffuseSample(s, 0u, rng);
                accDiffuse.rgb += v.rgb;
                if (v.w < NRD_FP16_MAX)
                {
                    accDiffuse.w += v.w;
                    accCount.x += 1.0;
                }
            }
            if ((signals & LAB_SIGNAL_SPECULAR) != 0u)
            {
                uint rng = InitRng(pixel, frame, sampleIndex, seed, LAB_STREAM_SPECULAR);
                vec4 v = SpecularSample(s, V, 0u, rng);
                accSpecular.rgb += v.rgb;
                if (v.w < NRD_FP16_MAX)
                {
                    accSpecular.w += v.w;
                    accCount.y += 1.0;
                }
            }
        }
    }

    imageStore(gAcc_Shadow, ip, accShadow);
    imageStore(gAcc_Translucency, ip, accTranslucency);
    imageStore(gAcc_Diffuse, ip, accDiffuse);
    imageStore(gAcc_Specular, ip, accSpecular);
    imageStore(gAcc_Count, ip, accCount);
}
