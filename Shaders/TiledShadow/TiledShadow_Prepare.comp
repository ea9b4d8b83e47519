#version 450
#extension GL_GOOGLE_include_directive : require

// TILED_SHADOW prepare (document 000, "Denoiser shadows prepare"): one invocation builds one tile's
// 32-bit mask from its 8x4 visibility samples. No subgroup operation, so any subgroup size works;
// an application whose ray pass writes IN_SHADOW_BITMASK directly skips this pass. Sky pixels are
// lit whatever their input holds (nothing is traced there): the classification's neighbourhood
// counts their bits.

#include "Bindings.glsl"
#include "TiledShadow_Prepare.resources.h"
#include "CommonFrame.glsl"
#include "TiledShadow_Common.glsl"

void main()
{
    uvec2 tile = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(tile, _TS_TileCount(gResourceSize))))
        return;

    ivec2 origin = ivec2(tile * uvec2(TS_TILE_W, TS_TILE_H));
    uint mask = 0u;
    for (int y = 0; y < TS_TILE_H; y++)
    {
        for (int x = 0; x < TS_TILE_W; x++)
        {
            ivec2 pixel = origin + ivec2(x, y);
            // Pixels outside the image count as lit (the classification ignores them anyway).
            bool isLit = true;
            if (all(lessThan(uvec2(pixel), gResourceSize)))
            {
                isLit = !(texelFetch(sampler2D(gIn_Visibility, gNearestClamp), pixel, 0).x < 0.5); // NaN: lit.
                // Only a shadowed sample needs its depth (most are lit: half the bandwidth).
                isLit = isLit || _NRD_IsSky(texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x);
            }
            mask |= isLit ? (1u << uint(x + TS_TILE_W * y)) : 0u;
        }
    }
    imageStore(gOut_Mask, ivec2(tile), uvec4(mask, 0u, 0u, 0u));
}
