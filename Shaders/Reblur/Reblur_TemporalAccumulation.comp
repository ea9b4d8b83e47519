// REBLUR temporal accumulation (document 004, REBLUR: "temporal accumulation" with fast and slow
// history, virtual motion for specular).
//
// Slow history: up to gMaxAccumulatedFrameNum frames (running mean, then exponential). Fast history:
// the luminance accumulated over at most gMaxFastAccumulatedFrameNum frames; where the slow
// luminance leaves the fast one by more than gAntilagSigmaScale of the fast history's expected
// noise, the history length is cut towards the fast length and the slow value is moved onto the
// fast one (anti-lag). Confidence (optional) shortens the history where < 1, to no less than
// REBLUR_DIFFUSE_CONFIDENCE_MIN_HISTORY frames (diffuse) or to its confidence's share (specular;
// what it takes is kept as a debt that narrows the history fix). Specular blends the
// surface-motion and virtual-motion histories (_Reblur_Reproject). Checkerboard: the pixels not
// traced this frame take history only (or, without history, their traced horizontal neighbours).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Reblur_TemporalAccumulation.resources.h"
#include "CommonFrame.glsl"
#include "Reblur_Common.glsl"

// Whether the surface moved on screen by more than REBLUR_PIXEL_ANTILAG_MOTION pixels since the
// previous frame (the self tests under motion).
bool IsMovedOnScreen(NrdFootprint footprint, ivec2 pixel)
{
    vec2 motion = vec2(footprint.origin) + footprint.f - vec2(pixel);
    return dot(motion, motion) > REBLUR_PIXEL_ANTILAG_MOTION * REBLUR_PIXEL_ANTILAG_MOTION;
}

// The history length a history test leaves: 'keep' of it in whole frames, at least one frame.
float CutHistory(float historyLength, float keep)
{
    return max(floor(historyLength * keep), min(historyLength, 1.0));
}

#if !REBLUR_SPECULAR && !REBLUR_OCCLUSION
// One tap of the lighting change test: this frame's pixel q against the previous texel p, both on
// the centre's surface (view depths within the tolerances), p's history at least 2 frames long.
// z.x: q's sample against p's history in p's per-pixel deviation; z.y: p's stored residual.
bool ChangeTestTap(ivec2 q, ivec2 p, float viewZ, float tolerance, float expectedViewZ, float tolerancePrev, out vec2 z)
{
    z = vec2(0.0);
    ivec2 size = ivec2(gResourceSize);
    if (any(lessThan(min(q, p), ivec2(0))) || any(greaterThanEqual(max(q, p), size)) || !_Reblur_IsTraced(q))
        return false;
    vec4 sq = texelFetch(sampler2D(gIn_Signal, gNearestClamp), q, 0);
    float zq = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
    float zp = texelFetch(sampler2D(gPrev_ViewZ, gNearestClamp), p, 0).x;
    if (!_NRD_IsFinite(sq) || !(abs(zq - viewZ) <= tolerance) || !(abs(zp - expectedViewZ) <= tolerancePrev))
        return false;
    vec2 sigmaLength = texelFetch(sampler2D(gPrev_Fast, gNearestClamp), p, 0).xy;
    float n = clamp(_NRD_Sanitize(sigmaLength.y, 0.0), 0.0, NRD_HISTORY_LENGTH_MAX);
    if (n < 2.0)
        return false;
    float mu = _Reblur_Luma(_Reblur_Sanitize(texelFetch(sampler2D(gPrev_History, gNearestClamp), p, 0)));
    float sigmaP = max(_NRD_Sanitize(sigmaLength.x, 0.0), 0.0);
    float variance = sigmaP * sigmaP * (1.0 + 1.0 / n) + 1e-4 * mu * mu + 1e-8;
    z.x = clamp((_Reblur_Luma(_Reblur_Sanitize(sq)) - mu) * inversesqrt(variance), -7.75, 7.75);
    z.y = _NRD_LightingChange_UnpackResidual(_NRD_LightingChange_UnpackValue(texelFetch(sampler2D(gPrev_Debt, gNearestClamp), p, 0).x));
    return true;
}
#endif

