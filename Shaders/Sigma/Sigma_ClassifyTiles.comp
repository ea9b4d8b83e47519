// SIGMA tile classification (document 004, SIGMA: "pay for what you use"). One workgroup per 16x16
// tile: the tile is MIXED if its non-sky input varies (a penumbra to denoise), UNIFORM if it is
// constant (all lit, all in umbra, or any constant translucency), SKY if it has no pixel to
// denoise. .y stores the largest kernel radius of its occluded pixels, so the filtering passes can
// dilate the map by how far their kernels reach.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Sigma_ClassifyTiles.resources.h"
#include "CommonFrame.glsl"
#include "Sigma_Common.glsl"

#if SIGMA_TRANSLUCENCY
#define SIGMA_CHANNELS 4
#else
#define SIGMA_CHANNELS 1
#endif

// Signal values are in [0, 1]: their float bits order like the values (sign bit masked off).
shared uint s_Min[SIGMA_CHANNELS];
shared uint s_Max[SIGMA_CHANNELS];
shared uint s_Radius;
shared uint s_NonSky;

void main()
{
    uint localIndex = gl_LocalInvocationIndex;
    if (localIndex < SIGMA_CHANNELS)
    {
        s_Min[localIndex] = 0x7FFFFFFFu;
        s_Max[localIndex] = 0u;
    }
    if (localIndex == 0u)
    {
        s_Radius = 0u;
        s_NonSky = 0u;
    }
    barrier();

    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (all(lessThan(uvec2(pixel), gResourceSize)))
    {
        float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
        if (!_NRD_IsSky(viewZ))
        {
            atomicOr(s_NonSky, 1u);
            vec2 shadowData = texelFetch(sampler2D(gIn_ShadowData, gNearestClamp), pixel, 0).xy;
#if SIGMA_TRANSLUCENCY
            vec4 signal = _Sigma_Signal01(texelFetch(sampler2D(gIn_ShadowTranslucency, gNearestClamp), pixel, 0));
            for (int c = 0; c < 4; c++)
            {
                uint bits = floatBitsToUint(signal[c]) & 0x7FFFFFFFu;
                atomicMin(s_Min[c], bits);
                atomicMax(s_Max[c], bits);
            }
#else
            uint bits = floatBitsToUint(_Sigma_Signal01(shadowData.x)) & 0x7FFFFFFFu;
            atomicMin(s_Min[0], bits);
            atomicMax(s_Max[0], bits);
#endif
            float penumbra = _Sigma_PenumbraPixels(shadowData.y);
            if (penumbra > 0.0)
                atomicMax(s_Radius, floatBitsToUint(_Sigma_KernelRadius(penumbra)));
        }
    }
    barrier();

    if (localIndex == 0u)
    {
        bool varies = false;
        for (int c = 0; c < SIGMA_CHANNELS; c++)
            varies = varies || s_Max[c] > s_Min[c];
        float state = s_NonSky == 0u ? SIGMA_TILE_SKY : (varies ? SIGMA_TILE_MIXED : SIGMA_TILE_UNIFORM);
        imageStore(gOut_Tiles, ivec2(gl_WorkGroupID.xy), vec4(state, uintBitsToFloat(s_Radius), 0.0, 0.0));
    }
}
