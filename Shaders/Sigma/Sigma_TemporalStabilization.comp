// SIGMA temporal stabilization (document 004, SIGMA).
//
// Reprojects this pixel into the previous frame (camera motion from the matrices, object motion
// from IN_MV, 2D or world-space 3D), fetches the previous result with a bilinear footprint whose
// taps are dropped when their stored viewZ disagrees with the expected one (disocclusion), clamps
// it to mean +- sigma of the blurred current frame's 5x5 neighbourhood (a moving shadow cannot
// leave a ghost), shortens the history where clamping had to move it (anti-lag) and blends with a
// per-pixel history length of at most gMaxStabilizedFrameNum frames. History = this frame's result,
// stored with its viewZ and history length (viewZ bits with the 5 low bits replaced by the length).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Sigma_TemporalStabilization.resources.h"
#include "CommonFrame.glsl"
#include "Sigma_Common.glsl"

#define BORDER 2
#define SMEM_SIZE (SIGMA_TILE_SIZE + 2 * BORDER)
#define HISTORY_LENGTH_MASK 31u
#define SIGMA_SCALE 1.0     // Clamping box: mean +- SIGMA_SCALE * sigma.
#define ANTILAG_SCALE 10.0  // History length lost per unit of clamping displacement.

shared float s_ViewZ[SMEM_SIZE][SMEM_SIZE]; // 0 = sky or outside the image
shared SIGMA_TYPE s_Signal[SMEM_SIZE][SMEM_SIZE];

SIGMA_TYPE LoadBlurred(ivec2 pixel)
{
#if SIGMA_TRANSLUCENCY
    return _Sigma_Signal01(texelFetch(sampler2D(gIn_Shadow, gNearestClamp), pixel, 0));
#else
    return _Sigma_Signal01(texelFetch(sampler2D(gIn_Shadow, gNearestClamp), pixel, 0).x);
#endif
}

SIGMA_TYPE LoadHistory(ivec2 pixel)
{
    // Previous history may be uninitialized where its taps are rejected: sanitize before weighting.
#if SIGMA_TRANSLUCENCY
    return _Sigma_Signal01(texelFetch(sampler2D(gPrev_Shadow, gNearestClamp), pixel, 0));
#else
    return _Sigma_Signal01(texelFetch(sampler2D(gPrev_Shadow, gNearestClamp), pixel, 0).x);
#endif
}

uint PackViewZAndHistoryLength(float viewZ, float historyLength)
{
    return (floatBitsToUint(viewZ) & ~HISTORY_LENGTH_MASK) | min(uint(historyLength + 0.5), HISTORY_LENGTH_MASK);
}

// Marks a pixel without history (sky): its viewZ never matches.
const uint kNoHistory = 0x7F7FFFE0u; // ~3.4e38, length 0

void WriteResult(ivec2 pixel, SIGMA_TYPE result, float viewZ, float historyLength)
{
    imageStore(gOut_ShadowTranslucency, pixel, vec4(result));
    imageStore(gHistory_Shadow, pixel, vec4(result));
    imageStore(gHistory_ViewZHistoryLength, pixel, uvec4(PackViewZAndHistoryLength(viewZ, historyLength)));
}