void main()
{
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), gResourceSize)) || _Reblur_IsSkyTile(gIn_Tiles, pixel))
        return;
    float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
    if (_NRD_IsSky(viewZ))
        return;

    // Current sample (the pre-pass result when it ran). A non-finite sample carries no information:
    // the pixel is treated as not traced this frame (it keeps its history).
    vec4 raw = texelFetch(sampler2D(gIn_Signal, gNearestClamp), pixel, 0);
#if REBLUR_OCCLUSION
    raw = raw.xxxx;
#endif
    bool isTraced = _Reblur_IsTraced(pixel) && _NRD_IsFinite(raw);
    vec4 current;
    if ((gFlags & REBLUR_FLAG_PREPASS) != 0u)
        current = _Reblur_Sanitize(imageLoad(gInOut_Signal, pixel));
    else if (isTraced)
        current = _Reblur_LoadInput(gIn_Signal, pixel);
    else
    {
        // Untraced checkerboard pixel: its horizontal neighbours were traced.
        ivec2 l = ivec2(max(pixel.x - 1, 0), pixel.y);
        ivec2 r = ivec2(min(pixel.x + 1, int(gResourceSize.x) - 1), pixel.y);
        current = 0.5 * (_Reblur_LoadInput(gIn_Signal, l) + _Reblur_LoadInput(gIn_Signal, r));
    }

    ReblurSurface s = _Reblur_Surface(gIn_NormalRoughness, pixel, viewZ);
    vec3 mv = texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz;
    ReblurReprojection rp = _Reblur_Reproject(gPrev_ViewZ, pixel, s, mv, current.w);

    // Histories along the surface motion (and, specular, the virtual motion).
    vec4 slow = _Reblur_FetchHistory(gPrev_History, rp.surface);
    vec2 fastLength = _NRD_BilinearHistory(gPrev_Fast, rp.surface).xy;
    float debt = _NRD_BilinearHistory(gPrev_Debt, rp.surface).x;
    float stabilized = _Reblur_FetchHistory(gPrev_Stabilized, rp.surface).x;
    float footprint = rp.surface.footprintWeight;
#if REBLUR_SPECULAR
    if (rp.virtualAmount > 0.0)
    {
        vec4 slowV = _Reblur_FetchHistory(gPrev_History, rp.virtual_);
        vec2 fastLengthV = _NRD_BilinearHistory(gPrev_Fast, rp.virtual_).xy;
        float debtV = _NRD_BilinearHistory(gPrev_Debt, rp.virtual_).x;
        float stabilizedV = _Reblur_FetchHistory(gPrev_Stabilized, rp.virtual_).x;
        // How well the virtual history matches: its hit distance should agree with the surface
        // history's on a mirror-like reflection; a mismatch moves the blend back to the surface.
        float a = rp.virtualAmount;
        if (footprint > 0.0)
            a *= clamp(1.0 - abs(slowV.w - slow.w) * 4.0, 0.25, 1.0);
        slow = footprint > 0.0 ? mix(slow, slowV, a) : slowV;
        fastLength = footprint > 0.0 ? mix(fastLength, fastLengthV, a) : fastLengthV;
        debt = footprint > 0.0 ? mix(debt, debtV, a) : debtV;
        stabilized = footprint > 0.0 ? mix(stabilized, stabilizedV, a) : stabilizedV;
        footprint = mix(footprint, rp.virtual_.footprintWeight, a);
    }
