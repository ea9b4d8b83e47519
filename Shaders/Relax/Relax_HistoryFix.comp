#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_control_flow_attributes : require

// RELAX history fix and history clamping (document 004, RELAX):
// - histories shorter than gHistoryFixFrameNum frames (not counting what a confidence input took: the
//   length texture's .y) are replaced by a 5x5 sparse average of their
//   neighbours (taps gHistoryFixStride * (1 - length / gHistoryFixFrameNum) / 2 pixels apart, at
//   least 1), weighted by tangent-plane distance, normal (cos^8), roughness (specular) and by
//   1 + the neighbour's history length, so that fresh disocclusions borrow settled neighbours;
// - anti-firefly (optional): the slow history's luminance is clamped to the range of its 3x3
//   neighbours on the same surface (tangent plane within 5% of viewZ, normals within 37 degrees);
// - diffuse mean clamp: the slow history's 3x3 mean is kept near the fast history's (within the fast
//   history's noise), shifted by the excess, which also shortens the history;
// - clamping: the slow history is clamped per channel to mean +- gHistoryClampSigma * sigma of the
//   fast history's 3x3 neighbourhood (specular: sigma from the slow history's spread and the fast
//   history's noise, the box centred on the slow history's own 3x3 mean while it agrees with the fast
//   one's); a slow history beyond gAntilagSigma sigma of the pixel's fast history also
//   loses history length (down to the fast history's), so that it keeps following it.
#include "Bindings.glsl"
#include "Relax_Constants.h"
#include "Relax_HistoryFix.resources.h"
#include "CommonFrame.glsl"
#include "Relax_Common.glsl"
#include "Reprojection.glsl"

// Diffuse: the slow history's 3x3 mean is kept within this many standard deviations of the fast
// history's (Relax_TemporalAccumulation.comp has the same test against the input).
#define RELAX_MEAN_CLAMP_SIGMA 1.0

// Specular: the clamping box's centre follows the fast history's 3x3 mean beyond this many standard
// deviations of its noise.
#define RELAX_SPECULAR_CENTER_SIGMA 2.0

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
    // .x: length and confidence debt; .y: the lighting change record, passed on (Relax_Common.glsl).
    vec2 packedLength = texelFetch(gIn_Length, pixel, 0).xy;
    vec2 lengthDebt = Relax_UnpackLengthAndDebt(packedLength.x);
    float historyLength = lengthDebt.x;
    // The confidence debt (Relax_TemporalAccumulation.comp) counts as history here.
    float debt = lengthDebt.y;
    float fixLength = historyLength + debt;

    if (fixLength < gHistoryFixFrameNum)
    {
        float stride = max(gHistoryFixStride * 0.5 * (1.0 - fixLength / gHistoryFixFrameNum), 1.0);
        vec4 slowSum = vec4(0.0), fastSum = vec4(0.0);
        float m2Sum = 0.0, weightSum = 0.0;
        for (int j = -2; j <= 2; j++)
            for (int i = -2; i <= 2; i++)
            {
                ivec2 q = pixel + ivec2(round(vec2(i, j) * stride));
                RelaxSurface n = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, q);
                if (n.z == 0.0)
                    continue;
                float w = Relax_PlaneWeight(s, n.X, 0.02 * stride);
                float c = max(dot(s.Nw, n.Nw), 0.0);
                c *= c;
                c *= c;
                w *= c * c;
#if RELAX_SPECULAR
                w *= Relax_RoughnessWeight(s.roughness, n.roughness, 0.3);
#endif
                if (w <= 0.0)
                    continue;
                w *= 1.0 + Relax_UnpackLengthAndDebt(texelFetch(gIn_Length, q, 0).x).x;
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
        vec3 mean = vec3(0.0), meanSq = vec3(0.0), meanSlow = vec3(0.0), meanSlowSq = vec3(0.0);
        float variance = 0.0, count = 0.0, lumaMin = NRD_FP16_MAX, lumaMax = 0.0;
        for (int j = -1; j <= 1; j++)
            for (int i = -1; i <= 1; i++)
            {
                ivec2 q = pixel + ivec2(i, j);
                RelaxSurface n = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, q);
                if (n.z == 0.0 || Relax_PlaneWeight(s, n.X, 0.05) <= 0.0 || dot(s.Nw, n.Nw) < 0.8)
                    continue;
                vec4 f = texelFetch(gIn_Fast, q, 0);
                vec3 sl = texelFetch(gIn_Slow, q, 0).rgb;
                float l = _NRD_Luminance(sl);
                mean += f.rgb;
                meanSq += f.rgb * f.rgb;
                meanSlow += sl;
                meanSlowSq += sl * sl;
                variance += max(f.w * f.w - l * l, 0.0);
                count += 1.0;
                if (i != 0 || j != 0)
                {
                    lumaMin = min(lumaMin, l);
                    lumaMax = max(lumaMax, l);
                }
            }
        mean /= count;
        meanSlow /= count;
        variance /= count;
        // Variance of the fast history at one pixel: an exponential average with alpha 1 / (n + 1)
        // holds 1 / (2n + 1) of one sample's (temporal moments, averaged over the neighbourhood).
        float nFast = min(historyLength, gMaxFastAccumulatedFrameNum);
        float fastNoise = variance / (2.0 * nFast + 1.0);
