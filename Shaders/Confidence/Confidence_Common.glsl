// CONFIDENCE: helpers shared by the passes (document 003, "Converting the Gradients into Confidence").
#ifndef CONFIDENCE_COMMON_GLSL
#define CONFIDENCE_COMMON_GLSL

// Confidence at or above this is output as 1 (NRDSettings.h, ConfidenceSettings).
#define CONFIDENCE_SNAP_TO_ONE 0.99

// ConfidenceSettings::localGradientRadius at most (NRDSettings.h, CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS).
#define CONFIDENCE_MAX_LOCAL_RADIUS 8

// A gradient texel as the passes use it: non-finite and negative values count as 0 (no gradient),
// huge ones are clamped so that sums of 9 weighted taps stay finite in fp16 storage.
vec4 _Confidence_LoadGradient(texture2D t, ivec2 texel)
{
    vec4 g = _NRD_Sanitize(texelFetch(sampler2D(t, gNearestClamp), texel, 0), 0.0);
    return clamp(g, vec4(0.0), vec4(NRD_FP16_MAX));
}

// The pixel whose G-buffer stands for a stratum in the edge-stopping weights: its centre, clamped
// to the image (strata at the right / bottom edge may be cut).
ivec2 _Confidence_StratumPixel(ivec2 texel, uvec2 size)
{
    return min(texel * 3 + 1, ivec2(size) - 1);
}

// Filtered difference and luminance -> confidence in [0, 1] (NRDSettings.h, ConfidenceSettings).
// A zero difference gives exactly 1, so a still scene keeps every history.
float _Confidence_FromGradient(float difference, float luminance, float threshold, float sensitivity)
{
    float g = difference / max(luminance, 1e-6);
    return clamp(1.0 - max(g - threshold, 0.0) * sensitivity, 0.0, 1.0);
}

#endif