#endif
    slow = _Reblur_Sanitize(slow);
    float fast = max(_NRD_Sanitize(fastLength.x, 0.0), 0.0);
    // With a confidence input the history length is not rounded to whole frames: a confidence of
    // 0.9 every frame then keeps 1 / (1 - 0.9) = 10 frames, where rounding (down or to the nearest)
    // kept a short history at its length for any confidence below 1 (0.9: 6 frames; rounded down, 1).
    bool hasConfidence = (gFlags & REBLUR_FLAG_CONFIDENCE) != 0u;
    float historyLength = clamp(_NRD_Sanitize(fastLength.y, 0.0), 0.0, gMaxAccumulatedFrameNum);
    stabilized = max(_NRD_Sanitize(stabilized, 0.0), 0.0);
    // Confidence debt: the frames of history the confidence took (up to gHistoryFixFrameNum). The
    // history fix's stride follows the length plus the debt: where the lighting changed on a surface
    // that was in view, every neighbour's history was cut as well, and the fix's wide grid (stride 4
    // at length 1) only spreads the light of other places (toggling_light, 64x64, sensitivity 2:
    // relMSE 1.57x -> 1.27x the run without confidence); a dense 5x5 average (stride 1) still helps
    // (skipping the fix: 2.25x). Carried along with the history, lost with it on disocclusion; 0
    // without a confidence input. Diffuse radiance keeps none: its debt texel holds the lighting change
    // record (below), and its cut keeps at least REBLUR_DIFFUSE_CONFIDENCE_MIN_HISTORY frames, more than the
    // history fix runs for, so a debt could only widen the fix's stride after a later disocclusion.
#if !REBLUR_SPECULAR && !REBLUR_OCCLUSION
    debt = 0.0;
#else
    debt = hasConfidence ? clamp(_NRD_Sanitize(debt, 0.0) * REBLUR_DEBT_SCALE, 0.0, gHistoryFixFrameNum) : 0.0;
#endif
    // A partly disoccluded footprint counts as a shorter history.
    historyLength *= min(footprint * 1.25, 1.0);
    debt *= min(footprint * 1.25, 1.0);
    historyLength = footprint > 0.01 ? (hasConfidence ? historyLength : floor(historyLength + 0.5)) : 0.0;
    debt = footprint > 0.01 ? debt : 0.0;

    float confidence = 1.0;
    if (hasConfidence)
    {
        confidence = clamp(_NRD_Sanitize(texelFetch(sampler2D(gIn_Confidence, gNearestClamp), pixel, 0).x, 1.0), 0.0, 1.0);
        #if REBLUR_SPECULAR
        // Specular restarts: its fast history follows a light that comes back too slowly for the
        // frames kept to be moved in time (light_switch, 64x64: -9% of the truth's mean on the first
        // lit frame with 4 kept, -2% restarted), and its blur covers the restart's noise (relMSE
        // against the run without confidence, 4 kept -> restarted: toggling_light 0.90x -> 0.83x).
        float kept = historyLength * confidence;
#else
        float kept = _NRD_ConfidenceHistoryLength(historyLength, confidence, REBLUR_DIFFUSE_CONFIDENCE_MIN_HISTORY);
#endif
        debt = min(debt + historyLength - kept, gHistoryFixFrameNum);
        historyLength = kept;
    }

    bool isReference = (gFlags & REBLUR_FLAG_REFERENCE) != 0u;
#if REBLUR_SPECULAR
    // Parallax: at most REBLUR_SPECULAR_PARALLAX_FRACTION of the lobe's half-angle over the view's
    // turn per frame (whole frames: a fraction of a frame of history still mixed the fins' bright
    // reflections into the gaps between them on mesh_engine). A still view keeps its history (also
    // on mirrors, whose lobe is 0); with checkerboard input the pixels not traced this frame keep a
    // frame of history (their alternative is the horizontal neighbours' average).
    if (!isReference && rp.parallax > 0.0)
    {
        float parallaxLimit = REBLUR_SPECULAR_PARALLAX_FRACTION * _Reblur_LobeHalfAngle(s.roughness) / rp.parallax;
        parallaxLimit = max(floor(min(parallaxLimit, NRD_HISTORY_LENGTH_MAX)), gCheckerboard != 0u ? 1.0 : 0.0);
        historyLength = min(historyLength, parallaxLimit);
    }
#endif
    float maxLength = isReference ? NRD_HISTORY_LENGTH_MAX : max(gMaxAccumulatedFrameNum, 1.0);
    float luma = _Reblur_Luma(current);

#if REBLUR_SPECULAR
    const int R = 1;
#else
    const int R = REBLUR_ANTILAG_RADIUS;
