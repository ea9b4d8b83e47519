// REBLUR tile classification (document 004: sky tiles are skipped): one 16x16 group per tile, 1 if
// any pixel is to be denoised. Also stores this frame's viewZ (fp16, sky as REBLUR_NO_VIEWZ) for
// the next frame's disocclusion tests.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Reblur_ClassifyTiles.resources.h"
#include "CommonFrame.glsl"
#include "Reblur_Common.glsl"

shared uint s_HasSurface;

void main()
{
    if (gl_LocalInvocationIndex == 0u)
        s_HasSurface = 0u;
    barrier();
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool isInside = all(lessThan(uvec2(pixel), gResourceSize));
    if (isInside)
    {
        float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
        bool isSky = _NRD_IsSky(viewZ);
        // Beyond fp16 range the stored depth would not compare: such pixels lose their history.
        imageStore(gOut_ViewZ, pixel, vec4(isSky || viewZ > NRD_FP16_MAX ? REBLUR_NO_VIEWZ : viewZ));
        if (!isSky)
            atomicOr(s_HasSurface, 1u);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u)
        imageStore(gOut_Tiles, ivec2(gl_WorkGroupID.xy), vec4(float(s_HasSurface)));
}
