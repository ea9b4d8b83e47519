#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_control_flow_attributes : require

// RELAX temporal accumulation (document 004, RELAX; SVGF section 4.1):
// - the history is reprojected with surface motion (Reprojection.glsl); each of the 2x2 bilinear
//   taps is kept only where its previous viewZ matches the point's (per-tap disocclusion), the kept
//   weights renormalized; under motion, where the whole footprint holds the same surface, both
//   histories are resampled with Catmull-Rom within the footprint's range (bilinear resampling every
//   frame blurs them); specular also follows the virtual motion of the reflection;
// - slow history: radiance, hit distance and the second luminance moment with alpha
//   1 / (n + 1), n = min(history length, gMaxAccumulatedFrameNum); fast history: radiance with
//   n = min(history length, gMaxFastAccumulatedFrameNum); under motion: the slow n at most
//   gMaxAccumulatedFrameNum / (1 + RELAX_MOTION_SHORTENING * motion in pixels), no fewer than the fast n;
// - the fast history is clamped to this frame's 3x3 input neighbourhood before it is blended;
// - diffuse: both histories' 5x5 means are kept near this frame's input mean (mean clamp); with a
//   confidence input, the nearer the lower the confidence (specular: only where the confidence cut
//   a long history);
// - diffuse: a sample far from the fast history (RELAX_SAMPLE_TEST_SIGMA), with a neighbour on the
//   same surface that departs from its own fast history the same way, shortens both histories;
// - diffuse change test: where this frame's samples depart from their fast histories the way the
//   previous frame's did (the 5x5 mean of the product of the two frames' residuals), the lighting
//   change record (Shaders/Include/LightingChange.glsl) rises; while it says the lighting moves, both
//   histories are kept to RELAX_MOVING_SLOW_FRAMES / RELAX_MOVING_FAST_FRAMES;
// - history that is not finite restarts;
// - anti-lag (optional): a 5x5 box mean of this frame's input luminance far from the same box of the
//   previous fast history (beyond gAntilagSigma standard deviations of the difference) shortens both
//   histories;
// - specular: the history of glossy surfaces is shortened by the parallax between the surface and
//   virtual reprojections, n <= max / (1 + parallax in pixels * (1 - roughness)^2);
// - optional confidence input: the history length is multiplied by it, to no less than
//   NRD_CONFIDENCE_MIN_HISTORY frames (what it takes is kept as a debt that keeps the history fix away),
//   and the mean clamp moves the frames kept to this frame's lighting; specular below a confidence of
//   RELAX_SPECULAR_CONFIDENCE_CLAMP_KNEE: the slow history is kept under the top of this frame's 3x3 box;
// - checkerboard: pixels not traced this frame take the mean of their traced 4-neighbours on the
//   same surface when they have no history, else keep the history unchanged.
#include "Bindings.glsl"
#include "Relax_Constants.h"
#include "Relax_TemporalAccumulation.resources.h"
#include "CommonFrame.glsl"
#include "Relax_Common.glsl"
#include "Reprojection.glsl"

// Half-width of the fast history's clamping box, in standard deviations of this frame's 3x3 input.
// Specular is heavy-tailed: a 3x3 box of its samples is narrow and low more often than wide and high,
// and a tight clamp darkens the history; 4 still removes absurd history within a frame.
#if RELAX_SPECULAR
#define RELAX_FAST_CLAMP_SIGMA 4.0
#else
#define RELAX_FAST_CLAMP_SIGMA 2.0
#endif

// Diffuse: local means of a history and of the input further apart than RELAX_MEAN_CLAMP_TRIGGER_SIGMA
// standard deviations of their difference are brought to RELAX_MEAN_CLAMP_SIGMA of them (mean clamp).
// A trigger at the target itself fires on a third of the pixels of a still view (noise of this
// frame's 5x5 mean) and each shift writes that noise into the history as a 5x5 blotch the a-trous
// filter cannot remove (thin_geometry at 128x128 without the a-trous filter: relMSE 0.0053 with the
// clamp at 1 sigma, 0.0035 without it).
#define RELAX_MEAN_CLAMP_SIGMA 1.0
#define RELAX_MEAN_CLAMP_TRIGGER_SIGMA 1.5

// Diffuse sample test (below): a sample this many standard deviations from the fast history, plus
// this part of its luminance (at 2% the test fired where the temporal variance is near 0, on the
// sky's ground and on thin features at 64x64: lavapipe, sky relMSE 0.00052 -> 0.00071).
#define RELAX_SAMPLE_TEST_SIGMA 2.0
#define RELAX_SAMPLE_TEST_FLOOR 0.1
// With a confidence input, a sample test's shortening stops at the frames the confidence kept unless
// the sample departs from the fast history by more than this many times the test's threshold (a
// shadow edge passing over the pixel: followed at once).
#define RELAX_SAMPLE_TEST_DECISIVE 3.0