#endif
    // Neighbourhood of this frame's input (traced, finite samples, not sky; diffuse: on the same surface).
    float m1 = 0.0, m2 = 0.0, count = 0.0;
    {
        ivec2 maxPixel = ivec2(gResourceSize) - 1;
        float zTolerance = gDisocclusionThreshold * 4.0 * viewZ + 2.0 * viewZ / max(gProjectY, NRD_EPS) * float(R);
        for (int j = -R; j <= R; j++)
        {
            for (int i = -R; i <= R; i++)
            {
                ivec2 q = clamp(pixel + ivec2(i, j), ivec2(0), maxPixel);
                // Non-finite samples carry no information (and must not pull the fast history).
                vec4 sq = texelFetch(sampler2D(gIn_Signal, gNearestClamp), q, 0);
#if REBLUR_OCCLUSION
                sq = sq.xxxx;
#endif
                if (!_Reblur_IsTraced(q) || !_NRD_IsFinite(sq))
                    continue;
                float zq = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
#if REBLUR_SPECULAR
                // The sky's input is whatever the application left there. (Its taps taking this
                // pixel's sample instead, as taps beyond the image's border take the border's:
                // sky 64x64 relMSE +2.5% instead of +0.6%.)
                if (_NRD_IsSky(zq))
                    continue;
#else
                if (!(abs(zq - viewZ) <= zTolerance))
                    continue;
#endif
                float l = _Reblur_Luma(_Reblur_Sanitize(sq));
                m1 += l;
                m2 += l * l;
                count += 1.0;
            }
        }
        m1 /= max(count, 1.0);
    }
    float sigma = sqrt(max(m2 / max(count, 1.0) - m1 * m1, 0.0));
#if REBLUR_SPECULAR
    float fastSample = luma;
#else
    // Diffuse: the anti-lag compares this frame's 5x5 input mean with the same mean of the
    // previous slow history (25 samples: a 20% lighting change stands out of 1-sample noise within
    // a frame, where a per-pixel fast history of single samples could not tell it from noise
    // before the slow history had mostly followed anyway: light_switch, moving_light). The fast
    // channel holds the per-pixel deviation of the samples the slow history accumulated (see the
    // per-pixel test below); a new history starts from this frame's 5x5 deviation.
    float fastSample = sigma;
    bool isPixelCut = false;
#endif

    if (historyLength == 0.0)
    {
        slow = current;
        fast = fastSample;
        stabilized = luma;
    }
#if REBLUR_SPECULAR
    // Checkerboard: the specular fast-history clamp and anti-lag run once per sample, on the frames
    // the pixel is traced (run on the frames between as well, their second clamp and cut of the
    // same history darkened the mean: static 64x64, -5.5% -> -2.6%).
    else if (!isReference && count > 0.0 && isTraced)
#else
    else if (!isReference && count > 0.0)
