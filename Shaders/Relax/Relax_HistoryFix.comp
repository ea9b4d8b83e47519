#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_control_flow_attributes : require

// RELAX history fix and history clamping (document 004, RELAX):
// - histories shorter than gHistoryFixFrameNum frames are replaced by a 5x5 sparse average of their
//   neighbours (taps gHistoryFixStride * (1 - length / gHistoryFixFrameNum) / 2 pixels apart, at
//   least 1), weighted by tangent-plane distance, normal (cos^8), roughness (specular) and by
//   1 + the neighbour's history length, so that fresh disocclusions borrow settled neighbours;
// - anti-firefly (optional): the slow history's luminance is clamped to the range of its 3x3
//   neighbours on the same surface (tangent plane within 5% of viewZ, normals within 37 degrees);
// - clamping: the slow history is clamped per channel to mean +- gHistoryClampSigma * sigma of the
//   fast history's 3x3 neighbourhood; a slow history beyond gAntilagSigma sigma of the pixel's fast
//   history also loses history length (down to the fast history's), so that it keeps following it.
#include "Bindings.glsl"
#include "Relax_Constants.h"
#include "Relax_HistoryFix.resources.h"
#include "CommonFrame.glsl"
#include "Relax_Common.glsl"
#include "Reprojection.glsl"

void main()
{
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if ((gFlags & RELAX_FLAG_WRITE_VIEWZ) != 0u && Relax_IsInImage(pixel))
    {
        float z = texelFetch(gIn_ViewZ, pixel, 0).x;
        imageStore(gOut_ViewZ, pixel, vec4(_NRD_IsSky(z) || z > NRD_FP16_MAX ? 0.0 : z));
    }
    if (Relax_IsTileSkipped(gIn_Tiles))
        return;
    RelaxSurface s = Relax_LoadSurface(gIn_NormalRoughness, gIn_ViewZ, pixel);
    if (s.z == 0.0)
        return;

    vec4 slow = texelFetch(gIn_Slow, pixel, 0);
    vec4 fast = texelFetch(gIn_Fast, pixel, 0);
    float historyLength = _NRD_UnpackHistoryLength(texelFetch(gIn_Length, pixel, 0).x);

    if (historyLength < gHistoryFixFrameNum)
    {
        float stride = max(gHistoryFixStride * 0.5 * (1.0 - historyLength / gHistoryFixFrameNum), 1.0);
        vec4 slowSum = vec4(0.0), fastSum = vec4(0.0);
        float m2Sum = 0.0, weightSum = 0.0;
        for (int j = -2; j <= 2; j++)
            for (int i = -2; i <= 2; i++)
            {
                ivec2 q = pixel + ivec2(round(vec2(i, j) * stride));
                RelaxSurface n = Relax_LoadSurface(gIn_NormalRoughness, gIn_ViewZ, q);
                if (n.z == 0.0)
                    continue;
                float w = Relax_PlaneWeight(s, n.X, 0.02 * stride);
                float c = max(dot(s.N, n.N), 0.0);
                c *= c;
                c *= c;
                w *= c * c;
#if RELAX_SPECULAR
                w *= Relax_RoughnessWeight(s.roughness, n.roughness, 0.3);
#endif
                if (w <= 0.0)
                    continue;
                w *= 1.0 + _NRD_UnpackHistoryLength(texelFetch(gIn_Length, q, 0).x);
                vec4 f = texelFetch(gIn_Fast, q, 0);
                slowSum += w * texelFetch(gIn_Slow, q, 0);
                fastSum += w * f;
                m2Sum += w * f.w * f.w;
                weightSum += w;
            }
        if (weightSum > 0.0)
        {
            slow = slowSum / weightSum;
            fast = vec4(fastSum.rgb / weightSum, sqrt(m2Sum / weightSum));
        }
    }
    else
    {
        // Neighbourhoods of the slow (anti-firefly) and fast (clamping) histories on this surface.
        vec3 mean = vec3(0.0), meanSq = vec3(0.0);
        float count = 0.0, lumaMin = NRD_FP16_MAX, lumaMax = 0.0;
        for (int j = -1; j <= 1; j++)
            for (int i = -1; i <= 1; i++)
            {
                ivec2 q = pixel + ivec2(i, j);
                RelaxSurface n = Relax_LoadSurface(gIn_NormalRoughness, gIn_ViewZ, q);
                if (n.z == 0.0 || Relax_PlaneWeight(s, n.X, 0.05) <= 0.0 || dot(s.N, n.N) < 0.8)
                    continue;
                vec3 f = texelFetch(gIn_Fast, q, 0).rgb;
                mean += f;
                meanSq += f * f;
                count += 1.0;
                if (i != 0 || j != 0)
                {
                    float l = _NRD_Luminance(texelFetch(gIn_Slow, q, 0).rgb);
                    lumaMin = min(lumaMin, l);
                    lumaMax = max(lumaMax, l);
                }
            }
        mean /= count;
        vec3 sigma = sqrt(max(meanSq / count - mean * mean, vec3(0.0)));

        if ((gFlags & RELAX_FLAG_ANTI_FIREFLY) != 0u && count > 1.0)
        {
            float l = _NRD_Luminance(slow.rgb);
            float clamped = clamp(l, lumaMin, lumaMax);
            slow.rgb *= l > 0.0 ? clamped / l : 1.0;
        }

        vec3 clamped = clamp(slow.rgb, mean - gHistoryClampSigma * sigma, mean + gHistoryClampSigma * sigma);
        float sigmaLuma = _NRD_Luminance(sigma) + 1e-6 + 0.01 * _NRD_Luminance(mean);
        float deviation = abs(_NRD_Luminance(slow.rgb) - _NRD_Luminance(fast.rgb)) / sigmaLuma;
        float antilag = gAntilagSigma > 0.0 ? clamp((deviation - gAntilagSigma) / gAntilagSigma, 0.0, 1.0) : 0.0;
        historyLength = mix(historyLength, min(historyLength, gMaxFastAccumulatedFrameNum + 1.0), antilag);
        slow.rgb = clamped;
    }
    imageStore(gOut_Slow, pixel, _NRD_ClampToHalf(slow));
    imageStore(gOut_Fast, pixel, _NRD_ClampToHalf(fast));
    imageStore(gOut_Length, pixel, vec4(_NRD_PackHistoryLength(historyLength)));
}