#if RELAX_SPECULAR
        // Specular: the box's half-width comes from the slow history's own spread (its detail) and
        // the fast history's expected noise, not from the fast samples' spread: with a heavy-tailed
        // signal a 3x3 box of fast samples is narrow and low more often than wide and high, and
        // clamping to it darkens the history (static: mean -3.4% of the truth's at 128x128).
        // The spread is at most twice the fast history's, which the temporal accumulation clamped to
        // this frame's input: absurd slow history left by out-of-range input widens its own spread.
        float lMean = _NRD_Luminance(mean) + 1e-6;
        vec3 slowSpread = max(meanSlowSq / count - meanSlow * meanSlow, vec3(0.0));
        vec3 fastSpread = max(meanSq / count - mean * mean, vec3(0.0));
        vec3 sigma = sqrt(min(slowSpread, 4.0 * fastSpread) + fastNoise * (mean / lMean) * (mean / lMean));
#else
        vec3 sigma = sqrt(max(meanSq / count - mean * mean, vec3(0.0)));

        // Diffuse mean clamp: the slow history's 3x3 mean is kept within RELAX_MEAN_CLAMP_SIGMA
        // standard deviations of the fast history's 3x3 mean (plus 2%), shifted by the excess, which
        // keeps the slow history's detail; the excess shortens the history as far as the fast one,
        // so that the detail of the old lighting goes too.
        // Not where a confidence input cut the history to its floor (a debt, and no more than
        // RELAX_DIFFUSE_CONFIDENCE_MIN_HISTORY + 1 frames): the temporal accumulation's mean clamp has
        // already moved both histories to this frame's lighting there, and what is left between their
        // means is noise of the new lighting, whose skewed samples the thresholded shift turns into
        // bias (light_switch 128x128 with confidence: +1.3% of the image mean on the frame the lamp
        // comes back, 0.2% without this shift; Shaders/Confidence/README.md).
        bool isCut = debt > 0.0 && historyLength <= RELAX_DIFFUSE_CONFIDENCE_MIN_HISTORY + 1.0 &&
                     !_NRD_LightingChange_IsMoving(_NRD_LightingChange_UnpackRecord(packedLength.y));
        if (!isCut)
        {
            float lFast = _NRD_Luminance(mean), lSlow = _NRD_Luminance(meanSlow);
            float threshold = RELAX_MEAN_CLAMP_SIGMA * sqrt(fastNoise / count) + 0.01 * max(lFast, lSlow) + 1e-6;
            float d = abs(lFast - lSlow);
            if (d > threshold)
            {
                float shift = 1.0 - threshold / d;
                slow.rgb = max(slow.rgb + (mean - meanSlow) * shift, vec3(0.0));
                historyLength = mix(historyLength, min(historyLength, gMaxFastAccumulatedFrameNum + 1.0), shift);
            }
        }
#endif

        if ((gFlags & RELAX_FLAG_ANTI_FIREFLY) != 0u && count > 1.0)
        {
            float l = _NRD_Luminance(slow.rgb);
            float clamped = clamp(l, lumaMin, lumaMax);
            slow.rgb *= l > 0.0 ? clamped / l : 1.0;
        }

        vec3 center = mean;
#if RELAX_SPECULAR
        // Specular: the box is centred on the slow history's own 3x3 mean while it stays within the
        // noise of the fast history's 3x3 mean (RELAX_SPECULAR_CENTER_SIGMA standard deviations plus
        // 2%), and moved towards the fast mean by the excess: the fast mean of heavy-tailed samples is
        // low more often than high, and a box centred on it darkens converged history.
        {
            float lFast = _NRD_Luminance(mean), lSlow = _NRD_Luminance(meanSlow);
            float threshold = RELAX_SPECULAR_CENTER_SIGMA * sqrt(fastNoise / count) + 0.02 * lFast + 1e-6;
            float d = abs(lFast - lSlow);
            center = meanSlow + (mean - meanSlow) * (d > threshold ? 1.0 - threshold / d : 0.0);
        }
#endif
        vec3 clamped = clamp(slow.rgb, max(center - gHistoryClampSigma * sigma, vec3(0.0)), center + gHistoryClampSigma * sigma);
        float sigmaLuma = _NRD_Luminance(sigma) + 1e-6 + 0.01 * _NRD_Luminance(mean);
        float deviation = abs(_NRD_Luminance(slow.rgb) - _NRD_Luminance(fast.rgb)) / sigmaLuma;
        float antilag = gAntilagSigma > 0.0 ? clamp((deviation - gAntilagSigma) / gAntilagSigma, 0.0, 1.0) : 0.0;
        historyLength = mix(historyLength, min(historyLength, gMaxFastAccumulatedFrameNum + 1.0), antilag);
        slow.rgb = clamped;
    }
    imageStore(gOut_Slow, pixel, _NRD_ClampToHalf(slow));
    imageStore(gOut_Fast, pixel, _NRD_ClampToHalf(fast));
    imageStore(gOut_Length, pixel, vec4(Relax_PackLengthAndDebt(historyLength, debt), packedLength.y, 0.0, 0.0));
}
