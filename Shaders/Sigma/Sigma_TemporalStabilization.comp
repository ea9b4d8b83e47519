// SIGMA temporal stabilization (document 004, SIGMA).
//
// Reprojects this pixel into the previous frame (camera motion from the matrices, object motion
// from IN_MV, 2D or world-space 3D), fetches the previous result with a bilinear footprint whose
// taps are dropped when their stored viewZ disagrees with the expected one (disocclusion; the
// tolerance grows with the surface's grazing angle), resamples it with Catmull-Rom where the whole
// footprint is valid, clamps it to mean +- sigma of the blurred current frame's 5x5 neighbourhood
// on the same surface (a moving shadow cannot leave a ghost), shortens the history where clamping
// had to move it (anti-lag) and blends with a per-pixel history length of at most
// gMaxStabilizedFrameNum frames. Hard shadows (sub-pixel penumbra) keep history only where it needs
// no resampling (where it does, only a lit sample whose previous samples were mostly dark takes some
// of it), and restart it where a shadow arrives or leaves; in a tile where hard shadows
// moved without motion vectors (many samples contradict settled histories, both ways) their pixels
// output this frame's sample, and so do hard shadows that the light's own move carried more than
// 1/20 pixel (SigmaSettings' moving lights; fewer frames of history for slower ones). History = this
// frame's result, stored with its viewZ, history length,
// whether this frame's sample was lit, whether a hard shadow's departure restarted it, whether
// its tile was moving and whether the sample was lit in the frame before too (viewZ bits with the 5
// low bits replaced by the length, bit 5 by the sample, bit 6 by the restart, bit 7 by the moving
// tile, bit 8 by the two lit samples, bit 9 where a hard shadow's history is its samples' running mean
// under motion, bit 10 where a moving tile's pass restarted a hard shadow's history at its sample).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Sigma_TemporalStabilization.resources.h"
#include "CommonFrame.glsl"
#include "Sigma_Common.glsl"
#include "ShadowMotion.glsl"

#define BORDER 2
#define SMEM_SIZE (SIGMA_TILE_SIZE + 2 * BORDER)
#define HISTORY_LENGTH_MASK 31u
// Bit 5 of the packed viewZ: the pixel's sample was lit (its value at least 0.5: a hard shadow's
// blur copies the input).
#define HISTORY_SAMPLE_BIT 32u
// Bit 6 of the packed viewZ: the history restarted there because a hard shadow left the pixel.
#define HISTORY_DEPARTED_BIT 64u
// Bit 7 of the packed viewZ: a hard shadow of a moving tile (see MovingTile).
#define HISTORY_MOVING_BIT 128u
// Bit 8 of the packed viewZ: the pixel's sample was lit, and so was the one of the frame before.
#define HISTORY_LIT_TWICE_BIT 256u
// Bit 9 of the packed viewZ: a hard shadow's history written under resampling (camera or surface
// motion): the running mean of its samples, not a still view's result.
#define HISTORY_MEAN_BIT 512u
// Bit 10 of the packed viewZ: a hard shadow's history that a moving tile's pass restarted at its sample
// (see the end of main): the moving-tile test leaves it out.
#define HISTORY_PASSED_BIT 1024u
#define HISTORY_VIEWZ_MASK (~(HISTORY_LENGTH_MASK | HISTORY_SAMPLE_BIT | HISTORY_DEPARTED_BIT | HISTORY_MOVING_BIT | HISTORY_LIT_TWICE_BIT | HISTORY_MEAN_BIT | \
                              HISTORY_PASSED_BIT))
// Clamping box: mean +- SIGMA_SCALE * sigma. History length lost per unit of clamping displacement:
// higher values follow moving shadows (moving lights and occluders) sooner at some cost in noise
// on still ones (measured on the scene lab's static / moving_light / moving_occluder scenes).
#define SIGMA_SCALE 1.0
#define ANTILAG_SCALE 15.0
#define HARD_SHADOW_ARRIVAL 0.75
// A hard-shadow pixel lit for the third frame in a row under history below 1 - HARD_SHADOW_LIT_RUN
// restarts it in a tile whose contradictions exceed a still view's (see main).
#define HARD_SHADOW_LIT_RUN 0.5
// A lit hard-shadow sample under resampled history (camera or surface motion) whose previous
// samples were lit on less than HARD_SHADOW_RESAMPLED_LIT of the bilinear footprint takes up to
// HARD_SHADOW_RESAMPLED_BLEND of the history (see main).
// A hard-shadow pixel whose history restarted, with a kernel radius of at least
// HARD_SHADOW_RESTART_RADIUS pixel, takes HARD_SHADOW_RESTART_BLEND of the 3x3 mean (see main).
#define HARD_SHADOW_RESTART_RADIUS 0.3
#define HARD_SHADOW_RESTART_BLEND 0.7
// ... and a shadowed sample of such a penumbra under dark history, in a tile whose departures are at
// least HARD_SHADOW_DEPARTING_TILE times its arrivals plus HARD_SHADOW_DEPARTING_EXCESS, takes
// HARD_SHADOW_FOLLOWER_BLEND of it (a still view's penumbra noise rarely gives 5 departures in rows).
#define HARD_SHADOW_DEPARTING_TILE 2.0
#define HARD_SHADOW_DEPARTING_EXCESS 5.0
#define HARD_SHADOW_FOLLOWER_BLEND 0.3
// A tile whose departures are at least HARD_SHADOW_DEPARTING_TILE times its arrivals plus its expected
// contradictions, plus HARD_SHADOW_DEPARTING_EXCESS, had its light switched on (see main).
#define HARD_SHADOW_RESAMPLED_LIT 0.25
#define HARD_SHADOW_RESAMPLED_BLEND 0.7
// Under resampling a hard shadow's history is the running mean of its samples over at most
// HARD_SHADOW_MEAN_FRAMES frames; a lit sample under a mean below HARD_SHADOW_MEAN_DARK takes
// HARD_SHADOW_MEAN_BLEND of the mean, weighted by the penumbra's kernel radius (all from
// HARD_SHADOW_MEAN_RADIUS pixel), unless the previous frame's sample there was lit too and the mean
// is above HARD_SHADOW_MEAN_LIT_AGAIN, or the surface moves on screen by more than
// HARD_SHADOW_MEAN_OBJECT_MOTION pixel beyond the camera's motion (see main).
#define HARD_SHADOW_MEAN_FRAMES 16.0
#define HARD_SHADOW_MEAN_DARK 0.5
#define HARD_SHADOW_MEAN_BLEND 0.75
#define HARD_SHADOW_MEAN_RADIUS 0.2
#define HARD_SHADOW_MEAN_LIT_AGAIN 0.35
#define HARD_SHADOW_MEAN_OBJECT_MOTION 0.05
// A light switched off (or a large occluder arriving) over a still surface: where the whole tile
// neighbourhood's input is 0 (a uniform tile) and the pixel's history was above HOLD_MIN_HISTORY, the
// output is the input, and the history keeps its value, length and flags. When the light returns, the
// blurred neighbourhood matches the kept history and it goes on where it stopped instead of restarting
// from the uniform 0 (a lamp switched every few frames); where the surface is lit otherwise, the clamp
// to the blurred neighbourhood shortens it as it would a moving shadow's. (One frame shorter per frame
// instead: the lengths of at most gMaxStabilizedFrameNum ran out within the lamps' off-periods.)
#define HOLD_MIN_HISTORY 0.01

