// SIGMA penumbra-driven blur (document 004, SIGMA), first spatial pass.
//
// 1. Penumbra estimate: occluded pixels know their penumbra radius, lit ones do not. The center's
//    penumbra is the weighted mean over the occluded pixels of a dense 5x5 window (shared memory),
//    preferring smaller penumbrae (1 / (1 + radius)) so wide penumbrae do not bleed into narrow ones.
// 2. Kernel radius = penumbra radius * gBlurRadiusScale (pixels; SigmaSettings::blurRadiusScale times
//    the ratio chosen in Source/Sigma.cpp), at most 32.
// 3. Filter: dense 5x5 around the center plus an 8-tap rotated disk on the tangent plane, Gaussian
//    falloff, plane-distance and normal weights; sky samples are skipped. The sparse samples also
//    refine the penumbra estimate, which the next passes reuse.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Sigma_Blur.resources.h"
#include "CommonFrame.glsl"
#include "Sigma_Common.glsl"

#define BORDER 2 // Dense window radius
#define SMEM_SIZE (SIGMA_TILE_SIZE + 2 * BORDER)
#define SPARSE_SAMPLE_NUM 8u

shared float s_ViewZ[SMEM_SIZE][SMEM_SIZE]; // 0 = sky or outside the image
shared float s_Penumbra[SMEM_SIZE][SMEM_SIZE]; // pixels, SIGMA_UNKNOWN_PENUMBRA where lit
shared SIGMA_TYPE s_Signal[SMEM_SIZE][SMEM_SIZE];

SIGMA_TYPE LoadSignal(ivec2 pixel, float visibility)
{
#if SIGMA_TRANSLUCENCY
    return _Sigma_Signal01(texelFetch(sampler2D(gIn_ShadowTranslucency, gNearestClamp), pixel, 0));
#else
    return _Sigma_Signal01(visibility);
#endif
}

void Preload(ivec2 smemPos, ivec2 pixel)
{
    float viewZ = 0.0;
    float penumbra = SIGMA_UNKNOWN_PENUMBRA;
    SIGMA_TYPE signal = SIGMA_TYPE(1.0);
    if (all(greaterThanEqual(pixel, ivec2(0))) && all(lessThan(uvec2(pixel), gResourceSize)))
    {
        float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
        if (!_NRD_IsSky(z))
        {
            vec2 shadowData = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), pixel, 0).xy;
            viewZ = z;
            penumbra = _Sigma_PenumbraPixels(shadowData.y);
            signal = LoadSignal(pixel, shadowData.x);
        }
    }
    s_ViewZ[smemPos.y][smemPos.x] = viewZ;
    s_Penumbra[smemPos.y][smemPos.x] = penumbra;
    s_Signal[smemPos.y][smemPos.x] = signal;
}

