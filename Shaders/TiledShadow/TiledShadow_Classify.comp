#version 450
#extension GL_GOOGLE_include_directive : require

// TILED_SHADOW tile classification (document 000, "Denoiser shadows tile classification"):
//   1. local neighbourhood encoding: Gaussian-weighted mean of the 1-spp bits over a 17x17 window,
//      separable and computed from the bitmasks (popcounts of row windows), pixels outside the
//      image excluded; the samples are 0 or 1, so the variance is mean * (1 - mean);
//   2. disocclusion: the expected previous viewZ from the clip -> previous clip matrix, compared
//      with the stored one under a tolerance that grows at grazing angles;
//   3. reprojection: temporal moments, variance boost on short history, history clamped to the
//      neighbourhood, blend toward the current sample by history length.
// Tiles whose 3x5-tile neighbourhood is uniformly lit or shadowed skip 2 and 3 (and the filter).
// Group: 16x16 pixels = 2x4 tiles; shared memory only, so any subgroup size works.

#include "Bindings.glsl"
#include "TiledShadow_Classify.resources.h"
#include "CommonFrame.glsl"
#include "TiledShadow_Common.glsl"

#define GROUP_SIZE 16
#define GROUP_TILES_X 2 // GROUP_SIZE / TS_TILE_W
#define GROUP_TILES_Y 4 // GROUP_SIZE / TS_TILE_H
#define RADIUS_MAX 8
// Tiles around the group that its pixels' neighbourhoods reach: 1 left and right, 2 up and down.
#define HALO_TILES_X 1
#define HALO_TILES_Y 2
#define REGION_TILES_X (GROUP_TILES_X + 2 * HALO_TILES_X)
#define REGION_TILES_Y (GROUP_TILES_Y + 2 * HALO_TILES_Y)
// Rows of horizontal sums: the group's rows plus RADIUS_MAX above and below.
#define SUM_ROWS (GROUP_SIZE + 2 * RADIUS_MAX)
#ifndef TS_HISTORY_REJECTION
#define TS_HISTORY_REJECTION 2.0
#endif

shared uint sMask[REGION_TILES_Y][REGION_TILES_X];
shared float sRowSum[SUM_ROWS][GROUP_SIZE];
shared uint sTileClass[GROUP_TILES_X * GROUP_TILES_Y];
shared uint sTileHasSurface[GROUP_TILES_X * GROUP_TILES_Y];

float MomentWeight(int i)
{
    vec4 w = i < 4 ? gMomentWeights0 : (i < 8 ? gMomentWeights1 : gMomentWeights2);
    return w[i & 3];
}

float MomentStep(int i)
{
    vec4 w = i < 4 ? gMomentSteps0 : (i < 8 ? gMomentSteps1 : gMomentSteps2);
    return w[i & 3];
}

// Bits of the 8 pixels of tile column 'tileX' in image row 'y' that lie inside the image.
uint RowValidBits(int tileX, int y)
{
    if (y < 0 || y >= int(gResourceSize.y) || tileX < 0)
        return 0u;
    int n = clamp(int(gResourceSize.x) - tileX * TS_TILE_W, 0, TS_TILE_W);
    return (1u << uint(n)) - 1u;
}

uint TileValidBits(ivec2 tile)
{
    uint bits = 0u;
    for (int y = 0; y < TS_TILE_H; y++)
        bits |= RowValidBits(tile.x, tile.y * TS_TILE_H + y) << uint(TS_TILE_W * y);
    return bits;
}

uint RowByte(uint mask, int row) { return (mask >> uint(TS_TILE_W * row)) & 0xFFu; }

// Sum over i in [-8, 8] of w(|i|) * bit(center + i) for the 17 bits of 'window' (center at bit 8):
// nested windows of half-width k weighted by w(k) - w(k + 1), one popcount each.
float WeightedRowSum(uint window)
{
    float sum = 0.0;
    for (int k = 0; k <= RADIUS_MAX; k++)
    {
        uint nested = ((2u << uint(2 * k)) - 1u) << uint(RADIUS_MAX - k);
        sum += MomentStep(k) * float(bitCount(window & nested));
    }
    return sum;
}

