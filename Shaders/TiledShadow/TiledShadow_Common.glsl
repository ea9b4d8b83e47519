// TILED_SHADOW: helpers shared by its passes (tiles, history packing).
#ifndef TILED_SHADOW_COMMON_GLSL
#define TILED_SHADOW_COMMON_GLSL

// Tiles are 8x4 pixels; bit (x % 8) + 8 * (y % 4) of a tile's mask is pixel (x, y), 1 = lit.
#define TS_TILE_W 8
#define TS_TILE_H 4

// Tile classes (the tile class texture, TiledShadowDebug::TILE_CLASS shows class / 4).
#define TS_TILE_FILTERED 0u
#define TS_TILE_LIT 1u      // Uniformly lit neighbourhood: skipped, written as 1.
#define TS_TILE_SHADOWED 2u // Uniformly shadowed neighbourhood: skipped, written as 0.
#define TS_TILE_SKY 3u      // Every pixel is sky: skipped, nothing written.

// gFlags bits of the classification pass.
#define TS_FLAG_TILE_SKIPPING 1u
#define TS_FLAG_HISTORY_VALID 2u

// TiledShadowDebug values.
#define TS_DEBUG_NONE 0u
#define TS_DEBUG_LOCAL_MEAN 1u
#define TS_DEBUG_TEMPORAL_VARIANCE 2u
#define TS_DEBUG_HISTORY_LENGTH 3u
#define TS_DEBUG_TILE_CLASS 4u

// The classification's variance channel below zero: the output is the sample 'TS_OUTPUT_SAMPLE -
// variance' with no variance, while the history keeps the shadow channel.
#define TS_OUTPUT_SAMPLE -1.0

// The (shadow, variance) the filter sees in a texel of the classification's output.
vec2 _TS_FilterInput(vec2 shadowVariance)
{
    return shadowVariance.y < 0.0 ? vec2(TS_OUTPUT_SAMPLE - shadowVariance.y, 0.0) : shadowVariance;
}

// Largest history length the packed state holds (TILED_SHADOW_MAX_HISTORY_FRAME_NUM).
#define TS_MAX_HISTORY 63.0

uvec2 _TS_TileCount(uvec2 size) { return (size + uvec2(TS_TILE_W - 1, TS_TILE_H - 1)) / uvec2(TS_TILE_W, TS_TILE_H); }

// The permanent state texture (RG32_UINT): .x = viewZ (float bits, the low 9 mantissa bits
// replaced by the running mean of the local mean, 8-bit unorm, and the pixel's raw sample in bit 8:
// viewZ keeps 14 mantissa bits),
// .y = history (the classification's temporal result, 12-bit unorm) | temporal mean of the raw samples
// (12-bit unorm) << 12 | accumulated samples * 4 (8 bits) << 24. The raw samples are 0 or 1, so
// their temporal variance follows from the mean: mean * (1 - mean).
// The classification hands the moments to the first a-trous pass in one R32_UINT: running local
// mean (bits 0..7), raw sample (bit 8), TS_MOMENTS_HELD, temporal mean << 12, samples * 4 << 24.
uint _TS_PackUnorm(float x, float scale) { return uint(clamp(_NRD_Sanitize(x, 0.0), 0.0, 1.0) * scale + 0.5); }

// Moments bit of a pixel whose state keeps its history (TS_HOLD_DECAY in the classification): the
// first a-trous pass stores the classification's shadow channel as its history, in skipped tiles too.
#define TS_MOMENTS_HELD 0x200u

uint _TS_PackMoments(float temporalMean, float samples, float localMean, float sample0)
{
    uint n = uint(clamp(_NRD_Sanitize(samples, 0.0), 0.0, TS_MAX_HISTORY) * 4.0 + 0.5);
    return _TS_PackUnorm(localMean, 255.0) | (sample0 != 0.0 ? 0x100u : 0u) | (_TS_PackUnorm(temporalMean, 4095.0) << 12) |
           (n << 24);
}

uvec2 _TS_PackState(float viewZ, float history, uint moments)
{
    return uvec2((floatBitsToUint(viewZ) & ~0x1FFu) | (moments & 0x1FFu), (moments & ~0xFFFu) | _TS_PackUnorm(history, 4095.0));
}

float _TS_UnpackViewZ(uint x) { return uintBitsToFloat(x & ~0x1FFu); }
float _TS_UnpackLocalMean(uint x) { return float(x & 0xFFu) * (1.0 / 255.0); }
uint _TS_UnpackSample(uint x) { return (x >> 8) & 1u; }

// .x history, .y temporal mean, .z accumulated samples.
vec3 _TS_UnpackHistory(uint packed)
{
    return vec3(float(packed & 4095u) * (1.0 / 4095.0), float((packed >> 12) & 4095u) * (1.0 / 4095.0),
                float(packed >> 24) * 0.25);
}

#endif
