#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require

// RELAX tile classification: one group per 8x8 tile; a tile whose pixels are all sky (or outside the
// image) is marked 0 and every later pass returns at once for it (its group matches the tile).
#include "Bindings.glsl"
#include "Relax_Constants.h"
#include "Relax_ClassifyTiles.resources.h"
#include "CommonFrame.glsl"

shared uint sAny;

void main()
{
    if (gl_LocalInvocationIndex == 0)
        sAny = 0u;
    barrier();
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (all(lessThan(pixel, ivec2(gResourceSize))) && !_NRD_IsSky(texelFetch(gIn_ViewZ, pixel, 0).x))
        atomicOr(sAny, 1u);
    barrier();
    if (gl_LocalInvocationIndex == 0)
        imageStore(gOut_Tiles, ivec2(gl_WorkGroupID.xy), vec4(float(sAny)));
}
