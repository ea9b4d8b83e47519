#version 450
#extension GL_GOOGLE_include_directive : require

// REFLECTION indirect arguments (document 002, "prepare indirect args").

#include "Bindings.glsl"
#include "Reflection_PrepareArgs.resources.h"
#include "Common.glsl"
#include "Reflection_Common.glsl"

void main()
{
    uint rays = gCounters[RF_WORD_LIVE_RAYS];
    uint tiles = gCounters[RF_WORD_LIVE_TILES];
    gCounters[RF_WORD_TRACE_ARGS + 0u] = (rays + REFLECTION_RAYS_PER_GROUP - 1u) / REFLECTION_RAYS_PER_GROUP;
    gCounters[RF_WORD_TRACE_ARGS + 1u] = 1u;
    gCounters[RF_WORD_TRACE_ARGS + 2u] = 1u;
    gCounters[RF_WORD_RAY_COUNT] = rays;
    gCounters[RF_WORD_DENOISE_ARGS + 0u] = tiles;
    gCounters[RF_WORD_DENOISE_ARGS + 1u] = 1u;
    gCounters[RF_WORD_DENOISE_ARGS + 2u] = 1u;
    gCounters[RF_WORD_TILE_COUNT] = tiles;
    gCounters[RF_WORD_LIVE_RAYS] = 0u;
    gCounters[RF_WORD_LIVE_TILES] = 0u;
}