void main()
{
    uint mode = _Sigma_GroupTileMode(gIn_Tiles);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool isInside = all(lessThan(uvec2(pixel), gResourceSize));

    if (mode != SIGMA_MODE_DENOISE)
    {
        if (!isInside)
            return;
        float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
        if (mode == SIGMA_MODE_SKY || _NRD_IsSky(z))
            imageStore(gHistory_ViewZHistoryLength, pixel, uvec4(kNoHistory));
        else // Uniform input: exact. Full length so that neighbours entering a penumbra keep it.
            WriteResult(pixel, LoadBlurred(pixel), z, gMaxStabilizedFrameNum);
        return;
    }

    ivec2 groupOrigin = ivec2(gl_WorkGroupID.xy) * SIGMA_TILE_SIZE - BORDER;
    for (uint i = gl_LocalInvocationIndex; i < uint(SMEM_SIZE * SMEM_SIZE); i += uint(SIGMA_TILE_SIZE * SIGMA_TILE_SIZE))
    {
        ivec2 smemPos = ivec2(int(i % uint(SMEM_SIZE)), int(i / uint(SMEM_SIZE)));
        ivec2 p = groupOrigin + smemPos;
        float z = 0.0;
        SIGMA_TYPE s = SIGMA_TYPE(0.0);
        if (all(greaterThanEqual(p, ivec2(0))) && all(lessThan(uvec2(p), gResourceSize)))
        {
            float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), p, 0).x;
            if (!_NRD_IsSky(viewZ))
            {
                z = viewZ;
                s = LoadBlurred(p);
            }
        }
        s_ViewZ[smemPos.y][smemPos.x] = z;
        s_Signal[smemPos.y][smemPos.x] = s;
    }
    barrier();

    if (!isInside)
        return;
    ivec2 c = ivec2(gl_LocalInvocationID.xy) + BORDER;
    float viewZ = s_ViewZ[c.y][c.x];
    if (viewZ == 0.0)
    {
        imageStore(gHistory_ViewZHistoryLength, pixel, uvec4(kNoHistory));
        return; // Sky: output not written.
    }

    // Neighbourhood statistics of the blurred current frame (5x5, sky excluded).
    SIGMA_TYPE m1 = SIGMA_TYPE(0.0);
    SIGMA_TYPE m2 = SIGMA_TYPE(0.0);
    float count = 0.0;
    for (int j = -BORDER; j <= BORDER; j++)
    {
        for (int i = -BORDER; i <= BORDER; i++)
        {
            if (s_ViewZ[c.y + j][c.x + i] == 0.0)
                continue;
            SIGMA_TYPE s = s_Signal[c.y + j][c.x + i];
            m1 += s;
            m2 += s * s;
            count += 1.0;
        }
    }
    m1 /= count; // >= 1: the center is not sky.
    m2 /= count;
    SIGMA_TYPE sigma = sqrt(max(m2 - m1 * m1, SIGMA_TYPE(0.0)));
    SIGMA_TYPE current = s_Signal[c.y][c.x];

    // Depth slope around the pixel: the disocclusion tolerance must cover a one-pixel step of the
    // footprint on surfaces seen at grazing angles.
    float slope = 0.0;
    for (int k = 0; k < 4; k++)
    {
        ivec2 o = ivec2(k == 0 ? 1 : (k == 1 ? -1 : 0), k == 2 ? 1 : (k == 3 ? -1 : 0));
        float z = s_ViewZ[c.y + o.y][c.x + o.x];
        if (z != 0.0)
            slope = max(slope, abs(z - viewZ));
    }

    // Reprojection.
    vec2 uv = _NRD_PixelUv(pixel);
    vec3 X = _NRD_WorldPosition(uv, viewZ);
    vec3 mv = texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz;
    vec3 Xprev;
    vec2 uvPrev = _NRD_PreviousUv(uv, X, mv, Xprev);
    float expectedViewZ = _NRD_PreviousViewZ(Xprev);
    float tolerance = gDisocclusionThreshold * abs(expectedViewZ) + 1.5 * slope;

    // Bilinear footprint with per-tap disocclusion test.
    vec2 footprint = uvPrev * vec2(gResourceSize) - 0.5;
    ivec2 origin = ivec2(floor(footprint));
    vec2 f = footprint - floor(footprint);
    float bilinear[4] = float[4]((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    SIGMA_TYPE history = SIGMA_TYPE(0.0);
    float historyLength = 0.0;
    float historyWeight = 0.0;
    bool isValidUv = gResetHistory == 0u && !isnan(footprint.x) && !isnan(footprint.y) && abs(footprint.x) < 65536.0 &&
                     abs(footprint.y) < 65536.0;
    for (int k = 0; k < 4 && isValidUv; k++)
    {
        ivec2 q = origin + ivec2(k & 1, k >> 1);
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(uvec2(q), gResourceSize)))
            continue;
        uint packed = texelFetch(usampler2D(gPrev_ViewZHistoryLength, gNearestClamp), q, 0).x;
        float prevViewZ = uintBitsToFloat(packed & ~HISTORY_LENGTH_MASK);
        if (!(abs(prevViewZ - expectedViewZ) <= tolerance))
            continue;
        float w = bilinear[k];
        history += LoadHistory(q) * w;
        historyLength += float(packed & HISTORY_LENGTH_MASK) * w;
        historyWeight += w;
    }

    SIGMA_TYPE result = current;
    float newLength = 1.0;
    if (historyWeight > 1e-3)
    {
        history /= historyWeight;
        historyLength /= historyWeight;

        SIGMA_TYPE clamped = clamp(history, m1 - SIGMA_SCALE * sigma, m1 + SIGMA_SCALE * sigma);
        float antilag = 1.0 - clamp(_Sigma_MaxComponent(abs(clamped - history)) * ANTILAG_SCALE, 0.0, 1.0);
        historyLength = min(historyLength * antilag, gMaxStabilizedFrameNum);

        result = mix(current, clamped, historyLength / (historyLength + 1.0));
        newLength = min(historyLength + 1.0, gMaxStabilizedFrameNum);
    }

    WriteResult(pixel, _Sigma_Signal01(result), viewZ, newLength);
}
