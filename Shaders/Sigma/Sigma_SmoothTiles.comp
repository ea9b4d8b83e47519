// SIGMA tile smoothing (document 004, SIGMA): one thread per 16x16 tile. A tile is denoised if a
// mixed tile lies within reach of its kernels (the map dilated by the kernel radius, 2 tiles at
// most), copied if only uniform tiles are in reach, and skipped if it holds only sky. The result
// is read once per workgroup by the filtering passes, so their copy and sky paths need no
// shared memory or barrier.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Sigma_SmoothTiles.resources.h"
#include "CommonFrame.glsl"
#include "Sigma_Common.glsl"

void main()
{
    ivec2 self = ivec2(gl_GlobalInvocationID.xy);
    ivec2 tilesNum = ivec2((gResourceSize + uvec2(SIGMA_TILE_SIZE - 1)) / uvec2(SIGMA_TILE_SIZE));
    if (any(greaterThanEqual(self, tilesNum)))
        return;

    vec2 selfTile = texelFetch(sampler2D(gIn_Tiles, gNearestClamp), self, 0).xy;
    float selfReach = _NRD_Sanitize(selfTile.y, SIGMA_MAX_PIXEL_RADIUS);
    bool isDenoised = false;
    for (int j = -2; j <= 2; j++)
    {
        for (int i = -2; i <= 2; i++)
        {
            ivec2 other = self + ivec2(i, j);
            if (any(lessThan(other, ivec2(0))) || any(greaterThanEqual(other, tilesNum)))
                continue;
            vec2 otherTile = texelFetch(sampler2D(gIn_Tiles, gNearestClamp), other, 0).xy;
            int distance = max(abs(i), abs(j));
            // Pixels between the two tiles, and how far kernels of either tile can read.
            float gap = float((distance - 1) * SIGMA_TILE_SIZE + 1);
            float reach = max(selfReach, _NRD_Sanitize(otherTile.y, SIGMA_MAX_PIXEL_RADIUS)) + SIGMA_TILE_REACH_MARGIN;
            isDenoised = isDenoised || (otherTile.x == SIGMA_TILE_MIXED && (distance <= 1 || reach >= gap));
        }
    }
    uint mode = selfTile.x == SIGMA_TILE_SKY ? SIGMA_MODE_SKY : (isDenoised ? SIGMA_MODE_DENOISE : SIGMA_MODE_COPY);
    imageStore(gOut_TileModes, self, vec4(_Sigma_EncodeTileMode(mode)));
}
