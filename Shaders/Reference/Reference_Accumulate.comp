#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Reference_Accumulate.resources.h"
#include "Common.glsl"

void main()
{
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), gSize)))
        return;

    // Non-finite samples contribute zero; huge ones are clamped so the fp32 mean stays finite.
    vec4 value = _NRD_Sanitize(texelFetch(sampler2D(gIn_Radiance, gNearestClamp), pixel, 0), 0.0);
    value = clamp(value, vec4(-1e30), vec4(1e30));

    vec4 history = gWeight >= 1.0 ? vec4(0.0) : _NRD_Sanitize(imageLoad(gHistory, pixel), 0.0);
    vec4 result = mix(history, value, gWeight);

    imageStore(gHistory, pixel, result);
    imageStore(gOut_Radiance, pixel, result);
}
