#version 450
#extension GL_GOOGLE_include_directive : require

// REFLECTION blur (document 002, "blur"). One 8x8 group per listed tile.

#define REFLECTION_DENOISE_PASS
#include "Bindings.glsl"
#include "Reflection_Constants.h"
#include "Reflection_Blur.resources.h"
#include "CommonFrame.glsl"
#include "Reflection_Common.glsl"

void main()
{
    ivec2 pixel = ivec2(_RF_TilePixel(gTileList[gl_WorkGroupID.x]));
    RfSurface c = _RF_LoadSurface(gIn_ViewZ, gIn_NormalRoughness, pixel);
    if (!c.needsDenoiser)
        return;
    vec3 Xc = _NRD_WorldPosition(_NRD_PixelUv(pixel), c.viewZ);
    const float kGauss[3] = float[3](6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0);
    // Within the reflection's footprint (from the spatially filtered hit distance).
    float footprint = _RF_FootprintSigma(_RF_LoadRadiance(gIn_Temporal, pixel).w, c.viewZ, c.roughness, gHitDistParams);
    float inv2Sigma2 = 0.5 / (footprint * footprint);
    vec4 sum = vec4(0.0);
    float weightSum = 0.0;
    for (int y = -2; y <= 2; y++)
    {
        for (int x = -2; x <= 2; x++)
        {
            ivec2 p = pixel + ivec2(x, y);
            float w = kGauss[abs(x)] * kGauss[abs(y)];
            if (x != 0 || y != 0)
            {
                RfSurface s = _RF_LoadSurface(gIn_ViewZ, gIn_NormalRoughness, p);
                vec3 Xs = _NRD_WorldPosition(_NRD_PixelUv(p), s.viewZ);
                w *= _RF_EdgeWeight(c, Xc, s, Xs, gNormalSigma) * exp(-dot(Xs - Xc, Xs - Xc) * inv2Sigma2);
            }
            if (w <= 0.0)
                continue;
            sum += _RF_LoadRadiance(gIn_Temporal, p) * w;
            weightSum += w;
        }
    }
    imageStore(gOut_Output, pixel, _NRD_ClampToHalf(sum / weightSum));
}