void main()
{
    uint mode = _Sigma_GroupTileMode(gIn_TileModes);
    if (mode == SIGMA_MODE_SKY)
        return;

    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool isInside = all(lessThan(uvec2(pixel), gResourceSize));

    if (mode == SIGMA_MODE_COPY)
    {
        if (!isInside)
            return;
        float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
        if (_NRD_IsSky(viewZ))
            return;
        vec2 shadowData = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), pixel, 0).xy;
        imageStore(gOut_Shadow, pixel, vec4(LoadSignal(pixel, shadowData.x)));
        imageStore(gOut_Penumbra, pixel, vec4(_Sigma_PenumbraPixels(shadowData.y)));
        return;
    }

    ivec2 groupOrigin = ivec2(gl_WorkGroupID.xy) * SIGMA_TILE_SIZE - BORDER;
    for (uint i = gl_LocalInvocationIndex; i < uint(SMEM_SIZE * SMEM_SIZE); i += uint(SIGMA_TILE_SIZE * SIGMA_TILE_SIZE))
    {
        ivec2 smemPos = ivec2(int(i % uint(SMEM_SIZE)), int(i / uint(SMEM_SIZE)));
        Preload(smemPos, groupOrigin + smemPos);
    }
    barrier();

    ivec2 c = ivec2(gl_LocalInvocationID.xy) + BORDER;
    float viewZ = s_ViewZ[c.y][c.x];
    if (!isInside || viewZ == 0.0)
        return; // Sky: not written.

    vec2 uv = _NRD_PixelUv(pixel);
    vec3 Xv = _NRD_ViewPosition(uv, viewZ);
    vec3 N = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), pixel, 0)).xyz;
    vec3 Nv = _Sigma_ViewNormal(N);
    SigmaPlane plane = _Sigma_Plane(uv, viewZ, Nv);

    // 1. Penumbra estimate (dense 5x5, Gaussian sigma 1.5 px). The geometry weights are kept for 3a.
    float geometryWeights[(2 * BORDER + 1) * (2 * BORDER + 1)];
    float penumbraSum = 0.0;
    float penumbraWeightSum = 0.0;
    for (int j = -BORDER; j <= BORDER; j++)
    {
        for (int i = -BORDER; i <= BORDER; i++)
        {
            float z = s_ViewZ[c.y + j][c.x + i];
            float g = z == 0.0 ? 0.0 : _Sigma_NeighbourPlaneWeight(plane, i, j, z);
            geometryWeights[(j + BORDER) * (2 * BORDER + 1) + i + BORDER] = g;
            float p = s_Penumbra[c.y + j][c.x + i];
            float w = p < 0.0 ? 0.0 : g * exp(-0.222 * float(i * i + j * j)) / (1.0 + p);
            penumbraSum += p * w;
            penumbraWeightSum += w;
        }
    }

    SIGMA_TYPE center = s_Signal[c.y][c.x];
    float penumbra = penumbraWeightSum > 0.0 ? penumbraSum / penumbraWeightSum : SIGMA_UNKNOWN_PENUMBRA;
    float radius = _Sigma_KernelRadius(max(penumbra, 0.0));
    if (radius < 0.5)
    {
        // No penumbra around (or a sub-pixel one): the input is already the answer.
        imageStore(gOut_Shadow, pixel, vec4(center));
        imageStore(gOut_Penumbra, pixel, vec4(penumbra));
        return;
    }

    // 3a. Dense 5x5 (the center has weight 1; distances: _Sigma_DenseDistance2).
    SIGMA_TYPE sum = SIGMA_TYPE(0.0);
    float weightSum = 0.0;
    SigmaDenseKernel denseKernel = _Sigma_DenseKernel(Xv, viewZ, Nv, radius * viewZ / gProjectY);
    float invRadius2 = 1.0 / (radius * radius);
    for (int j = -BORDER; j <= BORDER; j++)
    {
        for (int i = -BORDER; i <= BORDER; i++)
        {
            float g = geometryWeights[(j + BORDER) * (2 * BORDER + 1) + i + BORDER];
            float d2 = _Sigma_DenseDistance2(float(i * i + j * j) * invRadius2, denseKernel, i, j, s_ViewZ[c.y + j][c.x + i]);
            float w = g == 0.0 ? 0.0 : _Sigma_KernelWeight(d2) * g;
            sum += s_Signal[c.y + j][c.x + i] * w;
            weightSum += w;
        }
    }

    // 3b. Sparse rotated disk on the tangent plane.
    SigmaKernel kernel = _Sigma_Kernel(Xv, Nv, radius * viewZ / gProjectY, _Sigma_KernelAngle(pixel, 0u));
    for (uint n = 0u; n < SPARSE_SAMPLE_NUM; n++)
    {
        vec3 o = kSigmaDisk8[n];
        ivec2 q;
        if (!_Sigma_KernelSamplePixel(kernel, o.xy, q))
            continue;
        float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
        if (_NRD_IsSky(z))
            continue;
        vec3 Ns = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), q, 0)).xyz;
        vec2 shadowData = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), q, 0).xy;

        float w = o.z * _Sigma_NeighbourPlaneWeight(plane, q.x - pixel.x, q.y - pixel.y, z) *
                  _Sigma_NormalWeight(N, Ns);
        sum += LoadSignal(q, shadowData.x) * w;
        weightSum += w;

        float p = _Sigma_PenumbraPixels(shadowData.y);
        if (p >= 0.0)
        {
            float pw = w / (1.0 + p);
            penumbraSum += p * pw;
            penumbraWeightSum += pw;
        }
    }

    float refinedPenumbra = penumbraWeightSum > 0.0 ? penumbraSum / penumbraWeightSum : penumbra;
    imageStore(gOut_Shadow, pixel, vec4(sum / weightSum));
    imageStore(gOut_Penumbra, pixel, vec4(refinedPenumbra));
}