// Under motion the slow history is kept to gMaxAccumulatedFrameNum / (1 + this * motion in pixels)
// frames, no fewer than the fast history's. Each frame of motion resamples the history, and what it
// holds beyond the fast history's frames is mostly the blur of earlier resamplings (H100, 128x128, 30
// frames under motion against this: diffuse fast_orbit relMSE 0.0113 -> 0.0094, mesh_engine 0.0639 ->
// 0.0563; specular fast_orbit 0.0805 -> 0.0605, camera_rotation 0.0381 -> 0.0277; 256x256 specular
// mesh_thin 0.0804 -> 0.0650; a still camera is not affected).
#define RELAX_MOTION_SHORTENING 20.0

// RELAX_DIFFUSE_CONFIDENCE_MIN_HISTORY: Relax_Common.glsl.

// Specular with a confidence input: below this confidence the slow history is kept under the top of
// this frame's 3x3 box (below), at RELAX_FAST_CLAMP_SIGMA * (c / knee) standard deviations, no fewer
// than RELAX_SPECULAR_CONFIDENCE_CLAMP_MIN_SIGMA.
#define RELAX_SPECULAR_CONFIDENCE_CLAMP_KNEE 0.5
#define RELAX_SPECULAR_CONFIDENCE_CLAMP_MIN_SIGMA 2.0

// Diffuse change test (below): lighting that moves over a still surface without motion vectors, in
// stripes narrower than any clamping box (venetian_blinds: lines of sunlight one pixel wide crossing
// a floor, each pixel lit for a frame or two every dozen), leaves every history test but a lucky one
// below the noise of a single frame. What does show is that the departures persist: where a line
// of light arrives or leaves, the samples of this frame and of the last both lie above (or below)
// their fast histories, over many pixels. The test takes each tap's residual z = (sample - fast
// history) / sigma (sigma from the temporal variance of one sample, RELAX_RESIDUAL_NOISE, plus
// RELAX_RESIDUAL_FLOOR of the luminance) and the same tap's residual of the previous frame (the
// record's value), and fires where the mean of their products over the 5x5 taps on the same surface
// (divided by at least RELAX_CHANGE_MIN_TAPS) exceeds RELAX_CHANGE_THRESHOLD and the pixel's own
// residual is at least RELAX_CHANGE_MIN_RESIDUAL, or, where the record already says the lighting
// moves, half the threshold (it keeps firing while the lines move on). The noise of still views
// is uncorrelated from frame to frame (mean product 0). While the record says the lighting moves,
// the histories keep RELAX_MOVING_SLOW_FRAMES / RELAX_MOVING_FAST_FRAMES frames (2 + 1 frames: no
// history fix) and the variance estimation gives the a-trous filter a quarter of the variance
// (Relax_SpatialVariance.comp), so that it keeps lines that a short history still holds.
#define RELAX_RESIDUAL_NOISE 1.11
#define RELAX_RESIDUAL_FLOOR 0.05
#define RELAX_CHANGE_MIN_TAPS 12.0
#define RELAX_CHANGE_THRESHOLD 0.25
#define RELAX_CHANGE_MIN_RESIDUAL 0.5
#define RELAX_MOVING_SLOW_FRAMES 2.0
#define RELAX_MOVING_FAST_FRAMES 1.0

bool IsTraced(ivec2 p)
{
    return gCheckerboard == 0u || ((uint(p.x + p.y) + gFrameIndex + gCheckerboard) & 1u) == 0u;
}

// Whether the previous texel 'qPrev' (inside the image) holds a surface at the expected previous
// depth 'zExpected' (5%: the neighbourhoods' taps); sky was stored as 0. Elsewhere the history
// texels belong to another surface or to none (undefined).
bool IsPrevSameSurface(ivec2 qPrev, float zExpected)
{
    float zPrev = texelFetch(gPrev_ViewZ, qPrev, 0).x;
    return zPrev > 0.0 && abs(zPrev - zExpected) <= 0.05 * zExpected;
}

// Catmull-Rom history within the range of the bilinear footprint's 2x2 texels (no ringing), over
// the outer taps in 'outerValid'.
vec4 _Relax_CatmullRomWithinFootprint(texture2D history, NrdFootprint footprint, ivec2 size, uint outerValid)
{
    vec4 lo = vec4(NRD_FP16_MAX), hi = vec4(0.0);
    for (int k = 0; k < 4; k++)
    {
        vec4 v = _NRD_Sanitize(texelFetch(history, footprint.origin + ivec2(k & 1, k >> 1), 0), 0.0);
        lo = min(lo, v);
        hi = max(hi, v);
    }
    return clamp(_NRD_CatmullRomHistory(history, footprint, size, outerValid), lo, hi);
}