#endif
    {
        // Without a finite sample around (a frame of NaN input) the fast history and the anti-lag
        // wait for the next frame.
        float slowLuma = _Reblur_Luma(slow);
#if REBLUR_SPECULAR
        // The fast history follows "now": it is clamped to the 3x3 input neighbourhood (mean - 2
        // sigma, mean + 4 sigma), so a lighting change or a burst of bad values leaves it within a
        // few frames. The box is wider above: single samples are skewed (rare bright ones), and a
        // symmetric box cut the fast history's bright tail, so that the anti-lag pulled the slow
        // history below the mean.
        fast = clamp(fast, m1 - 2.0 * sigma, m1 + 4.0 * sigma);
        // Anti-lag: the slow history must agree with the fast one within the expected noise of a
        // mean of n frames (the neighbourhood's deviation as the per-frame scale, widened for
        // heavy-tailed specular). The fast history before this frame's sample decides: a cut that
        // depends on the sample gives the low samples of a skewed distribution (most of them) more
        // weight than the high ones.
        float n = min(historyLength, gMaxFastAccumulatedFrameNum);
        float reference = slowLuma;
        float fastNow = fast;
        // A confidence below 1 narrows the tolerance as for diffuse (the lighting changed: the slow
        // history follows the fast one sooner).
        float noise = (sigma + 0.05 * max(fast, slowLuma) + 1e-4) / sqrt(n + 1.0) * REBLUR_SPECULAR_ANTILAG_NOISE_SCALE *
                      max(confidence, 0.05);
#else
        // The same mean of the previous slow history around the reprojected position (the box of
        // each bilinear tap, weighted bilinearly), over the taps on the same surface.
        float reference = 0.0, referenceWeight = 0.0;
        ivec2 size = ivec2(gResourceSize);
        vec2 f = rp.surface.footprint.f;
        float zTolerance = gDisocclusionThreshold * 4.0 * rp.expectedViewZ + 2.0 * rp.expectedViewZ / max(gProjectY, NRD_EPS) * float(R);
        for (int j = -R; j <= R + 1; j++)
        {
            for (int i = -R; i <= R + 1; i++)
            {
                ivec2 q = rp.surface.footprint.origin + ivec2(i, j);
                if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)))
                    continue;
                float z = texelFetch(sampler2D(gPrev_ViewZ, gNearestClamp), q, 0).x;
                if (!(abs(z - rp.expectedViewZ) <= zTolerance))
                    continue;
                float w = (i == -R ? 1.0 - f.x : (i == R + 1 ? f.x : 1.0)) * (j == -R ? 1.0 - f.y : (j == R + 1 ? f.y : 1.0));
                reference += _Reblur_Luma(_Reblur_Sanitize(texelFetch(sampler2D(gPrev_History, gNearestClamp), q, 0))) * w;
                referenceWeight += w;
            }
        }
        reference = referenceWeight > 0.0 ? reference / referenceWeight : slowLuma;
        // Expected noise of a mean of 'count' samples (this frame's pixel is one of them: its weight
        // in the decision is small).
        float fastNow = m1;
        float noise = (sigma / sqrt(count) + 0.005 * max(m1, reference) + 1e-4) * REBLUR_DIFFUSE_ANTILAG_NOISE_SCALE;

        // Per-pixel test: shadows and stripes narrower than the 5x5 window (venetian_blinds,
        // mesh_thin's legs) move over still surfaces without changing that window's mean. Each 3x3
        // neighbour's sample is compared with its own history (the nearest previous texel, on the
        // same surface) in units of that history's per-pixel deviation (the fast channel, from the
        // samples it accumulated: the stripes themselves are not noise there, as they are in a
        // spatial deviation); squared, capped at REBLUR_PIXEL_ANTILAG_CAP (one outlier of a
        // heavy-tailed sample cannot decide alone) and averaged.
        {
            ivec2 nearest = rp.surface.footprint.origin + ivec2(greaterThanEqual(rp.surface.footprint.f, vec2(0.5)));
            float zTolerance1 = gDisocclusionThreshold * 4.0 * viewZ + 2.0 * viewZ / max(gProjectY, NRD_EPS);
            float zTolerancePrev = gDisocclusionThreshold * 4.0 * rp.expectedViewZ + 2.0 * rp.expectedViewZ / max(gProjectY, NRD_EPS);
            float chi = 0.0, chiCount = 0.0, chiSelf = 0.0;
            bool isSelfBelow = false;
            for (int j = -1; j <= 1; j++)
            {
                for (int i = -1; i <= 1; i++)
                {
                    ivec2 q = pixel + ivec2(i, j);
                    ivec2 p = nearest + ivec2(i, j);
                    if (any(lessThan(min(q, p), ivec2(0))) || any(greaterThanEqual(max(q, p), size)) || !_Reblur_IsTraced(q))
                        continue;
                    vec4 sq = texelFetch(sampler2D(gIn_Signal, gNearestClamp), q, 0);
#if REBLUR_OCCLUSION
                    sq = sq.xxxx;
#endif
                    float zq = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
                    float zp = texelFetch(sampler2D(gPrev_ViewZ, gNearestClamp), p, 0).x;
                    if (!_NRD_IsFinite(sq) || !(abs(zq - viewZ) <= zTolerance1) || !(abs(zp - rp.expectedViewZ) <= zTolerancePrev))
                        continue;
                    vec2 sigmaLength = texelFetch(sampler2D(gPrev_Fast, gNearestClamp), p, 0).xy;
                    float n = clamp(_NRD_Sanitize(sigmaLength.y, 0.0), 0.0, NRD_HISTORY_LENGTH_MAX);
                    if (n < 2.0)
                        continue;
                    float mu = _Reblur_Luma(_Reblur_Sanitize(texelFetch(sampler2D(gPrev_History, gNearestClamp), p, 0)));
                    float sigmaP = max(_NRD_Sanitize(sigmaLength.x, 0.0), 0.0);
                    // A sample against the mean of n: the difference's variance is sigma^2 (1 + 1 / n).
                    float variance = sigmaP * sigmaP * (1.0 + 1.0 / n) + 1e-4 * mu * mu + 1e-8;
                    float d = _Reblur_Luma(_Reblur_Sanitize(sq)) - mu;
                    float z2 = min(d * d / variance, REBLUR_PIXEL_ANTILAG_CAP);
                    if (i == 0 && j == 0)
                    {
                        chiSelf = z2;
                        isSelfBelow = d < 0.0;
                        continue;
                    }
                    chi += z2;
                    chiCount += 1.0;
                }
            }
            // The neighbours decide, the pixel's own sample must disagree too: a rare bright sample
            // then cuts neither its neighbours' histories nor its own (a history cut at a rare
            // sample kept it: sky and roughness_sweep, +15% relMSE when the pixel took part in the
            // mean). Fewer neighbours (checkerboard: the 4 diagonal ones; edges) give a noisier
            // mean and a higher limit (checkerboard static 128x128: +4% relMSE with the limit of 8).
            // The confidence does not narrow this test: it shortened the history already, to no
            // less than REBLUR_DIFFUSE_CONFIDENCE_MIN_HISTORY frames, which a narrower test cut further
            // (toggling_light 64x64 relMSE with confidence 1.02x the run without, 0.98x now).
            float chiLimit = REBLUR_PIXEL_ANTILAG_CHI * (1.0 + 4.0 / max(chiCount, 1.0)) / 1.5;
            float pixelExcess = chiCount >= 2.0 && chiSelf >= REBLUR_PIXEL_ANTILAG_SELF ? chi / (chiCount * chiLimit) - 1.0 : 0.0;
            if (pixelExcess > 0.0)
            {
                // Cut hard (stripes that move a pixel every few frames need a history of a few
                // frames); the slow value is kept: this frame's sample gets the weight of the shorter history.
                float keep = pow(1.0 + pixelExcess, -REBLUR_PIXEL_ANTILAG_POWER);
                historyLength = CutHistory(historyLength, keep);
                isPixelCut = true;
            }
            else if (isSelfBelow && chiSelf >= REBLUR_PIXEL_ANTILAG_SELF)
            {
                // The pixel alone, where it moved (REBLUR_PIXEL_ANTILAG_MOTION): a one-pixel gap whose
                // resampled history holds a neighbouring surface's light.
                if (IsMovedOnScreen(rp.surface.footprint, pixel))
                {
                    historyLength = CutHistory(historyLength, 0.5);
                    isPixelCut = true;
                }
            }
        }
