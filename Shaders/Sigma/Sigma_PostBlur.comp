// SIGMA post-blur (document 004, SIGMA), second spatial pass: the same tangent-plane kernel at half
// the radius, rotated independently of the first pass, over the first pass's result. Dense 3x3
// plus an 8-tap sparse disk; the penumbra estimate comes from the first pass.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Sigma_PostBlur.resources.h"
#include "CommonFrame.glsl"
#include "Sigma_Common.glsl"

#define RADIUS_SCALE 0.5
#define SPARSE_SAMPLE_NUM 8u

SIGMA_TYPE LoadBlurred(ivec2 pixel)
{
#if SIGMA_TRANSLUCENCY
    return _Sigma_Signal01(texelFetch(sampler2D(gIn_Shadow, gNearestClamp), pixel, 0));
#else
    return _Sigma_Signal01(texelFetch(sampler2D(gIn_Shadow, gNearestClamp), pixel, 0).x);
#endif
}

// The filter proper (mode DENOISE, radius >= 0.5 px).
SIGMA_TYPE Filter(ivec2 pixel, float viewZ, SIGMA_TYPE center, float radius)
{
    vec2 uv = _NRD_PixelUv(pixel);
    vec3 Xv = _NRD_ViewPosition(uv, viewZ);
    vec3 N = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), pixel, 0)).xyz;
    vec3 Nv = _Sigma_ViewNormal(N);
    SigmaPlane plane = _Sigma_Plane(uv, viewZ, Nv);

    SIGMA_TYPE sum = center;
    float weightSum = 1.0;
    float invRadius2 = 1.0 / (radius * radius);
    SigmaDenseKernel denseKernel = _Sigma_DenseKernel(Xv, viewZ, Nv, radius * viewZ / gProjectY);

    // Dense 3x3.
    for (int j = -1; j <= 1; j++)
    {
        for (int i = -1; i <= 1; i++)
        {
            ivec2 q = pixel + ivec2(i, j);
            if ((i == 0 && j == 0) || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(uvec2(q), gResourceSize)))
                continue;
            float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
            if (_NRD_IsSky(z))
                continue;
            float d2 = _Sigma_DenseDistance2(float(i * i + j * j) * invRadius2, denseKernel, i, j, z);
            float w = _Sigma_KernelWeight(d2) * _Sigma_NeighbourPlaneWeight(plane, i, j, z);
            sum += LoadBlurred(q) * w;
            weightSum += w;
        }
    }

    // Sparse rotated disk on the tangent plane.
    SigmaKernel kernel = _Sigma_Kernel(Xv, Nv, radius * viewZ / gProjectY, _Sigma_KernelAngle(pixel, 0x9e3779b9u));
    for (uint n = 0u; n < SPARSE_SAMPLE_NUM; n++)
    {
        vec3 o = kSigmaDisk8[n];
        ivec2 q;
        if (!_Sigma_KernelSamplePixel(kernel, o.xy, q))
            continue;
        float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
        if (_NRD_IsSky(z))
            continue;
        // Plane distance only: the first pass already kept other surfaces out of the signal.
        float w = o.z * _Sigma_NeighbourPlaneWeight(plane, q.x - pixel.x, q.y - pixel.y, z);
        sum += LoadBlurred(q) * w;
        weightSum += w;
    }

    return sum / weightSum;
}

void main()
{
    uint mode = _Sigma_GroupTileMode(gIn_TileModes);
    if (mode == SIGMA_MODE_SKY)
        return;

    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), gResourceSize)))
        return;
    float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
    if (_NRD_IsSky(viewZ))
        return; // Sky: not written.

    SIGMA_TYPE center = LoadBlurred(pixel);
    float penumbra = texelFetch(sampler2D(gIn_Penumbra, gNearestClamp), pixel, 0).x;
    float radius = _Sigma_KernelRadius(max(_NRD_Sanitize(penumbra, 0.0), 0.0)) * RADIUS_SCALE;

    SIGMA_TYPE result = center;
    if (mode == SIGMA_MODE_DENOISE && radius >= 0.5)
        result = Filter(pixel, viewZ, center, radius);
    imageStore(gOut_Shadow, pixel, vec4(result));
}