// The fast history clamped per channel to mean +- RELAX_FAST_CLAMP_SIGMA standard deviations of 'count'
// samples with sums 'm1' and squares 'm2'; its second moment bounded by the same box.
vec4 _Relax_ClampFast(vec4 fast, vec3 m1, vec3 m2, float count)
{
    if (count <= 0.0)
        return fast;
    m1 /= count;
    vec3 sigma = sqrt(max(m2 / count - m1 * m1, vec3(0.0)));
    vec3 lo = max(m1 - RELAX_FAST_CLAMP_SIGMA * sigma, vec3(0.0)), hi = m1 + RELAX_FAST_CLAMP_SIGMA * sigma;
    fast.rgb = clamp(fast.rgb, lo, hi);
    float lumaHi = _NRD_Luminance(hi), lumaSigma = _NRD_Luminance(sigma);
    fast.w = min(fast.w, sqrt(lumaHi * lumaHi + lumaSigma * lumaSigma));
    return fast;
}

// Bilinear history at 'uvPrev' over the taps that hold the same surface, renormalized; 'footprint'
// is the kept part of the bilinear weights (0: disoccluded), 'historyLength' and 'debt' (the
// confidence debt) in frames, 'record' the lighting change record of the tap of the largest weight.
void Reproject(vec2 uvPrev, float zExpected, float tolerance, out vec4 slow, out vec4 fast, out float historyLength,
               out float debt, out uint record, out float footprint)
{
    ivec2 size = ivec2(gResourceSize);
    NrdFootprint f = _NRD_Footprint(uvPrev, vec2(size));
    vec4 prevViewZ = _NRD_GatherFootprint(gPrev_ViewZ, f.origin, size);
    // Sky was stored as 0: never a match.
    prevViewZ = mix(prevViewZ, vec4(-1e30), lessThanEqual(prevViewZ, vec4(0.0)));
    NrdReprojection r = _NRD_Reprojection(uvPrev, size, prevViewZ, zExpected, tolerance);
    // A reprojection onto pixel centres (a still camera) must not blur the history through
    // rounding: fractions within 1e-3 of a texel snap to it.
    vec2 snapped = mix(r.footprint.f, round(r.footprint.f), lessThan(abs(r.footprint.f - round(r.footprint.f)), vec2(1e-3)));
    vec4 validity = _NRD_TapValidity(r.footprint.origin, size, prevViewZ, zExpected, tolerance);
    r.weights = _NRD_BilinearWeights(snapped) * validity;
    r.footprintWeight = dot(r.weights, vec4(1.0));
    footprint = gResetHistory != 0u || !(r.footprintWeight > 1e-4) ? 0.0 : r.footprintWeight;
    slow = footprint > 0.0 ? _NRD_BilinearHistory(gPrev_Slow, r) : vec4(0.0);
    fast = footprint > 0.0 ? _NRD_BilinearHistory(gPrev_Fast, r) : vec4(0.0);
    // Under motion both histories are resampled with Catmull-Rom where the whole bilinear footprint
    // holds the same surface: bilinear resampling every frame blurs them away from the truth's
    // detail. Kept within the footprint's range (Catmull-Rom rings).
    if (footprint > 0.0 && all(greaterThan(validity, vec4(0.5))) && any(notEqual(snapped, round(snapped))))
    {
        NrdFootprint crFootprint = r.footprint;
        crFootprint.f = snapped;
        uint outerValid = _NRD_CatmullRomOuterTaps(gPrev_ViewZ, r.footprint, size, zExpected, tolerance);
        slow.rgb = _Relax_CatmullRomWithinFootprint(gPrev_Slow, crFootprint, size, outerValid).rgb;
        fast.rgb = _Relax_CatmullRomWithinFootprint(gPrev_Fast, crFootprint, size, outerValid).rgb;
    }
    // Length and debt unpacked per tap, then interpolated; the record (a count) from one tap.
    vec2 lengthDebt = vec2(0.0);
    record = 0u;
    float recordWeight = 0.0;
    if (footprint > 0.0)
    {
        for (int k = 0; k < 4; k++)
        {
            if (r.weights[k] <= 0.0)
                continue;
            vec2 v = texelFetch(gPrev_Length, r.footprint.origin + ivec2(k & 1, k >> 1), 0).xy;
            lengthDebt += Relax_UnpackLengthAndDebt(v.x) * r.weights[k];
            if (r.weights[k] > recordWeight)
            {
                recordWeight = r.weights[k];
                record = _NRD_LightingChange_UnpackRecord(v.y);
            }
        }
        lengthDebt /= r.footprintWeight;
    }
    historyLength = lengthDebt.x;
    debt = clamp(lengthDebt.y, 0.0, gHistoryFixFrameNum);
    // History that is not finite (or not a radiance) restarts.
    if (!_NRD_IsFinite(slow) || !_NRD_IsFinite(fast) || !_NRD_IsFinite(historyLength) || any(lessThan(slow, vec4(0.0))) ||
        any(lessThan(fast, vec4(0.0))))
    {
        footprint = 0.0;
        slow = vec4(0.0);
        fast = vec4(0.0);
        historyLength = 0.0;
        debt = 0.0;
        record = 0u;
    }
    historyLength = clamp(historyLength, 0.0, RELAX_HISTORY_LENGTH_LIMIT);
}