shared float s_ViewZ[SMEM_SIZE][SMEM_SIZE]; // 0 = sky or outside the image
shared SIGMA_TYPE s_Signal[SMEM_SIZE][SMEM_SIZE];
shared float s_Penumbra[SMEM_SIZE][SMEM_SIZE]; // pixels
shared float s_OccluderMotion[SMEM_SIZE][SMEM_SIZE]; // pixels a moving occluder carried the shadow (0: none or unknown; -1: too soft to tell)
// Shadows that moving occluders carry (Shaders/Include/ShadowMotion.glsl): a hard-shadow pixel takes
// the fastest occluder motion of its neighbourhood of this radius (at most BORDER), unless a shadowed
// sample there has a penumbra radius of NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA pixels or more, or
// one of its 3x3 NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA or more.
#define OCCLUDER_MOTION_RADIUS 2
// A soft pixel (not a hard shadow) whose 5x5 holds penumbrae of NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA
// or more keeps at most this many of their widest radius of their fastest occluder's motion in its
// history (its history is where the surface was: a leg's shadow a few pixels soft at 960x540 trailed
// it, mesh_thin FLIP 1.05x the input's; at 1.0 radius 0.98x, at 0.5 0.93x). So does a hard pixel whose
// 3x3 holds penumbrae of NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA or more, none wider than
// NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA around (see main).
#define OCCLUDER_SOFT_RADII 0.5
// Moving-tile test (see MovingTile): over the group's hard-shadow pixels, the expected number of
// contradictions of a still view (x 1024), the contradictions with a neighbour contradicting the same
// way (departures: lit under dark history; arrivals: dark under lit), and how many of the pixels were
// in a moving tile the frame before.
shared uint s_ExpectedContradictions;
shared uint s_DepartureNum;
shared uint s_ArrivalNum;
shared uint s_WasMovingNum;
shared uint s_PixelNum;
shared int s_Contradiction[SIGMA_TILE_SIZE][SIGMA_TILE_SIZE]; // +1 departure, -1 arrival, 0 none

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

// Catmull-Rom resampling of the previous history around the bilinear footprint 'origin' + 'f'
// (taps outside the image are clamped to it); the 4 corner taps, whose weights are tiny, are left
// out and the rest renormalized. Clamped to [0, 1] against ringing. False (and 'result' untouched)
// where one of the 8 outer taps holds another surface or no history (sky, never written: its
// value is undefined) by the disocclusion test, with NRD_CATMULL_ROM_OUTER_TOLERANCE times the
// tolerance (the outer taps lie up to 2 pixels away); the caller keeps its bilinear history.
bool CatmullRomHistory(ivec2 origin, vec2 f, float expectedViewZ, float tolerance, inout SIGMA_TYPE result)
{
    vec4 wx = _NRD_CatmullRomWeights(f.x);
    vec4 wy = _NRD_CatmullRomWeights(f.y);
    ivec2 maxPixel = ivec2(gResourceSize) - 1;
    SIGMA_TYPE sum = SIGMA_TYPE(0.0);
    float weightSum = 0.0;
    for (int j = 0; j < 4; j++)
    {
        for (int i = 0; i < 4; i++)
        {
            bool isOuterI = i == 0 || i == 3, isOuterJ = j == 0 || j == 3;
            if (isOuterI && isOuterJ)
                continue;
            ivec2 q = clamp(origin + ivec2(i - 1, j - 1), ivec2(0), maxPixel);
            if (isOuterI || isOuterJ) // The inner 2x2 passed the test already.
            {
                uint packed = texelFetch(usampler2D(gPrev_ViewZHistoryLength, gNearestClamp), q, 0).x;
                if (!(abs(uintBitsToFloat(packed & HISTORY_VIEWZ_MASK) - expectedViewZ) <= NRD_CATMULL_ROM_OUTER_TOLERANCE * tolerance))
                    return false;
            }
            float w = wx[i] * wy[j];
            sum += LoadHistory(q) * w;
            weightSum += w;
        }
    }
    result = _Sigma_Signal01(sum / weightSum);
    return true;
}

uint PackViewZAndHistoryLength(float viewZ, float historyLength, bool isLit, bool isDeparted, bool isMoving, bool isLitTwice, bool isMean,
                               bool isPassedRestart)
{
    return (floatBitsToUint(viewZ) & HISTORY_VIEWZ_MASK) | min(uint(historyLength + 0.5), HISTORY_LENGTH_MASK) |
           (isLit ? HISTORY_SAMPLE_BIT : 0u) | (isDeparted ? HISTORY_DEPARTED_BIT : 0u) | (isMoving ? HISTORY_MOVING_BIT : 0u) |
           (isLit && isLitTwice ? HISTORY_LIT_TWICE_BIT : 0u) | (isMean ? HISTORY_MEAN_BIT : 0u) | (isPassedRestart ? HISTORY_PASSED_BIT : 0u);
}

// Lit samples (blurred signal at least 0.5) among the 8 neighbours of shared-memory position 'c'.
int LitNeighbourNum(ivec2 c)
{
    int litNum = 0;
    for (int j = -1; j <= 1; j++)
    {
        for (int i = -1; i <= 1; i++)
            litNum += (i != 0 || j != 0) && _Sigma_MaxComponent(s_Signal[c.y + j][c.x + i]) >= 0.5 ? 1 : 0;
    }
    return litNum;
}

// A hard shadow's pixel at 'q' of the previous frame (no resampling) with sample 'currentValue' now
// and 'packed' there: 0 unless lit now under dark history (lit sample minus history above
// HARD_SHADOW_ARRIVAL), 1 if so, 2 if its sample was lit there too (lit for the second frame in a row).
int DepartureLevel(ivec2 q, SIGMA_TYPE currentValue, uint packed)
{
    if (_Sigma_MaxComponent(currentValue) < 0.5 || !(_Sigma_MaxComponent(currentValue - LoadHistory(q)) > HARD_SHADOW_ARRIVAL))
        return 0;
    return (packed & HISTORY_SAMPLE_BIT) != 0u ? 2 : 1;
}

