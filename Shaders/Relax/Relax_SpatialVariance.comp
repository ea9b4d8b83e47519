#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require

// RELAX variance estimation (SVGF section 4.2): the luminance variance of the samples is
// E[l^2] - E[l]^2 from the temporal moments; while the history is shorter than
// gVarianceHistoryThreshold frames both moments are averaged over a 7x7 neighbourhood on the same
// surface (tangent-plane and normal weights) first. The a-trous filter receives the variance of the
// accumulated mean: the sample variance divided by the history length, so that converged history
// is filtered only within its remaining noise.
#include "Bindings.glsl"
#include "Relax_Constants.h"
#include "Relax_SpatialVariance.resources.h"
#include "CommonFrame.glsl"
#include "Relax_Common.glsl"
#include "Reprojection.glsl"

void main()
{
    if (Relax_IsTileSkipped(gIn_Tiles))
        return;
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    RelaxSurface s = Relax_LoadSurface(gIn_NormalRoughness, gIn_ViewZ, pixel);
    if (s.z == 0.0)
        return;
    vec3 radiance = texelFetch(gIn_Slow, pixel, 0).rgb;
    float m2 = texelFetch(gIn_Fast, pixel, 0).w;
    m2 *= m2;
    float m1 = _NRD_Luminance(radiance);
    vec2 packedLength = texelFetch(gIn_Length, pixel, 0).xy;
    float historyLength = max(Relax_UnpackLengthAndDebt(packedLength.x).x, 1.0);
    if (historyLength < gVarianceHistoryThreshold)
    {
        float sum1 = 0.0, sum2 = 0.0, weightSum = 0.0;
        for (int j = -3; j <= 3; j++)
            for (int i = -3; i <= 3; i++)
            {
                ivec2 q = pixel + ivec2(i, j);
                RelaxSurface n = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, q);
                if (n.z == 0.0)
                    continue;
                float w = Relax_PlaneWeight(s, n.X, 0.05) * max(dot(s.Nw, n.Nw), 0.0);
                if (w <= 0.0)
                    continue;
                float f = texelFetch(gIn_Fast, q, 0).w;
                sum1 += w * _NRD_Luminance(texelFetch(gIn_Slow, q, 0).rgb);
                sum2 += w * f * f;
                weightSum += w;
            }
        m1 = sum1 / weightSum;
        m2 = sum2 / weightSum;
    }
    float variance = max(m2 - m1 * m1, 0.0) / historyLength;
    // Where the lighting moves (diffuse change test, Relax_TemporalAccumulation.comp) the history is
    // 2 frames: a quarter of the variance keeps the a-trous filter from blurring away the lines of
    // light that such a history still holds (venetian_blinds; the variance is of the lighting's swing
    // as much as of the noise there).
    if (_NRD_LightingChange_IsMoving(_NRD_LightingChange_UnpackRecord(packedLength.y)))
        variance *= RELAX_MOVING_VARIANCE_SCALE;
    imageStore(gOut_RadianceVariance, pixel, _NRD_ClampToHalf(vec4(radiance, variance)));
}