void main()
{
    if (Relax_IsTileSkipped(gIn_Tiles))
        return;
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    RelaxSurface s = Relax_LoadSurface(gIn_NormalRoughness, gIn_ViewZ, pixel);
    if (s.z == 0.0)
        return; // Sky or outside: not denoised, not written.

    // This frame's sample (checkerboard: reconstructed where not traced).
    bool isTraced = IsTraced(pixel);
    vec4 signal = vec4(0.0);
    bool hasSample = isTraced;
    if (isTraced)
    {
        vec4 raw = texelFetch(gIn_Signal, pixel, 0);
        hasSample = Relax_IsSample(raw);
        signal = hasSample ? Relax_SanitizeSignal(raw) : vec4(0.0);
    }
    else
    {
        float weightSum = 0.0;
        const ivec2 kCross[4] = ivec2[4](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
        [[unroll]] for (int i = 0; i < 4; i++)
        {
            ivec2 q = pixel + kCross[i];
            RelaxSurface n = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, q);
            vec4 raw = n.z == 0.0 ? vec4(0.0) : texelFetch(gIn_Signal, q, 0);
            float w = n.z == 0.0 || !Relax_IsSample(raw) ? 0.0 : Relax_PlaneWeight(s, n.X, 0.05);
            signal += w * (w > 0.0 ? Relax_SanitizeSignal(raw) : vec4(0.0));
            weightSum += w;
        }
        hasSample = weightSum > 0.0;
        signal = hasSample ? signal / weightSum : vec4(0.0);
    }

    // Reprojection with per-tap disocclusion (Shaders/Include/Reprojection.glsl).
    vec2 uv = _NRD_PixelUv(pixel);
    vec3 worldPos = _NRD_WorldPosition(uv, s.z);
    vec3 worldPosPrev;
    vec2 uvPrev = _NRD_PreviousUv(uv, worldPos, texelFetch(gIn_MV, pixel, 0).xyz, worldPosPrev);
    float zExpected = _NRD_PreviousViewZ(worldPosPrev);
    float NoV = abs(dot(s.N, normalize(s.X)));
    float tolerance = _NRD_DisocclusionTolerance(s.z, zExpected, NoV, gDisocclusionThreshold, gProjectY);
    ivec2 size = ivec2(gResourceSize);

    vec4 prevSlow, prevFast;
    float prevLength, debt, footprint;
    uint record;
    Reproject(uvPrev, zExpected, tolerance, prevSlow, prevFast, prevLength, debt, record, footprint);
#if RELAX_SPECULAR
    // Virtual motion: reflections move with the reflected point's image, the more so the glossier
    // the lobe. The virtual history is taken where it holds the same surface, blended in by the
    // lobe's dominant-direction factor; their parallax shortens the glossy history.
    float hitDist = _NRD_GetHitDist(hasSample ? signal.w : 1.0, s.z, gHitDistParams, s.roughness);
    vec2 uvPrevVirtual = _NRD_VirtualPreviousUv(worldPos, worldPosPrev - worldPos, _NRD_CameraPosition(), hitDist,
                                                s.roughness, gWorldToClipPrev);
    vec4 virtualSlow, virtualFast;
    float virtualLength, virtualDebt, virtualFootprint;
    uint virtualRecord;
    Reproject(uvPrevVirtual, zExpected, tolerance, virtualSlow, virtualFast, virtualLength, virtualDebt, virtualRecord,
              virtualFootprint);
    float virtualAmount = virtualFootprint > 0.5 ? _NRD_SpecularDominantFactor(s.roughness) : 0.0;
    if (footprint <= 1e-4)
        virtualAmount = virtualFootprint > 1e-4 ? 1.0 : 0.0;
    prevSlow = mix(prevSlow, virtualSlow, virtualAmount);
    prevFast = mix(prevFast, virtualFast, virtualAmount);
    prevLength = mix(prevLength, virtualLength, virtualAmount);
    debt = mix(debt, virtualDebt, virtualAmount);
    footprint = max(footprint, virtualFootprint * virtualAmount);
    float parallax = _NRD_ParallaxInPixels(uvPrev, uvPrevVirtual, vec2(gResourceSize));
#endif
    bool hasHistory = footprint > 1e-4;
    if (!hasHistory)
    {
        prevLength = 0.0;
        debt = 0.0;
        record = 0u;
    }

    // The fast history follows "now": it is clamped per channel to this frame's 3x3 input
    // neighbourhood (traced pixels on the same surface, as the history fix's clamping box; mean +-
    // RELAX_FAST_CLAMP_SIGMA standard deviations), so that a lighting change, or absurd history left
    // by out-of-range input, is gone within a frame; its second moment is bounded by the same box. The slow history follows the fast one (history fix).
    // Diffuse gathers the box's moments in the mean clamp's 5x5 loop below (the same taps).
#if RELAX_CONFIDENCE
    float confidence = clamp(_NRD_Sanitize(texelFetch(gIn_Confidence, pixel, 0).x, 1.0), 0.0, 1.0);
#endif
#if RELAX_SPECULAR
    if (hasHistory && hasSample)
    {
        vec3 m1 = vec3(0.0), m2 = vec3(0.0);
        float count = 0.0;
        [[unroll]] for (int j = -1; j <= 1; j++)
            [[unroll]] for (int i = -1; i <= 1; i++)
            {
                ivec2 q = pixel + ivec2(i, j);
                if (!IsTraced(q))
                    continue;
                RelaxSurface n = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, q);
                if (n.z == 0.0 || Relax_PlaneWeight(s, n.X, 0.05) <= 0.0 || dot(s.Nw, n.Nw) < 0.8)
                    continue;
                vec4 raw = texelFetch(gIn_Signal, q, 0);
                if (!Relax_IsSample(raw))
                    continue;
                vec3 c = Relax_SanitizeSignal(raw).rgb;
                m1 += c;
                m2 += c * c;
                count += 1.0;
            }
#if RELAX_CONFIDENCE
        // Specular with a confidence input below RELAX_SPECULAR_CONFIDENCE_CLAMP_KNEE: the slow history
        // is also kept under the same box's top, narrowed with the confidence to no less than
        // RELAX_SPECULAR_CONFIDENCE_CLAMP_MIN_SIGMA standard deviations (RELAX_FAST_CLAMP_SIGMA *
        // _NRD_ConfidenceNarrowing). The frames the confidence keeps (NRD_CONFIDENCE_MIN_HISTORY) hold
        // a thin highlight that moved away as bright as it was, and the mean clamp's 5x5 taps, which
        // hold the highlight's new place, do not move them (venetian_blinds 256x256: a sun glint one
        // pixel high kept at 19 where the truth is 0.1). Only the top: a floor lifts the history where
        // this frame's 3x3 holds a bright sample, and bright samples stay in it for many frames; a top
        // tighter than 2 standard deviations darkens the frames after a lamp goes off (the 3x3 of a
        // heavy-tailed signal is low more often than high). Shaders/Confidence/README.md.
        if (confidence < RELAX_SPECULAR_CONFIDENCE_CLAMP_KNEE && count > 0.0)
        {
            float k = max(RELAX_FAST_CLAMP_SIGMA * _NRD_ConfidenceNarrowing(confidence, RELAX_SPECULAR_CONFIDENCE_CLAMP_KNEE, 1),
                          RELAX_SPECULAR_CONFIDENCE_CLAMP_MIN_SIGMA);
            vec3 mean = m1 / count, sigma = sqrt(max(m2 / count - mean * mean, vec3(0.0)));
            prevSlow.rgb = min(prevSlow.rgb, mean + k * sigma);
        }
#endif
        prevFast = _Relax_ClampFast(prevFast, m1, m2, count);
    }
