// REBLUR temporal stabilization (document 004, REBLUR: "temporal stabilization"): the luminance of
// the post-blurred signal is blended with its stabilized history (reprojected by the temporal
// accumulation along the same motion), which is first clamped to mean +- sigma of the 5x5
// neighbourhood on the same surface; the blend shortens where the clamp moved the history
// (luminance anti-lag) and where the hit distance changed. Writes the output (radiance rescaled to
// the stabilized luminance, hit distance of the post-blur) and the stabilized luminance.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Reblur_TemporalStabilization.resources.h"
#include "CommonFrame.glsl"
#include "Reblur_Common.glsl"

vec4 LoadSignal(ivec2 p)
{
    vec4 v = texelFetch(sampler2D(gIn_History, gNearestClamp), p, 0);
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
    float luma = _Reblur_Luma(center);
    float historyLength = clamp(_NRD_Sanitize(texelFetch(sampler2D(gIn_Fast, gNearestClamp), pixel, 0).y, 0.0), 0.0,
                                NRD_HISTORY_LENGTH_MAX);
    float stabilized = max(_NRD_Sanitize(imageLoad(gInOut_Stabilized, pixel).x, 0.0), 0.0);
    bool isReference = (gFlags & REBLUR_FLAG_REFERENCE) != 0u;

    float result = luma;
    if (gStabilizationFrameNum > 0.0 && historyLength > 1.0 && !isReference)
    {
        ReblurSurface s = _Reblur_Surface(gIn_NormalRoughness, pixel, viewZ);
        ivec2 maxPixel = ivec2(gResourceSize) - 1;
        float m1 = 0.0, m2 = 0.0, weightSum = 0.0;
        for (int j = -2; j <= 2; j++)
        {
            for (int i = -2; i <= 2; i++)
            {
                ivec2 q = clamp(pixel + ivec2(i, j), ivec2(0), maxPixel);
                float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
                if (_NRD_IsSky(z))
                    continue;
                vec3 Xs = _NRD_ViewPosition(_NRD_PixelUv(q), z);
                float w = clamp(1.0 - abs(dot(s.Nv, Xs - s.Xv)) / (gPlaneDistanceSensitivity * viewZ), 0.0, 1.0);
                float l = _Reblur_Luma(LoadSignal(q));
                m1 += l * w;
                m2 += l * l * w;
                weightSum += w;
            }
        }
        m1 /= weightSum; // >= 1: the centre has weight 1.
        m2 /= weightSum;
        float sigma = sqrt(max(m2 - m1 * m1, 0.0));
        // The box always holds the current value: mean +- sigma alone excludes the centre at local
        // extrema of a smooth image (a contact shadow's floor, a highlight's peak), and clamping
        // towards the mean there would blur them.
        float clamped = clamp(stabilized, min(m1 - sigma, luma), max(m1 + sigma, luma));
        // Anti-lag: a history the clamp had to move is out of date.
        float moved = abs(clamped - stabilized) / (sigma + 0.02 * m1 + 1e-6);
        // The stabilized history reaches back at most a quarter of the accumulated frames: older
        // outputs were blurred with a wider radius (it falls as 1 / (1 + length)) and would keep
        // their blur in the stabilized luminance.
        float n = min(gStabilizationFrameNum, (historyLength - 1.0) * 0.25) / (1.0 + moved);
        // Camera motion: the stabilized history is resampled every frame, and each resampling
        // blurs it a little more; it reaches back fewer frames the faster the view moves (the
        // camera's part of the motion, from the matrices).
        vec3 X = (gViewToWorld * vec4(s.Xv, 1.0)).xyz;
        vec4 clipPrev = gWorldToClipPrev * vec4(X, 1.0);
        if (clipPrev.w > NRD_EPS)
        {
            vec2 uvPrev = (clipPrev.xy / clipPrev.w) * 0.5 + 0.5;
            float motionPixels = length((uvPrev - _NRD_PixelUv(pixel)) * vec2(gResourceSize));
            n /= 1.0 + REBLUR_STABILIZATION_MOTION_SCALE * motionPixels;
#if !REBLUR_SPECULAR
            if (historyLength < REBLUR_STABILIZATION_MIN_MOVING_HISTORY && motionPixels > REBLUR_PIXEL_ANTILAG_MOTION)
                n = 0.0;
#endif
        }
        result = mix(luma, clamped, n / (n + 1.0));
    }
    imageStore(gInOut_Stabilized, pixel, vec4(result));
    vec4 output_ = _Reblur_WithLuma(center, result);
#if REBLUR_OCCLUSION
    output_ = vec4(output_.w);
#endif
    imageStore(gOut_Signal, pixel, output_);
}
