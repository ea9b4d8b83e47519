// CONFIDENCE a-trous pass (document 003: "a 4-pass A-trous filter with a 3x3 kernel ... luminance
// differences and absolute values are filtered independently"). Kernel (1/4, 1/2, 1/4) in each
// direction at step gStep; taps outside the gradient image are skipped and the weights
// renormalized. Strata without a gradient hold zeros in both channels, so they lower the filtered
// difference and luminance alike and leave their ratio alone. The edge-stopping weights (viewZ
// within gDepthThreshold of the centre's, normals by max(n . n', 0)^gNormalPower) keep a lighting
// change on one surface from invalidating the history of another one in front of it.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Confidence_Filter.resources.h"
#include "CommonFrame.glsl"
#include "Confidence_Common.glsl"

void main()
{
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(texel), gGradientSize)))
        return;

    ivec2 centerPixel = _Confidence_StratumPixel(texel, gResourceSize);
    float centerZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), centerPixel, 0).x;
    bool centerSky = _NRD_IsSky(centerZ);
    vec3 centerN = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), centerPixel, 0)).xyz;

    const float kernel[3] = float[3](0.25, 0.5, 0.25);
    vec4 sum = vec4(0.0);
    float weightSum = 0.0;
    for (int j = -1; j <= 1; j++)
    {
        for (int i = -1; i <= 1; i++)
        {
            ivec2 q = texel + ivec2(i, j) * gStep;
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(gGradientSize))))
                continue;
            float w = kernel[i + 1] * kernel[j + 1];
            if ((i != 0 || j != 0) && !centerSky)
            {
                ivec2 p = _Confidence_StratumPixel(q, gResourceSize);
                float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), p, 0).x;
                // A sky tap next to a surface may still hold a gradient (a stratum is 3x3 pixels):
                // it is kept without edge stopping.
                if (!_NRD_IsSky(z))
                {
                    if (gDepthThreshold > 0.0)
                        w *= abs(z - centerZ) < gDepthThreshold * abs(centerZ) ? 1.0 : 0.0;
                    if (gNormalPower > 0.0)
                    {
                        vec3 n = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), p, 0)).xyz;
                        w *= pow(clamp(dot(n, centerN), 0.0, 1.0), gNormalPower);
                    }
                }
            }
            sum += w * _Confidence_LoadGradient(gIn_Gradients, q);
            weightSum += w;
        }
    }
    // The centre tap always counts (weight 1/4), so weightSum > 0.
    imageStore(gOut_Gradients, texel, _NRD_ClampToHalf(sum / weightSum));
}