#endif
    // Confidence debt: the frames of history the confidence took (up to gHistoryFixFrameNum). The
    // history fix runs on the length plus the debt: where the lighting changed on a surface that was
    // in view, this frame's sample and the clamped history are better than the history fix's wide
    // average of neighbours whose histories were cut as well (toggling_light). Carried with the
    // history, lost with it on disocclusion; 0 without the confidence input.
    float lengthBeforeCut = prevLength;
#if RELAX_CONFIDENCE
#if RELAX_SPECULAR
    float kept = _NRD_ConfidenceHistoryLength(prevLength, confidence, NRD_CONFIDENCE_MIN_HISTORY);
#else
    float kept = _NRD_ConfidenceHistoryLength(prevLength, confidence, RELAX_DIFFUSE_CONFIDENCE_MIN_HISTORY);
#endif
    debt = min(debt + prevLength - kept, gHistoryFixFrameNum);
    prevLength = kept;
#else
    debt = 0.0;
#endif

    // Under motion the slow history is kept to RELAX_MOTION_SHORTENING's share, no fewer frames than
    // the fast history's.
    float motion = length((uvPrev - uv) * vec2(gResourceSize));
    float maxSlow = max(gMaxAccumulatedFrameNum / (1.0 + RELAX_MOTION_SHORTENING * motion),
                        min(gMaxFastAccumulatedFrameNum, gMaxAccumulatedFrameNum));
#if RELAX_SPECULAR
    // What the blend of surface and virtual history still misses grows with their parallax.
    float glossiness = (1.0 - s.roughness) * (1.0 - s.roughness);
    maxSlow = min(maxSlow, gMaxAccumulatedFrameNum / (1.0 + parallax * glossiness));
    float maxFast = min(gMaxFastAccumulatedFrameNum, maxSlow);
#else
    float maxFast = gMaxFastAccumulatedFrameNum;