#endif
#if REBLUR_SPECULAR
        // Where the surface moved on screen, a sample below REBLUR_SPECULAR_SELF_FRACTION of its own
        // history halves the history (the diffuse self test under motion, as a ratio: specular has no
        // per-pixel deviation): a history resampled along motion can hold a neighbouring surface's
        // reflection (mesh_thin's moving legs: histories of 3-10 frames at 0.4-1.0 where the truth
        // is 0 and the samples are 0).
        if (IsMovedOnScreen(rp.surface.footprint, pixel) && luma < REBLUR_SPECULAR_SELF_FRACTION * slowLuma)
            historyLength = CutHistory(historyLength, 0.5);
#endif
#if REBLUR_SPECULAR
        float excess = abs(reference - fastNow) / (gAntilagSigmaScale * noise) - 1.0;
#else
        // Diffuse: a confidence below REBLUR_DIFFUSE_CONFIDENCE_NARROWING_KNEE narrows the tolerance of
        // the correction below, not of the history's cut: the cut follows the tolerance without
        // confidence (excessWide). Where only the narrowed tolerance is exceeded the history keeps its
        // length and moves towards the neighbourhood's change with the weight keep (keep^2 where both
        // are): the trailing light still goes (light_switch 5 -> 0 frames, toggling_light 4 -> 2 at
        // 64x64), and the blinds' moving stripes, whose confidence stays a little below 1 frame after
        // frame, no longer lose their histories (venetian_blinds 128x128, relMSE with / without
        // confidence summed over seeds 1-6, NVIDIA H200: 1.029x with the narrowed cut, 0.998x now;
        // Shaders/Confidence/README.md).
        float narrowing = _NRD_ConfidenceNarrowing(confidence, REBLUR_DIFFUSE_CONFIDENCE_NARROWING_KNEE, 1);
        float excessWide = abs(reference - fastNow) / (gAntilagSigmaScale * noise) - 1.0;
        float excess = abs(reference - fastNow) / (gAntilagSigmaScale * noise * narrowing) - 1.0;