// Marks a pixel without history (sky): its viewZ never matches.
const uint kNoHistory = 0x7F7FFF80u; // ~3.4e38, length 0, flags clear

// 'shown': the output ('isPassed': this frame's sample instead); 'result': the history.
void WriteResult(ivec2 pixel, SIGMA_TYPE shown, SIGMA_TYPE result, float viewZ, float historyLength, SIGMA_TYPE current, bool isDeparted,
                 bool isPassed, bool isMoving, bool wasLit, bool isMean, bool isPassedRestart)
{
    // The nearest fp16 value (_NRD_NearestFp16): the store's rounding cannot take an ulp off a lit 1.
    imageStore(gOut_ShadowTranslucency, pixel, vec4(_NRD_NearestFp16(isPassed ? current : shown)));
    imageStore(gHistory_Shadow, pixel, vec4(result));
    bool isLit = _Sigma_MaxComponent(current) >= 0.5;
    imageStore(gHistory_ViewZHistoryLength, pixel,
               uvec4(PackViewZAndHistoryLength(viewZ, historyLength, isLit, isDeparted, isMoving, wasLit, isMean, isPassedRestart)));
}

void main()
{
    uint mode = _Sigma_GroupTileMode(gIn_TileModes);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool isInside = all(lessThan(uvec2(pixel), gResourceSize));

    if (mode != SIGMA_MODE_DENOISE)
    {
        if (!isInside)
            return;
        float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
        if (mode == SIGMA_MODE_SKY || _NRD_IsSky(z))
        {
            imageStore(gHistory_ViewZHistoryLength, pixel, uvec4(kNoHistory));
            imageStore(gHistory_Shadow, pixel, vec4(0.0));
        }
        else // Uniform input: exact. Full length so that neighbours entering a penumbra keep it.
        {
            SIGMA_TYPE value = LoadBlurred(pixel);
            // See HOLD_MIN_HISTORY. The pixel's own history first: a steady umbra reads nothing else.
            SIGMA_TYPE kept = SIGMA_TYPE(0.0);
            if (_Sigma_MaxComponent(value) == 0.0 && gResetHistory == 0u)
                kept = LoadHistory(pixel);
            if (_Sigma_MaxComponent(kept) > HOLD_MIN_HISTORY)
            {
                vec2 uv = _NRD_PixelUv(pixel);
                vec3 X = (gViewToWorld * vec4(_NRD_ViewPosition(uv, z), 1.0)).xyz;
                vec3 Xprev;
                vec2 uvPrev = _NRD_PreviousUv(uv, X, texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz, Xprev);
                if (_NRD_IsOwnTexel(uvPrev, pixel, vec2(gResourceSize)))
                {
                    uint packed = texelFetch(usampler2D(gPrev_ViewZHistoryLength, gNearestClamp), pixel, 0).x;
                    float expectedViewZ = _NRD_PreviousViewZ(Xprev);
                    if (abs(uintBitsToFloat(packed & HISTORY_VIEWZ_MASK) - expectedViewZ) < gDisocclusionThreshold * expectedViewZ &&
                        (packed & HISTORY_LENGTH_MASK) != 0u)
                    {
                        imageStore(gOut_ShadowTranslucency, pixel, vec4(value));
                        imageStore(gHistory_Shadow, pixel, vec4(kept));
                        imageStore(gHistory_ViewZHistoryLength, pixel, uvec4((floatBitsToUint(z) & HISTORY_VIEWZ_MASK) | (packed & ~HISTORY_VIEWZ_MASK)));
                        return;
                    }
                }
            }
            WriteResult(pixel, value, value, z, gMaxStabilizedFrameNum, value, false, false, false, false, false, false);
        }
        return;
    }

    bool isLightMoving = _NRD_ShadowMotion_IsLightMoving();
    if (gl_LocalInvocationIndex == 0u)
    {
        s_ExpectedContradictions = 0u;
        s_DepartureNum = 0u;
        s_ArrivalNum = 0u;
        s_WasMovingNum = 0u;
        s_PixelNum = 0u;
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
        float penumbra = SIGMA_UNKNOWN_PENUMBRA;
        if (z != 0.0)
            penumbra = _NRD_Sanitize(texelFetch(sampler2D(gIn_Penumbra, gNearestClamp), p, 0).x, SIGMA_UNKNOWN_PENUMBRA);
        // Occluder motion where the penumbra is narrow enough to use it (NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA);
        // a wider one holds -1 minus its occluder's motion (OCCLUDER_SOFT_RADII).
        float occluder = penumbra >= NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA ? -1.0 : 0.0;
        if (z != 0.0 && penumbra >= 0.0 && penumbra < NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA)
            occluder = _NRD_ShadowMotion_OccluderPixels(p, z, penumbra);
        else if (z != 0.0 && penumbra >= NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA && penumbra < NRD_FP16_MAX * 0.75)
            occluder = -1.0 - min(_NRD_ShadowMotion_OccluderPixels(p, z, penumbra), NRD_FP16_MAX * 0.5); // -1 - its motion.
        s_OccluderMotion[smemPos.y][smemPos.x] = occluder;
        s_Penumbra[smemPos.y][smemPos.x] = penumbra;
    }
    barrier();

    ivec2 c = ivec2(gl_LocalInvocationID.xy) + BORDER;
    float viewZ = isInside ? s_ViewZ[c.y][c.x] : 0.0;
    bool isHardShadow = false;
    SIGMA_TYPE current = SIGMA_TYPE(0.0);
    SIGMA_TYPE m1 = SIGMA_TYPE(0.0);
    SIGMA_TYPE nearMean = SIGMA_TYPE(0.0);
    float nearWeight = 0.0;
    SIGMA_TYPE sigma = SIGMA_TYPE(0.0);
    SIGMA_TYPE minimum = SIGMA_TYPE(0.0);
    SIGMA_TYPE maximum = SIGMA_TYPE(0.0);
    ivec2 origin = ivec2(0);
    vec2 f = vec2(0.0);
    SIGMA_TYPE history = SIGMA_TYPE(0.0);
    float historyLength = 0.0;
    float historyWeight = 0.0;
    int contradiction = 0;
    bool wasLit = false;
    bool isResampledHard = false;
    bool isMovingHard = false; // isResampledHard by this frame's motion (not only by a mean history)
    bool isObjectMoving = false; // The surface moves on screen by more than the camera's motion.
    uint nearestPacked = 0u; // The nearest history texel's packed viewZ, where it passed the disocclusion test.
    float tapLit = 0.0;
    float kernelRadius = 0.0;
    float occluderMotion = 0.0; // Pixels moving occluders carried the shadows around this frame.
    bool isWideAround = false; // A penumbra too wide for them lies around.
    bool isSoftAround = false; // A penumbra of NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA or more lies around.
    float nearWidest = 0.0; // The 3x3's widest penumbra radius (pixels).
    float softMotion = 0.0, softWidest = 0.0; // The fastest occluder of the wider penumbrae around, their widest.
    float shadowMotion = 0.0; // Pixels the light's move carried the shadow this frame (ShadowMotion.glsl).
    bool isDarkTerminator = false; // On the dark half of the light's terminator (see isResampledHard).
    float expectedViewZ = 0.0; // The surface's viewZ in the previous frame, and the disocclusion test's tolerance.
    float tolerance = 0.0;
    if (viewZ != 0.0)
    {
        // Hard shadow: a kernel under a pixel (the blurs copied it or barely changed it). The input is
        // then exact away from edges, and history only helps (anti-aliasing) on a still view.
        float penumbra = texelFetch(sampler2D(gIn_Penumbra, gNearestClamp), pixel, 0).x;
        kernelRadius = _Sigma_KernelRadius(max(_NRD_Sanitize(penumbra, 0.0), 0.0));
        isHardShadow = kernelRadius < 1.0;
        if (isLightMoving)
        {
            // The penumbra estimate of a pixel prefers the smaller penumbrae around it (Sigma_Blur):
            // the largest of the 3x3 neighbourhood's (on a surface) sets the motion. Where there is
            // none (lit, SIGMA_UNKNOWN_PENUMBRA) a shadow that was there has moved on, and a lit
            // sample is exact.
            float widest = SIGMA_UNKNOWN_PENUMBRA;
            for (int j = -1; j <= 1; j++)
                for (int i = -1; i <= 1; i++)
                    widest = max(widest, s_Penumbra[c.y + j][c.x + i]);
            float motionPerPenumbra = _NRD_ShadowMotion_PerPenumbra(_NRD_ViewPosition(_NRD_PixelUv(pixel), viewZ));
            shadowMotion = _NRD_ShadowMotion_Pixels(widest, motionPerPenumbra);
        }

        // Shadows that moving occluders carried (OCCLUDER_MOTION_RADIUS): the neighbourhood's, so that
        // the lit pixels that a moving shadow just left, and those it is about to cover, count as
        // moved too.
        for (int j = -OCCLUDER_MOTION_RADIUS; j <= OCCLUDER_MOTION_RADIUS; j++)
        {
            for (int i = -OCCLUDER_MOTION_RADIUS; i <= OCCLUDER_MOTION_RADIUS; i++)
            {
                float m = s_OccluderMotion[c.y + j][c.x + i];
                occluderMotion = max(occluderMotion, m);
                if (m < 0.0)
                {
                    softMotion = max(softMotion, -1.0 - m);
                    softWidest = max(softWidest, s_Penumbra[c.y + j][c.x + i]);
                }
                // A penumbra of NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA or more around, or of
                // NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA or more in the 3x3.
                isSoftAround = isSoftAround || m < 0.0;
                if (abs(i) <= 1 && abs(j) <= 1 && s_Penumbra[c.y + j][c.x + i] < NRD_FP16_MAX * 0.75)
                    nearWidest = max(nearWidest, s_Penumbra[c.y + j][c.x + i]);
                isWideAround = isWideAround || m < 0.0 ||
                               (abs(i) <= 1 && abs(j) <= 1 && s_Penumbra[c.y + j][c.x + i] >= NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA);
            }
        }

        vec2 uv = _NRD_PixelUv(pixel);
        vec3 Xv = _NRD_ViewPosition(uv, viewZ);
        vec3 N = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), pixel, 0)).xyz;
        vec3 Nv = _Sigma_ViewNormal(N);
        SigmaPlane plane = _Sigma_Plane(uv, viewZ, Nv);
        float horizon = _NRD_ShadowMotion_HorizonVisibility(Xv, Nv);
        isDarkTerminator = horizon > 0.0 && horizon < 0.5;

        // Neighbourhood statistics of the blurred current frame (5x5; sky and other surfaces excluded
        // by plane distance, so a thin object's box is not widened by its background).
        current = s_Signal[c.y][c.x];
        SIGMA_TYPE m2 = SIGMA_TYPE(0.0);
        minimum = current; // 3x3 range, for hard shadows
        maximum = current;
        float weightSum = 0.0;
        for (int j = -BORDER; j <= BORDER; j++)
        {
            for (int i = -BORDER; i <= BORDER; i++)
            {
                float z = s_ViewZ[c.y + j][c.x + i];
                float w = z == 0.0 ? 0.0 : _Sigma_NeighbourPlaneWeight(plane, i, j, z);
                SIGMA_TYPE s = s_Signal[c.y + j][c.x + i];
                m1 += s * w;
                m2 += s * s * w;
                weightSum += w;
                if (abs(i) <= 1 && abs(j) <= 1) // 3x3 mean, weights 1, 1/2, 1/4 (see the restart below).
                {
                    float wn = w * (i == 0 ? 1.0 : 0.5) * (j == 0 ? 1.0 : 0.5);
                    nearMean += s * wn;
                    nearWeight += wn;
                }
                if (abs(i) <= 1 && abs(j) <= 1 && w > 0.5)
                {
                    minimum = min(minimum, s);
                    maximum = max(maximum, s);
                }
            }
        }
        m1 /= weightSum; // >= 1: the center has weight 1.
        nearMean /= nearWeight;
        m2 /= weightSum;
        sigma = sqrt(max(m2 - m1 * m1, SIGMA_TYPE(0.0)));

        // Reprojection.
        vec3 X = (gViewToWorld * vec4(Xv, 1.0)).xyz;
        vec3 mv = texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz;
        vec3 Xprev;
        vec2 uvPrev = _NRD_PreviousUv(uv, X, mv, Xprev);
        expectedViewZ = _NRD_PreviousViewZ(Xprev);
        isObjectMoving = _NRD_ObjectMotionPixels(uvPrev, X) > HARD_SHADOW_MEAN_OBJECT_MOTION;

        // Disocclusion tolerance: relative depth, plus the depth change across the one pixel that
        // separates a bilinear tap from the reprojected point on a surface seen at a grazing angle.
        float NoV = abs(dot(Nv, normalize(Xv)));
        tolerance = _NRD_DisocclusionTolerance(viewZ, expectedViewZ, NoV, gDisocclusionThreshold, gProjectY);

        // Bilinear footprint with per-tap disocclusion test.
        vec2 footprint = uvPrev * vec2(gResourceSize) - 0.5;
        NrdFootprint nearestTexels = _NRD_Footprint(uvPrev, vec2(gResourceSize));
        origin = nearestTexels.origin;
        f = nearestTexels.f;
        vec4 bilinear = _NRD_BilinearWeights(f);
        bool isValidUv = gResetHistory == 0u && !isnan(footprint.x) && !isnan(footprint.y) && abs(footprint.x) < 65536.0 &&
                         abs(footprint.y) < 65536.0;
        // A hard shadow keeps history only where it needs no resampling (still camera and surface): the
        // input is as sharp as the truth there, and resampled history (even Catmull-Rom) would soften
        // it. (Fading history out up to 3-pixel penumbrae instead helped rotating cameras and hurt
        // translating ones by as much.) Where it needs resampling, see isResampledHard below.
        // So does a whole-pixel move (the nearest history texel is another pixel's), and the first
        // still frame after motion (the nearest texel holds a running mean, HISTORY_MEAN_BIT).
        vec2 subpixel = min(f, 1.0 - f);
        int nearestTap = (f.x >= 0.5 ? 1 : 0) + (f.y >= 0.5 ? 2 : 0);
        isMovingHard = isHardShadow && (max(subpixel.x, subpixel.y) >= 0.01 || origin + ivec2(nearestTap & 1, nearestTap >> 1) != pixel);
        for (int k = 0; k < 4 && isValidUv; k++)
        {
            ivec2 q = origin + ivec2(k & 1, k >> 1);
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(uvec2(q), gResourceSize)))
                continue;
            uint packed = texelFetch(usampler2D(gPrev_ViewZHistoryLength, gNearestClamp), q, 0).x;
            float prevViewZ = uintBitsToFloat(packed & HISTORY_VIEWZ_MASK);
            if (!(abs(prevViewZ - expectedViewZ) <= tolerance))
                continue;
            if (k == nearestTap)
                nearestPacked = packed;
            float w = bilinear[k];
            tapLit += (packed & HISTORY_SAMPLE_BIT) != 0u ? w : 0.0;
            history += LoadHistory(q) * w;
            historyLength += float(packed & HISTORY_LENGTH_MASK) * w;
            historyWeight += w;
        }
        isResampledHard = isMovingHard || (isHardShadow && (nearestPacked & HISTORY_MEAN_BIT) != 0u);

        // Moving-tile test, 1: the hard-shadow pixels whose history needs no resampling; on an edge
        // (both samples in the 3x3 range) under settled history (within 1 - HARD_SHADOW_ARRIVAL of 0
        // or 1), the chance that a still view's sample contradicts it (the history's distance to the
        // nearer end, at least 0.03 and a quarter of what a young history of its length allows: 1 /
        // (length + 2) by the rule of succession; 0.008 for a history of the full length, whose
        // samples agreed for longer than the length tells), and whether the sample does. Not where a
        // moving tile's pass restarted the history at its sample (HISTORY_PASSED_BIT): one draw of a
        // penumbra is no settled history, and the next draws contradict it far more often than the
        // chance above, which kept still tiles moving and output the lit draws of penumbrae whose
        // truth is under 0.2 (without this, fast_occluder's relMSE ratio 1.86 -> 1.59 at 64x64, FLIP
        // 0.814x -> 0.833x the input's).
        if (isHardShadow && !isResampledHard && historyWeight > 0.999)
        {
            uint packedQ = nearestPacked;
            atomicAdd(s_PixelNum, 1u);
            if ((packedQ & HISTORY_MOVING_BIT) != 0u)
                atomicAdd(s_WasMovingNum, 1u);
            wasLit = (packedQ & HISTORY_SAMPLE_BIT) != 0u;
            if (_Sigma_MaxComponent(maximum - minimum) >= 0.5 && (packedQ & HISTORY_PASSED_BIT) == 0u)
            {
                SIGMA_TYPE h = history / historyWeight;
                float settled = _Sigma_MaxComponent(min(h, 1.0 - h));
                if (settled < 1.0 - HARD_SHADOW_ARRIVAL)
                {
                    float length = historyLength / historyWeight;
                    float chance = max(settled, length > gMaxStabilizedFrameNum - 0.5 ? 0.008 : max(0.03, 0.25 / (length + 2.0)));
                    atomicAdd(s_ExpectedContradictions, uint(chance * 1024.0 + 0.5));
                }
                if (_Sigma_MaxComponent(current - h) > HARD_SHADOW_ARRIVAL)
                    contradiction = 1;
                else if (_Sigma_MaxComponent(h - current) > HARD_SHADOW_ARRIVAL)
                    contradiction = -1;
            }
        }
    }
    // 2. Contradictions with a neighbour in the tile that contradicts the same way (a shadow edge that
    // moved turns rows of pixels; a still penumbra's noise mostly single ones).
    ivec2 t = ivec2(gl_LocalInvocationID.xy);
    s_Contradiction[t.y][t.x] = contradiction;
    barrier();
    if (contradiction != 0)
    {
        bool isRow = false;
        for (int j = -1; j <= 1; j++)
        {
            for (int i = -1; i <= 1; i++)
            {
                ivec2 n = clamp(t + ivec2(i, j), ivec2(0), ivec2(SIGMA_TILE_SIZE - 1));
                isRow = isRow || (n != t && s_Contradiction[n.y][n.x] == contradiction);
            }
        }
        if (isRow && contradiction > 0)
            atomicAdd(s_DepartureNum, 1u);
        else if (isRow)
            atomicAdd(s_ArrivalNum, 1u);
    }
    barrier();
    // 3. The tile's hard shadows moved without motion vectors (a turning light, moving stripes, an
    // animated occluder's shadow on a still receiver) where they contradict their histories twice as
    // often as a still view would, by at least 3, and both ways (departures and arrivals: a light
    // switched on or off turns all of them one way, and the arrival and departure rules restart
    // those); or, in a tile whose pixels were mostly in a moving tile the frame before, as often as a
    // still view would, by at least 1. A tile whose hard shadows contradict their histories more
    // often than a still view would, by at least 1, is "stirred" (see the lit run below).
    float expected = float(s_ExpectedContradictions) / 1024.0;
    float contradictionNum = float(s_DepartureNum + s_ArrivalNum);
    bool isStirredTile = contradictionNum >= expected + 1.0;
    bool isDepartingTile = float(s_DepartureNum) >= HARD_SHADOW_DEPARTING_TILE * float(s_ArrivalNum) + HARD_SHADOW_DEPARTING_EXCESS;
    // A light switched on: departures beyond what the tile's young histories give a still view as well
    // (after a switch-on the penumbrae's histories are young, and a few departures a frame are their
    // noise: tl_5nosun's tile gave 5 departures two frames after the switch, expected 4; 51 at it,
    // expected 0.65).
    bool isSwitchedOnTile = float(s_DepartureNum) >=
                            HARD_SHADOW_DEPARTING_TILE * (float(s_ArrivalNum) + expected) + HARD_SHADOW_DEPARTING_EXCESS;
    bool isMovingTile = (min(s_DepartureNum, s_ArrivalNum) >= 2u && contradictionNum >= 2.0 * expected + 3.0) ||
                        (contradictionNum >= expected + 1.0 && 2u * s_WasMovingNum > s_PixelNum);
    // A hard shadow of a moving tile outputs its sample: a history of a shadow that moves a pixel or
    // more a frame is worth little and leaves grey trails along every edge. A lit sample only where
    // one of its 8 neighbours is lit too or it was lit the frame before (a single lit sample in a
    // dark penumbra is noise, and the costliest error there; the end of a one-pixel lit stripe has
    // one lit neighbour).
    bool isPassed = false;
    bool isMotionPassed = false; // Passed by the light's or the occluder's motion (not the moving tile).
    if (isHardShadow && isMovingTile)
    {
        isPassed = _Sigma_MaxComponent(current) < 0.5 || LitNeighbourNum(c) >= 1 || wasLit;
    }

    if (!isInside)
        return;
    if (viewZ == 0.0)
    {
        imageStore(gHistory_ViewZHistoryLength, pixel, uvec4(kNoHistory));
        imageStore(gHistory_Shadow, pixel, vec4(0.0)); // Never read (kNoHistory), but defined.
        return; // Sky: output not written.
    }


    SIGMA_TYPE result = current;
    SIGMA_TYPE shown = current; // The output where it is not the history.
    bool isMean = false; // The history is a hard shadow's running mean (HISTORY_MEAN_BIT).
    float newLength = 1.0;
    bool isDeparted = false;
    SIGMA_TYPE passHistory = current; // A still view's clamped history and its length (see the pass below).
    float passLength = 0.0;
    if (isResampledHard)
    {
        // A hard shadow whose history needs resampling (camera or surface motion). Resampled history
        // softens the edges and greys the pixels beside them, where the truth is 0 or 1: the sample
        // is output as it is, and the history becomes the running mean of the samples (over at most
        // HARD_SHADOW_MEAN_FRAMES, the resampled history clamped to the 3x3 range): where the
        // pixel's centre lies in a sub-pixel penumbra, its samples at the points the motion carries
        // it through average towards the pixel's coverage. Two lit samples take from it: the
        // costliest error there is a lit sample of a mostly dark penumbra (relMSE weighs a dark truth
        // most), and a dark sample stays dark (a grey history on a pixel whose truth is 0 costs 100
        // times the same error on a lit one).
        // - A lit sample under a mean below HARD_SHADOW_MEAN_DARK takes HARD_SHADOW_MEAN_BLEND of the
        //   mean (all of it darkens the penumbra's local average, whose dark samples stay 0, and FLIP
        //   rises), weighted by the penumbra's kernel radius (none at 0: a lit sample under dark
        //   history there is more often a geometric detail that the previous frame's pixels missed
        //   than a penumbra; all from HARD_SHADOW_MEAN_RADIUS. None up to 0.05 pixel instead took the
        //   hard sun's fast orbits to the input's FLIP, from 1.009x, but camera_rotation over 10
        //   frames at 64x64 above the input's FLIP and temporal instability, 1.002x and 1.003x), and
        //   all of it on the dark half of the light's terminator (less than half of the light's disk
        //   above the surface's tangent plane:
        //   a sphere's self-shadow edge, whose visibility is fractional while the penumbra estimate
        //   of its self-occlusion, a hit next to the sample, is 0; camera_translation at 256x256:
        //   relMSE ratio 1.89 -> 2.40, FLIP lower). Not where the previous frame's sample
        //   at the nearest texel was lit as well and the mean is above HARD_SHADOW_MEAN_LIT_AGAIN: a
        //   lit corner beside a hard edge, whose mean the bilinear footprint darkens from across the
        //   edge. Nor on a moving object: its shadows move over it as it turns under the light (a
        //   spider's legs: lit pixels whose mean holds the self-shadow of a few frames before).
        // - A lit sample where the previous frame's samples around the reprojected point were mostly
        //   dark (lit on less than HARD_SHADOW_RESAMPLED_LIT of the bilinear footprint) takes
        //   HARD_SHADOW_RESAMPLED_BLEND of the clamped history, weighted by the kernel radius (none
        //   below 0.1 pixel, all from 0.5), or the above where that is darker.
        // The first still frame after motion (the nearest texel holds a mean) restarts a dark sample:
        // a still view's history would blend the mean, greyed by the resampling, into an exact 0. So
        // does a lit one where the kernel is under HARD_SHADOW_MEAN_RADIUS (the weight of the mean in
        // the output above is then under 1): the lit pixels beside a sharp edge that the camera moved
        // over hold means greyed from across the edge, which the still view then blended into their
        // exact 1 for frames (cr_fast, a pan that stops: 0.65 where the truth is 1; FLIP 1.09x the
        // input's at 128x128 -> 0.91x).
        if (historyWeight > 0.999)
        {
            SIGMA_TYPE clamped = clamp(history / historyWeight, minimum, maximum);
            float n = min(historyLength / historyWeight, HARD_SHADOW_MEAN_FRAMES);
            SIGMA_TYPE mean = mix(current, clamped, n / (n + 1.0));
            if (_Sigma_MaxComponent(current) >= 0.5)
            {
                bool wasLitThere = (nearestPacked & HISTORY_SAMPLE_BIT) != 0u;
                float darkMean = _Sigma_MaxComponent(mean);
                if (darkMean < HARD_SHADOW_MEAN_DARK && !(wasLitThere && darkMean > HARD_SHADOW_MEAN_LIT_AGAIN) && !isObjectMoving)
                {
                    float blend = HARD_SHADOW_MEAN_BLEND * (isDarkTerminator ? 1.0 : clamp(kernelRadius / HARD_SHADOW_MEAN_RADIUS, 0.0, 1.0));
                    shown = mix(current, mean, blend);
                }
                if (tapLit < HARD_SHADOW_RESAMPLED_LIT)
                    shown = min(shown, mix(current, clamped, HARD_SHADOW_RESAMPLED_BLEND * clamp((kernelRadius - 0.1) * 2.5, 0.0, 1.0)));
            }
            result = mean;
            newLength = n + 1.0;
            isMean = isMovingHard;
            if (!isMovingHard && (_Sigma_MaxComponent(current) < 0.5 || kernelRadius < HARD_SHADOW_MEAN_RADIUS))
            {
                result = current;
                newLength = 1.0;
            }
        }
    }
    else if (historyWeight > 1e-3)
    {
        history /= historyWeight;
        historyLength /= historyWeight;

        // With the whole bilinear footprint valid, resample with Catmull-Rom (12 taps, corners
        // dropped) instead: repeated bilinear resampling under camera motion blurs the history a
        // little more every frame, which shows on sharp shadow edges.
        if (historyWeight > 0.999 && !isHardShadow)
            CatmullRomHistory(origin, f, expectedViewZ, tolerance, history);

        // Soft shadows: mean +- sigma of the blurred frame. Hard shadows: the 3x3 range of the
        // (exact away from edges) input, so a shadow that moved leaves nothing outside the pixel
        // ring along its new edge, where a 5x5 box spanning both sides would keep the old one.
        SIGMA_TYPE clamped = isHardShadow ? clamp(history, minimum, maximum)
                                          : clamp(history, m1 - SIGMA_SCALE * sigma, m1 + SIGMA_SCALE * sigma);
        float antilag = 1.0 - clamp(_Sigma_MaxComponent(abs(clamped - history)) * ANTILAG_SCALE, 0.0, 1.0);
        // A hard shadow that arrives (an exact dark sample under bright history) restarts the
        // history: brightness left in the dark is the costly error. One that leaves is only lagged.
        if (isHardShadow && _Sigma_MaxComponent(history - current) > HARD_SHADOW_ARRIVAL)
            antilag = 0.0;
        // One that leaves (lit under dark history) restarts it too where at least three of its eight
        // neighbours (on a surface) are lit under dark history as well, or where it was lit the frame
        // before too and so are two neighbours now, or one twice as well. A shadow edge that moved
        // without motion vectors (a turning light, moving stripes, a light switched on) turns a row
        // of pixels at once; a still penumbra's noise rarely gives three such pixels side by side.
        // The restart spreads along the departed edge: a pixel lit for the second frame in a row
        // under history below 1 - HARD_SHADOW_ARRIVAL (one that the rows missed and the blend only
        // partly brightened) restarts next to a marked one of the previous frame, and is marked
        // itself; a row restart marks the pixel only where it was lit twice in a row (still
        // penumbrae rarely start the chain). (The history is not resampled here: the previous
        // frame's pixels are this frame's.)
        if (isHardShadow && historyWeight > 0.999 && _Sigma_MaxComponent(current) >= 0.5)
        {
            ivec2 q = origin + ivec2(greaterThanEqual(f, vec2(0.5)));
            uint packedQ = nearestPacked;
            int level = DepartureLevel(q, current, packedQ);
            bool wasLit = (packedQ & HISTORY_SAMPLE_BIT) != 0u;
            bool mayFollow = wasLit && _Sigma_MaxComponent(current - history) > 1.0 - HARD_SHADOW_ARRIVAL;
            if (level > 0 || mayFollow)
            {
                int departed = level - 1;
                int departedTwice = 0;
                bool isNextToDeparted = false;
                for (int j = -1; j <= 1; j++)
                {
                    for (int i = -1; i <= 1; i++)
                    {
                        ivec2 n = q + ivec2(i, j);
                        if ((i == 0 && j == 0) || s_ViewZ[c.y + j][c.x + i] == 0.0 || any(lessThan(n, ivec2(0))) ||
                            any(greaterThanEqual(uvec2(n), gResourceSize)))
                            continue;
                        uint packed = texelFetch(usampler2D(gPrev_ViewZHistoryLength, gNearestClamp), n, 0).x;
                        int l = DepartureLevel(n, s_Signal[c.y + j][c.x + i], packed);
                        departed += l > 0 ? 1 : 0;
                        departedTwice += l > 1 ? 1 : 0;
                        isNextToDeparted = isNextToDeparted || (packed & HISTORY_DEPARTED_BIT) != 0u;
                    }
                }
                // In a tile whose light was switched on, one departed neighbour is enough where the
                // shadow's edge is sharp (a kernel under HARD_SHADOW_RESTART_RADIUS): the off-state's
                // dark history says nothing of the pixel, and the lit tip of a shadow's corner has
                // fewer than three lit neighbours (tl_3hard: a pixel whose truth is 1 output 1/6 at
                // every switch-on). Wider penumbrae keep the three: a lit sample there is more often
                // a mostly dark pixel's draw (tl_5nosun: truth 0.09 at a kernel of 0.96 pixel; see the
                // restarted length below for the figures). So does a lit sample with fewer than two lit
                // neighbours (toggling_light 128x128: draws of truth 0.09-0.25 restarted at 1; relMSE
                // ratio 4.06 -> 3.93 without this), and a moving tile, whose departures are a shadow
                // leaving rather than a light switched on (fast_occluder 128x128: the restarted draws'
                // arrivals kept the tile moving; FLIP 0.746x -> 0.748x the input's without this).
                bool isSwitchedOnEdge = isSwitchedOnTile && !isMovingTile && kernelRadius < HARD_SHADOW_RESTART_RADIUS && LitNeighbourNum(c) >= 2;
                bool isRow = level > 0 && (departed >= 3 || (level == 2 && departedTwice > 0) || (isSwitchedOnEdge && departed >= 1));
                isDeparted = (isRow && level == 2) || (mayFollow && isNextToDeparted);
                if (isRow || isDeparted)
                    antilag = 0.0;
            }
            // A pixel lit for the third frame in a row under history below 1 - HARD_SHADOW_LIT_RUN in a
            // stirred tile: a shadow that left it (a thin shadow moving by its width in a frame leaves
            // pixels whose history the rules above did not restart, and that the blend brightens by
            // a sixth a frame); a still penumbra's noise rarely gives three lit samples in a row
            // where the history is that dark, and its tiles are rarely stirred.
            if (isStirredTile && wasLit && (packedQ & HISTORY_LIT_TWICE_BIT) != 0u && _Sigma_MaxComponent(current - history) > HARD_SHADOW_LIT_RUN)
                antilag = 0.0;
        }
        historyLength = min(historyLength * antilag, gMaxStabilizedFrameNum);
        // While the light moves, a lit hard-shadow sample under dark history (below 1 -
        // HARD_SHADOW_ARRIVAL) next to a lit neighbour is output as it is: the shadow left the pixel.
        // The motion estimate below cannot say so where the dark neighbours' penumbra estimate is 0
        // (it prefers the smaller penumbrae; a shadow near its occluder's contact): there it read
        // "not carried" and the history kept the pixel at 1/6 for frames (moving_light 64x64, truth 1).
        if (isHardShadow && isLightMoving && _Sigma_MaxComponent(current) >= 0.5 && _Sigma_MaxComponent(current - history) > HARD_SHADOW_ARRIVAL)
            isMotionPassed = LitNeighbourNum(c) >= 1;
        // A hard shadow that the light's move, or its occluder's, carried (ShadowMotion.glsl) keeps no
        // more frames than hold NRD_SHADOW_MOTION_HISTORY_PIXELS of its motion: older ones are the
        // shadow where it was.
        float motion = max(shadowMotion, isWideAround ? 0.0 : occluderMotion);
        if (isHardShadow && motion > 0.0)
        {
            float keep = _NRD_ShadowMotion_KeptFrames(motion);
            if (keep < 1.0)
                isMotionPassed = true;
            else
                historyLength = min(historyLength, keep);
        }
        isPassed = isPassed || isMotionPassed;

        // A soft shadow that a moving occluder carried (OCCLUDER_SOFT_RADII): its history is where the
        // surface was, so it keeps no more frames than hold that fraction of its widest penumbra radius
        // of the motion.
        if (!isHardShadow && softMotion > 0.0)
            historyLength = min(historyLength, OCCLUDER_SOFT_RADII * softWidest / softMotion);
        // So does a hard shadow whose 3x3 holds penumbrae of NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA to
        // NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA (too wide for the hard shadows' rule above) with none
        // wider around: their widest radius, and the fastest occluder of the 5x5 (mesh_thin's legs at
        // 128x128 and 192x144, 0.5-0.6 pixel soft, trailed them for the five frames of the history:
        // FLIP 1.004x and 1.020x the input's).
        if (isHardShadow && isWideAround && !isSoftAround && occluderMotion > 0.0)
            historyLength = min(historyLength, OCCLUDER_SOFT_RADII * nearWidest / occluderMotion);
        // (At least one fp16 step: a pixel whose samples stay the same reaches them exactly.)
        passHistory = clamped;
        passLength = historyLength;
        result = _NRD_Fp16Converge(mix(current, clamped, historyLength / (historyLength + 1.0)), clamped, current);
        newLength = min(historyLength + 1.0, gMaxStabilizedFrameNum);
    }

    // A hard-shadow pixel whose history restarted this frame (an arrival, a departure row, a light
    // switched on or off) where the penumbra estimate gives a kernel of at least
    // HARD_SHADOW_RESTART_RADIUS and the 3x3 holds lit and shadowed samples starts from
    // HARD_SHADOW_RESTART_BLEND of the way to the 3x3 mean of the blurred signal: its sample is one
    // 0/1 draw of a penumbra about a pixel wide, which the blurs (a kernel under a pixel) copied. The
    // history goes on from there. (Where the 3x3 agrees, the sample is exact: kept.)
    // In a tile whose hard shadows depart (HARD_SHADOW_DEPARTING_TILE: a light switched on, a shadow
    // moving off), a shadowed sample of such a penumbra under dark history (below 1 -
    // HARD_SHADOW_ARRIVAL) that did not restart is the dark draw of the same penumbra that its lit
    // neighbours restarted from: it takes HARD_SHADOW_FOLLOWER_BLEND of the 3x3 mean, its history
    // going on as it was (a shadow that stays costs a hundred times more when lit).
    bool isRestarted = newLength < 1.5;
    bool isFollower = isDepartingTile && !isRestarted && _Sigma_MaxComponent(current) < 0.5 &&
                      _Sigma_MaxComponent(history) < 1.0 - HARD_SHADOW_ARRIVAL;
    if (isHardShadow && !isResampledHard && historyWeight > 0.999 && kernelRadius >= HARD_SHADOW_RESTART_RADIUS &&
        (isRestarted || isFollower) && !isPassed && _Sigma_MaxComponent(maximum - minimum) >= 0.5)
        result = mix(result, nearMean, isRestarted ? HARD_SHADOW_RESTART_BLEND : HARD_SHADOW_FOLLOWER_BLEND);
    // Such a shadowed sample on a sharp edge (a kernel under HARD_SHADOW_RESTART_RADIUS: the 3x3 holds
    // both, the pixel straddles the edge) in a tile whose light was switched on restarts its history's
    // length: the history is the off state's exact 0, which the full length kept for frames, so that
    // the pixel's lit draws of the next frames counted for a sixth each (tl_3hard: an edge pixel whose
    // truth is 0.78 output 0.17 two frames after the switch; FLIP 1.13x the input's). Its samples
    // since the switch average instead. Wider penumbrae keep the length: the pixel is more often a
    // mostly dark one, whose lit draw a young history would take at half. (Both switch-on rules at
    // 64x64: tl_3hard FLIP 1.130x -> 1.002x the input's, relMSE ratio 2.25 -> 2.07; tl_2 and tl_5nosun
    // relMSE ratio 1.86 -> 1.87 and 2.55 -> 2.56, FLIP 0.98x -> 0.93x and 0.89x -> 0.82x; without the
    // radius tests their relMSE ratios fell to 1.73 and 2.32.)
    if (isHardShadow && !isResampledHard && historyWeight > 0.999 && isFollower && isSwitchedOnTile &&
        kernelRadius < HARD_SHADOW_RESTART_RADIUS && !isPassed && _Sigma_MaxComponent(maximum - minimum) >= 0.5)
        newLength = 1.0;
    if (!isResampledHard)
        shown = result;
    // A hard shadow whose sample the light's or its occluder's motion passes (a moving light, a shadow
    // carried more than its history may hold) restarts its history there: the blend of the history it
    // did not show is the shadow where it was, and the first frame that no longer passes the sample
    // showed it (vb_fast: relMSE ratio 0.95, FLIP 1.13x the input's; ml_fasthard FLIP 1.023x). One that
    // a moving tile passes restarts only where its sample contradicts a history of one frame (length
    // below 1.5: an arrival's restart) and at least 3 of its neighbours are lit: a shadow that crossed
    // the pixel in one frame (mo_fasthard: a pixel lit again after one shadowed frame output 0.67 ->
    // 0.92 over eight frames where the truth is 1; FLIP 1.119x -> 1.064x the input's). Elsewhere the
    // moving tile's pass keeps blending: one draw of a penumbra is a poor history (restarting all of
    // them: fast_occluder's relMSE ratio 1.86 -> 1.75 at 64x64, FLIP 0.814x -> 0.859x; 128x128 FLIP
    // 0.746x -> 0.786x). Such a restart is marked (HISTORY_PASSED_BIT) for the moving-tile test.
    bool isPassedRestart = false;
    if (isPassed && !isResampledHard)
    {
        bool isCrossed = passLength < 1.5 && LitNeighbourNum(c) >= 3 && _Sigma_MaxComponent(abs(current - passHistory)) > HARD_SHADOW_ARRIVAL;
        if (isMotionPassed || isCrossed)
        {
            result = current;
            newLength = 1.0;
            isPassedRestart = !isMotionPassed;
        }
    }
    WriteResult(pixel, _Sigma_Signal01(shown), _Sigma_Signal01(result), viewZ, newLength, current, isDeparted, isPassed,
                isHardShadow && isMovingTile, wasLit, isMean, isPassedRestart);
}