#endif

    // Local means (5x5 taps on the same surface, this frame's input against the same taps of the
    // previous histories around the reprojected point, so that spatial structure cancels):
    // - diffuse mean clamp: a history whose local mean is further from the input's than the noise of
    //   the two means allows (RELAX_MEAN_CLAMP_TRIGGER_SIGMA standard deviations, from the temporal
    //   variance of one sample, plus 1%) is shifted by the excess over RELAX_MEAN_CLAMP_SIGMA of them,
    //   keeping its own detail, so that a lighting
    //   change is followed within frames; the test is on means, with a variance that does not depend
    //   on this frame's samples, so still history is moved up as often as down (no darkening). With a
    //   confidence input the allowed distance is multiplied by _NRD_ConfidenceNarrowing (c / 0.6)^2
    //   below RELAX_DIFFUSE_CONFIDENCE_NARROWING_KNEE (near 0: the means are made equal), so the
    //   frames kept where a lamp changed take this frame's level;
    // - specular has no mean clamp without a confidence input: its heavy tail would spread single
    //   bright samples over the 5x5 history. With one, it is clamped as diffuse (distance times the
    //   confidence) by (1 - confidence)^2 of the excess, only where the confidence cut a history
    //   longer than twice NRD_CONFIDENCE_MIN_HISTORY: there the frames kept hold the old lighting for
    //   many frames (n kept frames are n / (n + k) of the history k frames later: light_switch's lamp).
    //   Each shift carries the noise of this frame's 5x5 mean into the history, so it runs once per
    //   change, not on every frame of a light that moves every frame (moving_light, whose histories
    //   stay near the frames kept);
    // - anti-lag (optional, gAntilagSigma > 0): a mean beyond gAntilagSigma of the same noise
    //   shortens both histories.
#if RELAX_SPECULAR && RELAX_CONFIDENCE
    float clampAmount = lengthBeforeCut > 2.0 * NRD_CONFIDENCE_MIN_HISTORY + 0.5 ? (1.0 - confidence) * (1.0 - confidence) : 0.0;
    float clampScale = confidence;
#elif RELAX_SPECULAR
    float clampAmount = 0.0, clampScale = 1.0;
#elif RELAX_CONFIDENCE
    float clampAmount = 1.0, clampScale = _NRD_ConfidenceNarrowing(confidence, RELAX_DIFFUSE_CONFIDENCE_NARROWING_KNEE, 2);
#else
    float clampAmount = 1.0, clampScale = 1.0;
#endif
    bool meanClamp = clampAmount > 0.0;
    // Diffuse change test: the sum of the taps' residual products, the taps, this pixel's residual.
    float residualProducts = 0.0, residualTaps = 0.0, residual = 0.0;
    if (hasHistory && hasSample && (meanClamp || gAntilagSigma > 0.0))
    {
        ivec2 prevCenter = ivec2(floor(uvPrev * vec2(gResourceSize)));
        vec3 sumIn = vec3(0.0), sumFast = vec3(0.0), sumSlow = vec3(0.0);
        float sumVariance = 0.0, sumSq = 0.0, count = 0.0;
#if !RELAX_SPECULAR
        vec3 m1 = vec3(0.0), m2 = vec3(0.0);
        float count3 = 0.0;
#endif
        for (int dy = -2; dy <= 2; dy++)
            for (int dx = -2; dx <= 2; dx++)
            {
                ivec2 q = pixel + ivec2(dx, dy), qPrev = prevCenter + ivec2(dx, dy);
                if (!Relax_IsInImage(q) || !IsTraced(q))
                    continue;
                // Same surface now (as the fast history's clamping box) and before (viewZ).
                RelaxSurface n = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, q);
                if (n.z == 0.0 || Relax_PlaneWeight(s, n.X, 0.05) <= 0.0 || dot(s.Nw, n.Nw) < 0.8)
                    continue;
                vec4 raw = texelFetch(gIn_Signal, q, 0);
                if (!Relax_IsSample(raw))
                    continue;
                vec3 c = Relax_SanitizeSignal(raw).rgb;
#if !RELAX_SPECULAR
                if (abs(dx) <= 1 && abs(dy) <= 1)
                {
                    m1 += c;
                    m2 += c * c;
                    count3 += 1.0;
                }
#endif
                if (!Relax_IsInImage(qPrev) || !IsPrevSameSurface(qPrev, zExpected))
                    continue;
                vec4 f = _NRD_Sanitize(texelFetch(gPrev_Fast, qPrev, 0), 0.0);
                vec3 sl = _NRD_Sanitize(texelFetch(gPrev_Slow, qPrev, 0).rgb, 0.0);
                float l = _NRD_Luminance(c), ls = _NRD_Luminance(sl);
                sumIn += c;
                sumFast += f.rgb;
                sumSlow += sl;
                sumSq += l * l;
                sumVariance += max(f.w * f.w - ls * ls, 0.0);
                count += 1.0;
#if !RELAX_SPECULAR
                {
                    float lf = _NRD_Luminance(f.rgb);
                    float sigma = sqrt(max(f.w * f.w - ls * ls, 0.0) * RELAX_RESIDUAL_NOISE) + RELAX_RESIDUAL_FLOOR * max(lf, l) + 1e-6;
                    float z = clamp((l - lf) / sigma, -7.75, 7.75);
                    float zPrev = _NRD_LightingChange_UnpackResidual(_NRD_LightingChange_UnpackValue(texelFetch(gPrev_Length, qPrev, 0).y));
                    residualProducts += z * zPrev;
                    if (dx == 0 && dy == 0)
                        residual = z;
                }
#endif
            }
        residualTaps = count;
