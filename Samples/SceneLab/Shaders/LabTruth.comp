// LabTruth.comp - ground truth of one signal (LAB_SIGNAL): adds samples [first, first + count) to
// per-pixel sums, for the same primary hit as the noisy input. The host runs it in chunks (each
// dispatch a few samples, so a CPU implementation never stalls for long) and divides at the end.
// Sample s uses sample index 1 + s: the noisy input (index 0) is not part of its own truth.
// Accumulator layouts: LabShared.glsl. Sky pixels are left at 0.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "LabScene.glsl"

layout(local_size_x = LAB_GROUP_X, local_size_y = LAB_GROUP_Y, local_size_z = 1) in;

layout(push_constant) uniform LabTruthChunkBlock
{
    LabTruthChunk chunk;
};

layout(set = 0, binding = LAB_BINDING_ACC_A, rgba32f) uniform image2D gAcc_A;
#if LAB_SIGNAL != LAB_SIGNAL_SHADOW
layout(set = 0, binding = LAB_BINDING_ACC_B, rgba32f) uniform image2D gAcc_B;
#endif

void main()
{
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(pixel, c.gSize.xy)))
        return;
    ivec2 ip = ivec2(pixel);
    uint frame = c.gSize.z;
    uint seed = c.gSize.w;
    uint first = chunk.gChunk.x;
    uint count = chunk.gChunk.y;
    bool restart = first == 0u;

    vec4 accA = restart ? vec4(0.0) : imageLoad(gAcc_A, ip);
#if LAB_SIGNAL != LAB_SIGNAL_SHADOW
    vec4 accB = restart ? vec4(0.0) : imageLoad(gAcc_B, ip);
#endif

    vec3 origin, dir;
    PrimaryRay(pixel, 0u, origin, dir);
    Hit h = TraceClosest(origin, dir, LAB_NO_HIT, 0u);
    if (h.object >= 0)
    {
        Surface s = GetSurface(h);
        vec3 V = -dir;
        float viewZ = ViewZ(h.pos, 0u);
        for (uint k = 0u; k < count; k++)
        {
            uint sampleIndex = 1u + first + k;
#if LAB_SIGNAL == LAB_SIGNAL_SHADOW
            uint rng = InitRng(pixel, frame, sampleIndex, seed, LAB_STREAM_SHADOW);
            LightSample ls = SampleLight(c.gCounts.z, 0u, h.pos, s.N, Next2(rng));
            accA.x += Visibility(ls, h.pos, s.N, 0u);
#elif LAB_SIGNAL == LAB_SIGNAL_TRANSLUCENCY
            uint rng = InitRng(pixel, frame, sampleIndex, seed, LAB_STREAM_TRANSLUCENCY);
            float visibleNum = 0.0;
            for (uint li = 0u; li < c.gCounts.y; li++)
            {
                LightSample ls = SampleLight(li, 0u, h.pos, s.N, Next2(rng));
                float v = Visibility(ls, h.pos, s.N, 0u);
                accA.xyz += ls.E;
                accB.xyz += ls.E * v;
                visibleNum += v;
            }
            accA.w += c.gCounts.y > 0u ? visibleNum / float(c.gCounts.y) : 1.0;
#elif LAB_SIGNAL == LAB_SIGNAL_DIFFUSE || LAB_SIGNAL == LAB_SIGNAL_SPECULAR
#  if LAB_SIGNAL == LAB_SIGNAL_DIFFUSE
            uint rng = InitRng(pixel, frame, sampleIndex, seed, LAB_STREAM_DIFFUSE);
            vec4 v = DiffuseSample(s, 0u, rng);
            float roughness = 1.0;
#  else
            uint rng = InitRng(pixel, frame, sampleIndex, seed, LAB_STREAM_SPECULAR);
            vec4 v = SpecularSample(s, V, 0u, rng);
            float roughness = s.linearRoughness;
#  endif
            // The radiance as it is (its mean is the truth), the hit distance normalized as the noisy
            // input is: the truth of the normalized hit distance (AO / SO) is its mean.
            accA.rgb += v.rgb;
            accB.y += REBLUR_FrontEnd_GetNormHitDist(v.w, viewZ, c.gHitDistParams, roughness);
#endif
        }
    }

    imageStore(gAcc_A, ip, accA);
#if LAB_SIGNAL != LAB_SIGNAL_SHADOW
    imageStore(gAcc_B, ip, accB);
#endif
}