// 17 bits around column 'x' (center at bit 8) of image row 'y', from region tile row 'regionY';
// 'valid' receives which of them lie inside the image.
uint RowWindow(int regionY, int rowInTile, int localX, int tileX, int y, out uint valid)
{
    int regionX = localX / TS_TILE_W + HALO_TILES_X;
    uint window = RowByte(sMask[regionY][regionX - 1], rowInTile) | (RowByte(sMask[regionY][regionX], rowInTile) << 8) |
                  (RowByte(sMask[regionY][regionX + 1], rowInTile) << 16);
    valid = RowValidBits(tileX - 1, y) | (RowValidBits(tileX, y) << 8) | (RowValidBits(tileX + 1, y) << 16);
    uint shift = uint(localX % TS_TILE_W);
    valid >>= shift;
    return (window >> shift) & valid;
}

void main()
{
    uint threadIndex = gl_LocalInvocationIndex;
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    ivec2 groupOrigin = ivec2(gl_WorkGroupID.xy) * GROUP_SIZE;
    ivec2 groupTile = ivec2(gl_WorkGroupID.xy) * ivec2(GROUP_TILES_X, GROUP_TILES_Y);
    ivec2 tileCount = ivec2(_TS_TileCount(gResourceSize));
    ivec2 pixel = groupOrigin + local;
    bool isInside = all(lessThan(pixel, ivec2(gResourceSize)));

    // Masks of the group's tiles and their neighbours; tiles outside the image read as 0 (their
    // bits are never valid).
    if (threadIndex < REGION_TILES_X * REGION_TILES_Y)
    {
        ivec2 region = ivec2(threadIndex % REGION_TILES_X, threadIndex / REGION_TILES_X);
        ivec2 tile = groupTile + region - ivec2(HALO_TILES_X, HALO_TILES_Y);
        uint mask = 0u;
        if (all(greaterThanEqual(tile, ivec2(0))) && all(lessThan(tile, tileCount)))
            mask = texelFetch(usampler2D(gIn_Mask, gNearestClamp), tile, 0).x;
        sMask[region.y][region.x] = mask;
    }
    if (threadIndex < GROUP_TILES_X * GROUP_TILES_Y)
        sTileHasSurface[threadIndex] = 0u;

    float viewZ = isInside ? texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x : 0.0;
    bool isSky = !isInside || _NRD_IsSky(viewZ);
    uint localTile = uint(local.y / TS_TILE_H) * GROUP_TILES_X + uint(local.x / TS_TILE_W);
    barrier();

    if (!isSky)
        atomicOr(sTileHasSurface[localTile], 1u);

    // Tile classes: uniform when every in-image bit of the 3x5 tiles around the tile is equal.
    if (threadIndex < GROUP_TILES_X * GROUP_TILES_Y)
    {
        ivec2 t = ivec2(threadIndex % GROUP_TILES_X, threadIndex / GROUP_TILES_X);
        bool anyLit = false, anyShadowed = false;
        for (int dy = -HALO_TILES_Y; dy <= HALO_TILES_Y; dy++)
        {
            for (int dx = -HALO_TILES_X; dx <= HALO_TILES_X; dx++)
            {
                uint valid = TileValidBits(groupTile + t + ivec2(dx, dy));
                uint bits = sMask[t.y + dy + HALO_TILES_Y][t.x + dx + HALO_TILES_X] & valid;
                anyLit = anyLit || bits != 0u;
                anyShadowed = anyShadowed || bits != valid;
            }
        }
        uint tileClass = TS_TILE_FILTERED;
        if ((gFlags & TS_FLAG_TILE_SKIPPING) != 0u && !(anyLit && anyShadowed))
            tileClass = anyLit ? TS_TILE_LIT : TS_TILE_SHADOWED;
        sTileClass[threadIndex] = tileClass;
    }
    barrier();

    // Final classes (all-sky tiles are known now) and whether this group needs the moments.
    bool needsMoments = gDebugView == TS_DEBUG_LOCAL_MEAN;
    uint tileClass = TS_TILE_FILTERED;
    for (uint i = 0u; i < GROUP_TILES_X * GROUP_TILES_Y; i++)
    {
        uint c = sTileClass[i];
        if (c == TS_TILE_FILTERED && sTileHasSurface[i] == 0u)
            c = TS_TILE_SKY;
        needsMoments = needsMoments || c == TS_TILE_FILTERED;
        if (i == localTile)
            tileClass = c;
    }

    // Tile classes and counters (TILED_SHADOW_COUNTERS_* in NRDSettings.h).
    if (threadIndex < GROUP_TILES_X * GROUP_TILES_Y)
    {
        ivec2 tile = groupTile + ivec2(threadIndex % GROUP_TILES_X, threadIndex / GROUP_TILES_X);
        uint c = sTileClass[threadIndex];
        if (c == TS_TILE_FILTERED && sTileHasSurface[threadIndex] == 0u)
            c = TS_TILE_SKY;
        if (all(lessThan(tile, tileCount)))
        {
            imageStore(gOut_TileClass, tile, uvec4(c, 0u, 0u, 0u));
            uint slot = gCounterSlot * 4u;
            if (c == TS_TILE_LIT || c == TS_TILE_SHADOWED)
                atomicAdd(gCounters[slot + 0u], 1u);
            else if (c == TS_TILE_SKY)
                atomicAdd(gCounters[slot + 1u], 1u);
        }
    }
    if (threadIndex == 0u && gl_WorkGroupID.x == 0u && gl_WorkGroupID.y == 0u)
    {
        uint slot = gCounterSlot * 4u, other = (1u - gCounterSlot) * 4u;
        gCounters[slot + 2u] = uint(tileCount.x * tileCount.y);
        gCounters[slot + 3u] = gMethodFrame;
        for (uint i = 0u; i < 4u; i++)
            gCounters[other + i] = 0u;
    }

    // 1. Local neighbourhood: horizontal sums of the rows the group's columns need, then a
    // vertical sum per pixel.
    float localMean = 0.0;
    if (needsMoments)
    {
        for (uint entry = threadIndex; entry < SUM_ROWS * GROUP_SIZE; entry += GROUP_SIZE * GROUP_SIZE)
        {
            int row = int(entry) / GROUP_SIZE, localX = int(entry) % GROUP_SIZE;
            int y = groupOrigin.y - RADIUS_MAX + row;
            uint valid;
            uint window = RowWindow(row / TS_TILE_H, row % TS_TILE_H, localX, groupTile.x + localX / TS_TILE_W, y, valid);
            sRowSum[row][localX] = WeightedRowSum(window);
        }
        barrier();

        // Weight of the in-image pixels: the same column weight for every in-image row.
        uint columnValid;
        int ownRow = local.y + RADIUS_MAX;
        RowWindow(ownRow / TS_TILE_H, ownRow % TS_TILE_H, local.x, groupTile.x + local.x / TS_TILE_W, pixel.y, columnValid);
        float columnWeight = WeightedRowSum(columnValid);
        float sum = 0.0, rowWeight = 0.0;
        for (int i = -RADIUS_MAX; i <= RADIUS_MAX; i++)
        {
            float w = MomentWeight(abs(i));
            int y = pixel.y + i;
            sum += w * sRowSum[ownRow + i][local.x];
            rowWeight += (y >= 0 && y < int(gResourceSize.y)) ? w : 0.0;
        }
        float weight = columnWeight * rowWeight;
        localMean = weight > 0.0 ? sum / weight : 0.0;
    }

    if (!isInside)
        return;

    ivec2 tile = pixel / ivec2(TS_TILE_W, TS_TILE_H);
    uint mask = sMask[tile.y - groupTile.y + HALO_TILES_Y][tile.x - groupTile.x + HALO_TILES_X];
    float sample0 = ((mask >> uint((pixel.x % TS_TILE_W) + TS_TILE_W * (pixel.y % TS_TILE_H))) & 1u) != 0u ? 1.0 : 0.0;

    // Written for skipped tiles and sky: the uniform value with a full history, so that a tile
    // turning non-uniform starts from a stable, clamped history.
    float result = tileClass == TS_TILE_LIT ? 1.0 : 0.0;
    float variance = 0.0;
    float temporalMean = result;
    float samples = tileClass == TS_TILE_SKY || isSky ? 0.0 : gMaxHistoryFrameNum;

    if (tileClass == TS_TILE_FILTERED && !isSky)
    {
        vec2 uv = _NRD_PixelUv(pixel);
        vec3 N = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_Normal, gNearestClamp), pixel, 0)).xyz;
        vec3 mv = _NRD_Sanitize(texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz, 0.0);
        vec3 Xv = _NRD_ViewPosition(uv, viewZ);

        // 2. Disocclusion. Previous clip position of the surface point: the camera motion through
        // the reprojection matrix, plus the object's own motion (world-space vectors), or the uv
        // motion of 2D vectors (their depth change is unknown: the camera-only depth is expected).
        vec4 clipPrev = gClipToClipPrev * (gViewToClip * vec4(Xv, 1.0));
        if (gMotionVectorScale.w != 0.0)
            clipPrev += gWorldToClipPrev * vec4(mv * gMotionVectorScale.xyz, 0.0);
        vec2 uvPrev = clipPrev.w > NRD_EPS ? (clipPrev.xy / clipPrev.w) * 0.5 + 0.5 : vec2(-1.0);
        if (gMotionVectorScale.w == 0.0 && (gMotionVectorScale.x != 0.0 || gMotionVectorScale.y != 0.0))
            uvPrev = uv + mv.xy * gMotionVectorScale.xy;
        float viewZPrevExpected = clipPrev.w;

        // The depth tolerance grows where the view grazes the surface (large depth changes per pixel).
        vec3 V = -normalize(mat3(gViewToWorld) * Xv);
        float grazing = pow(clamp(1.0 - dot(V, N), 0.0, 1.0), 8.0);
        float tolerance = mix(gDisocclusionThreshold, gDisocclusionThresholdGrazing, grazing) * viewZPrevExpected;

        // Bilinear footprint, taps behind a depth discontinuity dropped.
        vec3 history = vec3(0.0);
        float footprint = 0.0;
        if ((gFlags & TS_FLAG_HISTORY_VALID) != 0u && viewZPrevExpected > NRD_EPS)
        {
            vec2 position = uvPrev * vec2(gResourceSize) - 0.5;
            ivec2 origin = ivec2(floor(position));
            vec2 f = position - vec2(origin);
            for (int i = 0; i < 4; i++)
            {
                ivec2 p = origin + ivec2(i & 1, i >> 1);
                if (any(greaterThanEqual(uvec2(p), gResourceSize)))
                    continue;
                uvec2 state = texelFetch(usampler2D(gPrev_State, gNearestClamp), p, 0).xy;
                float viewZPrev = uintBitsToFloat(state.x);
                if (_NRD_IsSky(viewZPrev) || abs(viewZPrev - viewZPrevExpected) >= tolerance)
                    continue;
                float w = ((i & 1) != 0 ? f.x : 1.0 - f.x) * ((i >> 1) != 0 ? f.y : 1.0 - f.y);
                history += w * _TS_UnpackHistory(state.y);
                footprint += w;
            }
        }
        bool isDisoccluded = footprint < 0.01;
        history = isDisoccluded ? vec3(sample0, 0.0, 0.0) : history / footprint;

        // 3. Reprojection: running moments of the raw samples, variance of a 0/1 sample from the mean.
        samples = min(history.z + 1.0, gMaxHistoryFrameNum);
        temporalMean = history.y + (sample0 - history.y) / samples;
        variance = samples > 1.0 ? temporalMean * (1.0 - temporalMean) * samples / (samples - 1.0) : 1.0;

        // History clamped to the neighbourhood (moving shadows have no motion vectors).
        float localVariance = max(localMean - localMean * localMean, 0.0);
        float halfWidth = gHistoryClampSigma * sqrt(localVariance);
        float clamped = clamp(history.x, localMean - halfWidth, localMean + halfWidth);

        // History outside the clamp box (a moving shadow) counts as fewer samples: the distance in
        // standard errors of the local mean, so that noise alone rarely shortens the history.
        float outside = max(abs(history.x - localMean) - halfWidth, 0.0) / max(gLocalMeanNoise * sqrt(localVariance), 0.002);
        samples *= exp(-TS_HISTORY_REJECTION * outside * outside);

        // Variance boost while few samples are known: a stronger spatial filter.
        if (samples < 16.0)
            variance = max(variance, localVariance) * max(16.0 - samples, 1.0);

        // Blend toward the current sample by history length.
        float alpha = mix(0.05, 1.0, sqrt(max(8.0 - samples, 0.0) / 8.0));
        result = mix(clamped, sample0, alpha);
    }

    imageStore(gOut_Temporal, pixel, vec4(result, variance, temporalMean, samples));

    if (gDebugView != TS_DEBUG_NONE)
    {
        float value = 0.0;
        if (gDebugView == TS_DEBUG_LOCAL_MEAN)
            value = localMean;
        else if (gDebugView == TS_DEBUG_TEMPORAL_VARIANCE)
            value = variance;
        else if (gDebugView == TS_DEBUG_HISTORY_LENGTH)
            value = samples / TS_MAX_HISTORY;
        else if (gDebugView == TS_DEBUG_TILE_CLASS)
            value = float(tileClass) * 0.25;
        imageStore(gOut_Debug, pixel, vec4(value));
    }
}