#endif
        if (excess > 0.0)
        {
            float keep = 1.0 / (1.0 + excess);
#if REBLUR_SPECULAR
            bool isCut = true;
            float cutKeep = keep;
#else
            bool isCut = excessWide > 0.0;
            float cutKeep = 1.0 / (1.0 + max(excessWide, 0.0));
#endif
            if (isCut)
            {
                historyLength = CutHistory(historyLength, cutKeep);
                historyLength = min(historyLength, max(gMaxFastAccumulatedFrameNum, 1.0));
            }
#if REBLUR_SPECULAR
            slow = _Reblur_WithLuma(slow, mix(fastNow, slowLuma, keep));
#else
            // The neighbourhood's change applies to the pixel's own history as a ratio (lighting
            // scales the radiance; the pixel keeps its detail).
            float target = reference > 1e-4 ? slowLuma * fastNow / reference : slowLuma + fastNow - reference;
            slow = _Reblur_WithLuma(slow, max(mix(target, slowLuma, isCut ? keep * keep : keep), 0.0));
#endif
            // The stabilized luminance follows the same correction: reprojected as it was, it kept
            // the old lighting for as long as the stabilization's own clamp took to let go of it
            // (light_switch diffuse, 64x64: +3.0% of the truth's mean on the frame the lamp goes
            // off, +2.1% with this).
            float movedLuma = _Reblur_Luma(slow);
            stabilized = slowLuma > 1e-6 ? stabilized * (movedLuma / slowLuma) : movedLuma;
#if REBLUR_OCCLUSION
            stabilized = min(stabilized, 1.0);
            slow.w = min(slow.w, 1.0);
#endif
        }
    }