#if !RELAX_SPECULAR
        prevFast = _Relax_ClampFast(prevFast, m1, m2, count3);
#endif
        if (count > 0.0)
        {
            vec3 meanIn = sumIn / count, meanFast = sumFast / count, meanSlow = sumSlow / count;
            float lIn = _NRD_Luminance(meanIn), lFast = _NRD_Luminance(meanFast), lSlow = _NRD_Luminance(meanSlow);
            // Variance of one sample: the histories' temporal estimate; this frame's spatial one while
            // the history is too short to have one (a light that turns on had no temporal variance).
            float variance = sumVariance / count;
            if (prevLength < gVarianceHistoryThreshold)
                variance = max(variance, max(sumSq / count - lIn * lIn, 0.0));
            float nFastPrev = min(prevLength, maxFast), nSlowPrev = min(prevLength, maxSlow);
            // An exponential average with alpha 1 / (n + 1) holds 1 / (2n + 1) of one sample's variance.
            float floorSigma = 0.01 * max(lIn, max(lFast, lSlow)) + 1e-6;
            float sigmaFast = sqrt(variance / count * (1.0 + 1.0 / (2.0 * nFastPrev + 1.0))) + floorSigma;
            float sigmaSlow = sqrt(variance / count * (1.0 + 1.0 / (2.0 * nSlowPrev + 1.0))) + floorSigma;
            float slowLuma = _NRD_Luminance(prevSlow.rgb);

            float dFast = abs(lIn - lFast), dSlow = abs(lIn - lSlow);
            if (meanClamp)
            {
                float thresholdFast = RELAX_MEAN_CLAMP_SIGMA * clampScale * sigmaFast;
                float thresholdSlow = RELAX_MEAN_CLAMP_SIGMA * clampScale * sigmaSlow;
                const float kTrigger = RELAX_MEAN_CLAMP_TRIGGER_SIGMA / RELAX_MEAN_CLAMP_SIGMA;
                if (dFast > kTrigger * thresholdFast)
                    prevFast.rgb = max(prevFast.rgb + (meanIn - meanFast) * (clampAmount * (1.0 - thresholdFast / dFast)), vec3(0.0));
                if (dSlow > kTrigger * thresholdSlow)
                    prevSlow.rgb = max(prevSlow.rgb + (meanIn - meanSlow) * (clampAmount * (1.0 - thresholdSlow / dSlow)), vec3(0.0));
                // The second moment moves with the mean (same variance).
                float slowLumaNew = _NRD_Luminance(prevSlow.rgb);
                prevFast.w = sqrt(max(prevFast.w * prevFast.w + slowLumaNew * slowLumaNew - slowLuma * slowLuma, slowLumaNew * slowLumaNew));
            }

            if (gAntilagSigma > 0.0)
            {
                float threshold = gAntilagSigma * sigmaFast;
                float excess = clamp((dFast - threshold) / threshold, 0.0, 1.0);
                prevLength *= 1.0 - excess;
                maxFast *= 1.0 - excess;
            }
        }
    }

