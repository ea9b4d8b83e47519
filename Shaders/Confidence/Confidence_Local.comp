// CONFIDENCE local limit (not in document 003; Shaders/Confidence/README.md, "The local limit"):
// the mean of the unfiltered gradients over the (2 r + 1) x (2 r + 1) strata around each stratum
// (texels outside the image repeat the edge's), differences and luminances separately. The
// temporal pass interpolates it bilinearly as the filtered gradients and takes, per signal, the
// smaller of the two normalized gradients.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Confidence_Local.resources.h"
#include "CommonFrame.glsl"
#include "Confidence_Common.glsl"

void main()
{
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(texel), gGradientSize)))
        return;
    ivec2 maxTexel = ivec2(gGradientSize) - 1;
    vec4 sum = vec4(0.0);
    for (int j = -gRadius; j <= gRadius; j++)
        for (int i = -gRadius; i <= gRadius; i++)
            sum += _Confidence_LoadGradient(gIn_Gradients, clamp(texel + ivec2(i, j), ivec2(0), maxTexel));
    // The mean, not the sum: fp16 storage (values up to NRD_FP16_MAX each).
    float n = float(2 * gRadius + 1);
    imageStore(gOut_Local, texel, _NRD_ClampToHalf(sum / (n * n)));
}