#if !REBLUR_SPECULAR && !REBLUR_OCCLUSION
    // Lighting change test (REBLUR_CHANGE_* in Reblur_Common.glsl; the debt texture holds the record
    // and the residual). Taps as the per-pixel test's: this frame's pixel q against the nearest
    // previous texel p of the same offset, on the same surface both times. With a confidence input it
    // runs as well, after the confidence's cut: the confidence follows the application's lighting
    // changes, its gradients blurred over many pixels, and the test the lines of light narrower than
    // that which move over a still surface (venetian_blinds 64x64, relMSE with / without confidence:
    // 1.35x while the test ran only without, 1.003x now).
    uint record = 0u;
    float residual = 0.0;
    if (!isReference && historyLength > 0.0)
    {
        ivec2 nearest = rp.surface.footprint.origin + ivec2(greaterThanEqual(rp.surface.footprint.f, vec2(0.5)));
        float zTolerance1 = gDisocclusionThreshold * 4.0 * viewZ + 4.0 * viewZ / max(gProjectY, NRD_EPS);
        float zTolerancePrev = gDisocclusionThreshold * 4.0 * rp.expectedViewZ + 4.0 * rp.expectedViewZ / max(gProjectY, NRD_EPS);
        // The record of the nearest texel where it holds the surface, as the taps below (another
        // surface's is not this one's; the sky's texels were never written).
        if (all(greaterThanEqual(nearest, ivec2(0))) && all(lessThan(nearest, ivec2(gResourceSize))) &&
            abs(texelFetch(sampler2D(gPrev_ViewZ, gNearestClamp), nearest, 0).x - rp.expectedViewZ) <= zTolerancePrev)
            record = _NRD_LightingChange_UnpackRecord(texelFetch(sampler2D(gPrev_Debt, gNearestClamp), nearest, 0).x);
        // The pixel's own tap first: a change needs its |z| at least CHANGE_MIN_RESIDUAL unless the
        // lighting already moves, so most pixels skip the other 24 taps (the same result).
        vec2 zc;
        bool isCenter = ChangeTestTap(pixel, nearest, viewZ, zTolerance1, rp.expectedViewZ, zTolerancePrev, zc);
        residual = isCenter ? zc.x : 0.0;
        bool isMoving = _NRD_LightingChange_IsMoving(record);
        bool isChanged = false;
        if (isMoving || (isCenter && abs(zc.x) >= REBLUR_CHANGE_MIN_RESIDUAL))
        {
            float sumZ = 0.0, sumZPrev = 0.0, sumProducts = 0.0, taps = 0.0;
            if (isCenter)
            {
                sumZ = zc.x;
                sumZPrev = zc.y;
                sumProducts = zc.x * zc.y;
                taps = 1.0;
            }
            for (int j = -2; j <= 2; j++)
            {
                for (int i = -2; i <= 2; i++)
                {
                    vec2 zt;
                    if ((i == 0 && j == 0) ||
                        !ChangeTestTap(pixel + ivec2(i, j), nearest + ivec2(i, j), viewZ, zTolerance1, rp.expectedViewZ, zTolerancePrev, zt))
                        continue;
                    sumZ += zt.x;
                    sumZPrev += zt.y;
                    sumProducts += zt.x * zt.y;
                    taps += 1.0;
                }
            }
            float t = max(taps, REBLUR_CHANGE_MIN_TAPS);
            float covariance = taps > 0.0 ? sumProducts / t - (sumZ / t) * (sumZPrev / t) : 0.0;
            isChanged = taps > 0.0 && ((covariance > REBLUR_CHANGE_THRESHOLD && abs(residual) >= REBLUR_CHANGE_MIN_RESIDUAL) ||
                                       (isMoving && covariance > 0.0));
        }
        record = _NRD_LightingChange_Update(record, isChanged);
        if (_NRD_LightingChange_IsMoving(record))
            historyLength = min(historyLength, REBLUR_MOVING_HISTORY);
    }
#endif

    // Accumulation (checkerboard: untraced pixels keep their history).
    bool isSampled = isTraced || historyLength == 0.0 || (gFlags & REBLUR_FLAG_PREPASS) != 0u;
    float newLength = min(historyLength + (isSampled ? 1.0 : 0.0), maxLength);
    vec4 slowBefore = slow;
    if (isSampled)
    {
        slow = mix(slow, current, 1.0 / newLength);
#if REBLUR_SPECULAR
        fast = mix(fast, fastSample, 1.0 / max(min(newLength, gMaxFastAccumulatedFrameNum + 1.0), 1.0));
#else
        // Per-pixel deviation of the samples: running mean of the squared difference between each
        // sample and the history before it, over at least REBLUR_PIXEL_ANTILAG_MOMENT_FRAMES frames
        // (a history cut keeps the deviation it had: from a few samples it would be too noisy for
        // the test above, whose false detections would cut again). A change the test found is not
        // noise: the deviation stays as it was.
        if (newLength > 1.0 && !isPixelCut)
        {
            float d = luma - _Reblur_Luma(slowBefore);
            fast = sqrt(mix(fast * fast, d * d, 1.0 / max(newLength, REBLUR_PIXEL_ANTILAG_MOMENT_FRAMES)));
        }
        // The stabilized luminance restarts where the test found a change.
        if (isPixelCut)
            stabilized = _Reblur_Luma(slow);
#endif
    }

#if !REBLUR_SPECULAR && !REBLUR_OCCLUSION
    float debtTexel = _NRD_LightingChange_Pack(record, _NRD_LightingChange_PackResidual(residual));
#else
    float debtTexel = debt / REBLUR_DEBT_SCALE;
#endif
    vec4 aux = vec4(fast, newLength, stabilized, debtTexel);
#if REBLUR_OCCLUSION
    imageStore(gInOut_Signal, pixel, vec4(aux.xyz, slow.w)); // .xyz are free: auxiliary values
#else
    imageStore(gInOut_Signal, pixel, slow);
    imageStore(gOut_Aux, pixel, aux);
#endif
}