#if !RELAX_SPECULAR
    // Diffuse sample test: lighting that changes under a still surface without motion vectors (a
    // shadow edge that moves, stripes of light narrower than the mean clamp's 5x5 taps) shows as a
    // sample further from the fast history than RELAX_SAMPLE_TEST_SIGMA standard deviations (the
    // temporal variance of one sample and the fast history's noise, plus 10%). Where a neighbour on the
    // same surface departs from its own fast history the same way (a single sample's noise seldom
    // has such a neighbour), both histories are shortened to the fast length times the test's
    // threshold over the distance (at least 1 frame), so that they follow the change.
    if (hasHistory && hasSample && prevLength > 1.0)
    {
        float lIn = _NRD_Luminance(signal.rgb), lFast = _NRD_Luminance(prevFast.rgb), lSlow = _NRD_Luminance(prevSlow.rgb);
        float noise = 1.0 + 1.0 / (2.0 * min(prevLength, maxFast) + 1.0);
        float threshold = RELAX_SAMPLE_TEST_SIGMA * sqrt(max(prevFast.w * prevFast.w - lSlow * lSlow, 0.0) * noise) +
                          RELAX_SAMPLE_TEST_FLOOR * max(lFast, lIn) + 1e-6;
        float d = lIn - lFast;
        if (abs(d) > threshold)
        {
            ivec2 prevCenter = ivec2(floor(uvPrev * vec2(gResourceSize)));
            bool confirmed = false;
            for (int k = 0; k < 9 && !confirmed; k++)
            {
                ivec2 o = ivec2(k % 3 - 1, k / 3 - 1);
                ivec2 q = pixel + o, qPrev = prevCenter + o;
                if (k == 4 || !Relax_IsInImage(q) || !Relax_IsInImage(qPrev) || !IsTraced(q) || !IsPrevSameSurface(qPrev, zExpected))
                    continue;
                RelaxSurface nq = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, q);
                if (nq.z == 0.0 || Relax_PlaneWeight(s, nq.X, 0.05) <= 0.0 || dot(s.Nw, nq.Nw) < 0.8)
                    continue;
                vec4 raw = texelFetch(gIn_Signal, q, 0);
                if (!Relax_IsSample(raw))
                    continue;
                float lq = _NRD_Luminance(Relax_SanitizeSignal(raw).rgb);
                vec4 fq = _NRD_Sanitize(texelFetch(gPrev_Fast, qPrev, 0), 0.0);
                float lSlowQ = _NRD_Luminance(_NRD_Sanitize(texelFetch(gPrev_Slow, qPrev, 0).rgb, 0.0));
                float lFastQ = _NRD_Luminance(fq.rgb);
                float thresholdQ = RELAX_SAMPLE_TEST_SIGMA * sqrt(max(fq.w * fq.w - lSlowQ * lSlowQ, 0.0) * noise) +
                                   RELAX_SAMPLE_TEST_FLOOR * max(lFastQ, lq) + 1e-6;
                confirmed = (lq - lFastQ) * sign(d) > thresholdQ;
            }
            if (confirmed)
            {
                float shortened = max(maxFast * threshold / abs(d), 1.0);
#if RELAX_CONFIDENCE
                // Where the confidence cut the history, not below the frames it kept (the mean clamp
                // has moved them to this frame's lighting; a second cut to 1 frame only adds noise:
                // 64x64 relMSE with / without confidence, moving_light 1.008x -> 0.976x,
                // mesh_character 1.013x -> 0.996x, fast_occluder 1.011x -> 1.007x), unless the sample
                // departs decisively (RELAX_SAMPLE_TEST_DECISIVE: moving_occluder 1.045x -> 1.003x,
                // moving_light 0.998x -> 1.004x; Shaders/Confidence/README.md).
                if (confidence < 1.0 && abs(d) < RELAX_SAMPLE_TEST_DECISIVE * threshold)
                    shortened = max(shortened, min(prevLength, NRD_CONFIDENCE_MIN_HISTORY));
#endif
                prevLength = min(prevLength, shortened);
                maxFast = min(maxFast, shortened);
            }
        }
    }

    // Diffuse change test (RELAX_CHANGE_THRESHOLD above): the record rises where this frame's and the
    // previous frame's residuals agree over the neighbourhood; while the lighting moves, the histories
    // stay short.
    bool isMoving = _NRD_LightingChange_IsMoving(record);
    float correlation = residualProducts / max(residualTaps, RELAX_CHANGE_MIN_TAPS);
    bool isChanged = residualTaps > 0.0 && ((correlation > RELAX_CHANGE_THRESHOLD && abs(residual) >= RELAX_CHANGE_MIN_RESIDUAL) ||
                                            (isMoving && correlation > 0.5 * RELAX_CHANGE_THRESHOLD));
    record = _NRD_LightingChange_Update(record, isChanged);
    if (_NRD_LightingChange_IsMoving(record))
    {
        maxSlow = min(maxSlow, RELAX_MOVING_SLOW_FRAMES);
        maxFast = min(maxFast, RELAX_MOVING_FAST_FRAMES);
    }
#endif
    float n = min(prevLength, maxSlow);
    float nFast = min(prevLength, maxFast);
    vec4 slow, fast;
    float historyLength;
    if (!hasSample)
    {
        // Not traced, nothing to reconstruct from: keep the history (or nothing).
        slow = prevSlow;
        fast = prevFast;
        historyLength = prevLength;
    }
    else
    {
        float alpha = hasHistory ? 1.0 / (n + 1.0) : 1.0;
        float alphaFast = hasHistory ? 1.0 / (nFast + 1.0) : 1.0;
        float luminance = _NRD_Luminance(signal.rgb);
        slow.rgb = mix(prevSlow.rgb, signal.rgb, alpha);
        // Hit distances vary more slowly than the radiance they come with; keep them responsive.
        slow.w = mix(prevSlow.w, signal.w, max(alpha, 0.1));
        fast.rgb = mix(prevFast.rgb, signal.rgb, alphaFast);
        fast.w = sqrt(mix(prevFast.w * prevFast.w, luminance * luminance, alpha));
        historyLength = n + 1.0;
    }
    // pixel is inside the image (Relax_LoadSurface returned a surface).
    imageStore(gOut_Slow, pixel, _NRD_ClampToHalf(slow));
    imageStore(gOut_Fast, pixel, _NRD_ClampToHalf(fast));
    // Specular: no change test (record 0, residual 0).
#if RELAX_SPECULAR
    record = 0u;
#endif
    imageStore(gOut_Length, pixel, vec4(Relax_PackLengthAndDebt(historyLength, debt),
                                        _NRD_LightingChange_Pack(record, _NRD_LightingChange_PackResidual(hasSample ? residual : 0.0)), 0.0, 0.0));
}
