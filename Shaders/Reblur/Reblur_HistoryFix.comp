// REBLUR history fix (document 004, REBLUR: "history fix"), first half: anti-firefly (the
// luminance is clamped to mean + gFireflyScale * sigma of the 3x3 neighbours, centre excluded), and
// the accumulated signal, the fast history + length and the reprojected stabilized luminance
// written to the permanent textures. The second half, the wide sparse reconstruction of short
// histories, runs in the blur dispatch (Reblur_Blur.comp): the history must keep the temporally
// accumulated signal only, or the reconstruction's wide footprint would stay in the running mean
// for many frames (contact shadows washed out on still views).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Reblur_HistoryFix.resources.h"
#include "CommonFrame.glsl"
#include "Reblur_Common.glsl"

vec4 LoadAux(ivec2 p)
{
#if REBLUR_OCCLUSION
    return vec4(texelFetch(sampler2D(gIn_Signal, gNearestClamp), p, 0).xyz, 0.0);
#else
    return texelFetch(sampler2D(gIn_Aux, gNearestClamp), p, 0);
#endif
}

vec4 LoadSignal(ivec2 p)
{
    vec4 v = texelFetch(sampler2D(gIn_Signal, gNearestClamp), p, 0);
#if REBLUR_OCCLUSION
    v.xyz = vec3(0.0);
#endif
    return _Reblur_Sanitize(v);
}

void main()
{
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), gResourceSize)) || _Reblur_IsSkyTile(gIn_Tiles, pixel))
        return;
    float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
    if (_NRD_IsSky(viewZ))
        return;

    vec4 center = LoadSignal(pixel);
    vec4 aux = LoadAux(pixel);
    float historyLength = aux.y;
    bool isReference = (gFlags & REBLUR_FLAG_REFERENCE) != 0u;
    ivec2 maxPixel = ivec2(gResourceSize) - 1;

    vec4 result = center;

    // Anti-firefly on what the blur receives.
    if (gFireflyScale > 0.0 && !isReference)
    {
        float m1 = 0.0, m2 = 0.0, n = 0.0;
        for (int j = -1; j <= 1; j++)
        {
            for (int i = -1; i <= 1; i++)
            {
                ivec2 q = clamp(pixel + ivec2(i, j), ivec2(0), maxPixel);
                if ((i == 0 && j == 0) || _NRD_IsSky(texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x))
                    continue;
                float l = _Reblur_Luma(LoadSignal(q));
                m1 += l;
                m2 += l * l;
                n += 1.0;
            }
        }
        if (n > 0.0)
        {
            m1 /= n;
            float sigma = sqrt(max(m2 / n - m1 * m1, 0.0));
            float luma = _Reblur_Luma(result);
            float limit = m1 + gFireflyScale * sigma;
            if (luma > limit)
                result = _Reblur_WithLuma(result, limit);
        }
    }

#if REBLUR_OCCLUSION
    result.xyz = vec3(0.0);
#endif
    imageStore(gOut_History, pixel, _NRD_ClampToHalf(result));
    imageStore(gOut_Fast, pixel, vec4(aux.x, historyLength, 0.0, 0.0));
    imageStore(gOut_Stabilized, pixel, vec4(aux.z));
    // The debt texel as the temporal pass packed it (Reblur_Common.glsl; occlusion: none, its
    // auxiliary values have no room for it).
    imageStore(gOut_Debt, pixel, vec4(aux.w));
}
