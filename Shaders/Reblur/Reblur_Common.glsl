// REBLUR: helpers shared by the passes (document 004, REBLUR). Include after the pass's
// .resources.h and CommonFrame.glsl.
//
// Signal: a vec4, .rgb radiance (zero in the occlusion variants), .w normalized hit distance in
// [0, 1]. REBLUR_SPECULAR selects the specular rules (virtual motion, lobe-aware weights),
// REBLUR_OCCLUSION the hit-distance-only variants (the denoised hit distance is the AO / SO).
#ifndef REBLUR_COMMON_GLSL
#define REBLUR_COMMON_GLSL

// Sky value of the stored viewZ: never within any tolerance of a positive viewZ.
#define REBLUR_NO_VIEWZ (-1.0)

// Largest radiance kept (fp16 storage, and 1e30 inputs cannot overflow the sums).
#define REBLUR_MAX_RADIANCE 60000.0

// Plane distance a reprojected diffuse history tap may have from the surface, in units of
// gDisocclusionThreshold * viewZ (0.1% of viewZ with the default threshold; fp16 viewZ keeps
// 0.05%). 1 (1% of viewZ) still let the gaps between the parts of mesh_engine through.
#define REBLUR_PLANE_TOLERANCE 0.1

// The anti-lag's noise estimate of specular radiance, relative to diffuse's: single specular
// samples are heavy-tailed (rare bright ones), so the fast history strays from the slow one by more
// than a Gaussian's few sigma far more often; each such cut shortened the history soon after the
// rare bright samples had entered it at a small weight, and darkened the mean (sky at 64x64:
// -5.3% with 1, -2.9% with 1.5, -1.3% with 2). The fast history's clamp to this frame's 3x3 box
// (mean + 4 sigma of nine skewed samples, most often without a bright one) keeps it below the slow
// history most of the time; without that clamp there is no bias, but a light switched off then
// stays in the history. 2.5 since the specular history follows the view's parallax (the camera
// motion that made camera_translation's error rise with this scale is now the parallax limit's):
// sky at 128x128 (H100) -4.6% -> -2.9%, roughness_sweep -3.5% -> -2.5%, errors within 1% except
// roughness_sweep's (+8%).
#define REBLUR_SPECULAR_ANTILAG_NOISE_SCALE 2.5

// Specular history under parallax: a reflection seen from a direction that turned by an angle
// theta since the previous frame shows another part of the lobe's surroundings; the history keeps
// at most (this fraction of the lobe's half-angle) / theta frames, whole frames (the view turns by
// at most about a sixth of the lobe over the history). On mesh_engine (steel of roughness 0.45 reflecting its own fins, a camera
// swinging 1.8 degrees a frame) the reflections change more from one frame to the next than the
// input's noise (the truth reprojected along the exact motion: relMSE 1.8 against the input's
// 0.64): 30 frames of history, and even one, left the output worse than its input.
#define REBLUR_SPECULAR_PARALLAX_FRACTION 0.15

// Temporal stabilization under camera motion: its history length is divided by 1 + this times the
// camera's motion in pixels (each resampling of the stabilized history blurs it a little more).
#define REBLUR_STABILIZATION_MOTION_SCALE 4.0

// Diffuse temporal stabilization under camera motion: off for histories shorter than this many
// frames (the stabilized luminance of a short, resampled history holds the light of the blurred
// outputs before it; mesh_engine's gaps between fins, 128x128 lavapipe: relMSE 0.0812 -> 0.0763,
// still views unchanged).
#define REBLUR_STABILIZATION_MIN_MOVING_HISTORY 16.0


// Diffuse anti-lag: radius of the input neighbourhood whose mean is compared with the same mean of
// the previous history (2: 5x5), and the tolerance in units of that mean's expected noise
// (relative to gAntilagSigmaScale). Neighbours count where their viewZ is within 4 times
// gDisocclusionThreshold plus 2 pixels' footprint per pixel of distance (the same surface, any slope).
#define REBLUR_ANTILAG_RADIUS 2
#define REBLUR_DIFFUSE_ANTILAG_NOISE_SCALE 0.67

// Diffuse per-pixel anti-lag (Reblur_TemporalAccumulation.comp). z^2: a sample's squared difference
// from its own history in units of the history's per-pixel deviation (the fast channel), capped at
// CAP. The history is cut where the mean z^2 of the 8 neighbours exceeds CHI and the pixel's own
// z^2 exceeds SELF, to its length times
// (mean / CHI)^-POWER. The deviation is a running mean over at least MOMENT_FRAMES samples.
// Lower CHI / SELF follow moving stripes sooner and cut still scenes' histories at rare samples
// (128x128, lavapipe: CHI 2 / SELF 4: venetian_blinds 0.0339, sky 0.00037; 1.4 / 2: 0.0303,
// 0.00037; without SELF, CHI 2: 0.0310, sky 0.00040).
#define REBLUR_PIXEL_ANTILAG_CAP 9.0
#define REBLUR_PIXEL_ANTILAG_CHI 1.4
#define REBLUR_PIXEL_ANTILAG_SELF 2.0
#define REBLUR_PIXEL_ANTILAG_POWER 4.0
#define REBLUR_PIXEL_ANTILAG_MOMENT_FRAMES 8.0

// Diffuse, where the surface moved on screen (by more than REBLUR_PIXEL_ANTILAG_MOTION pixels since
// the previous frame): a sample below its own history by more than REBLUR_PIXEL_ANTILAG_SELF (z^2)
// halves the history even where the neighbours agree with theirs. A history resampled along motion
// can carry a neighbouring surface's light into a one-pixel gap or crease (mesh_engine's fins: 
// histories of 5-10 frames at 0.5-1.0 where the truth is below 0.05 and the samples are 0), and a
// one-pixel feature has no neighbours to confirm the change. On a still view the history cannot
// come from elsewhere and the rule stays off (there it only cut histories at rare dark samples:
// thin_geometry +3%, sky +4% when always on).
#define REBLUR_PIXEL_ANTILAG_MOTION 0.05

// Specular, where the surface moved on screen: a sample below this fraction of its own history halves
// the history (heavy-tailed specular samples have no per-pixel deviation to measure the difference
// with; a quarter of the history is rare for a sample of the same surface and usual for a reflection
// that is not there). mesh_thin 128x128 (lavapipe, truth 64 spp): relMSE 0.1202 -> 0.0708,
// camera_rotation 0.0289 -> 0.0230, camera_translation 0.0244 -> 0.0253, mesh_engine 0.0824 ->
// 0.0842, the other scenes unchanged (on a still view the rule is off; always on, static +13%).
#define REBLUR_SPECULAR_SELF_FRACTION 0.25

// Diffuse blur and history fix (Reblur_Blur.comp): a neighbour's weight falls as a Gaussian of its
// accumulated luminance's difference from the centre's, in units of SIGMA standard deviations of
// the two means (per-pixel deviation^2 / history length). Where the luminance-weighted neighbours
// carry less than ISOLATED_LOW of the geometric weight, the centre is taken for a rare sample and
// the geometric result is used (up to ISOLATED_HIGH: a blend).
#define REBLUR_LUMA_WEIGHT_SIGMA 3.0
#define REBLUR_LUMA_ISOLATED_LOW 0.2
#define REBLUR_LUMA_ISOLATED_HIGH 0.5

// Diffuse with a confidence input: a cut history keeps at least this many frames (specular restarts,
// see Reblur_TemporalAccumulation.comp). Anti-lag moves them to this frame's lighting; with 4 (the
// consumers' NRD_CONFIDENCE_MIN_HISTORY) the noise of the frames after a lamp comes on cost more than
// the trailing light removed (toggling_light 64x64, relMSE with / without confidence summed over
// seeds 1-6: 1.015x with 4, 0.988x with 6; light_switch 0.971x -> 0.952x; NVIDIA H200,
// Shaders/Confidence/README.md, "One seed against several").
#define REBLUR_DIFFUSE_CONFIDENCE_MIN_HISTORY 6.0

// Diffuse with a confidence input: the anti-lag's correction narrows its tolerance by
// min(confidence / this, 1) (at least 0.05). A confidence above it leaves the tolerance as without
// confidence: slight dips, which moving shadow edges cause frame after frame over whole regions,
// moved the pixels beside the edges by their 5x5 neighbourhood's change (venetian_blinds, relMSE with
// / without confidence summed over seeds, NVIDIA H200: 1.005x at 128x128 and 1.017x at 256x256 with
// the confidence itself, 0.998x and 0.997x with 0.7); a lamp switched on or off still moves its
// pixels at once (toggling_light 64x64: trailing light 4 -> 2 frames, 4 -> 1 with 0.75, 4 -> 0 with
// 1; Shaders/Confidence/README.md).
#define REBLUR_DIFFUSE_CONFIDENCE_NARROWING_KNEE 0.7

// Confidence debt (the frames of history a confidence input took, up to gHistoryFixFrameNum), stored
// in R8 UNORM as debt / REBLUR_MAX_HISTORY_FIX_FRAME_NUM (NRDSettings.h: 3).
#define REBLUR_DEBT_SCALE 3.0
// Specular: a history the confidence cut keeps the history fix for this many times the debt's
// frames longer (Reblur_Blur.comp). 1 -> 2, lavapipe, 64x64, 40 frames, relMSE with / without
// confidence summed over seeds 1-6: fast_occluder 1.0001x -> 0.990x, every other lighting scene
// within 2.3% of its gain (Shaders/Confidence/README.md, "The regrowth over twice the debt's
// frames").
#define REBLUR_SPECULAR_DEBT_FIX_SCALE 2.0

// Diffuse lighting change test (Reblur_TemporalAccumulation.comp), with or without a confidence input: lines
// of light narrower than any clamping box that move over a still surface without motion vectors
// (venetian_blinds) change a pixel by less than one sample's noise a frame. What shows is that
// departures persist and keep their spatial pattern: each 5x5 tap on the same surface has a
// residual z (its sample against its own history, in the history's per-pixel deviation), and where
// this frame's and the previous frame's residuals covary over the taps (their mean product less the
// product of their means, which takes out an error the whole window shares, such as a blotch of the
// blurred history or a uniform lighting change the anti-lag follows) by more than CHANGE_THRESHOLD,
// with the pixel's own |z| at least CHANGE_MIN_RESIDUAL (where the lighting already moves: any
// positive covariance), the lighting change record (Shaders/Include/LightingChange.glsl) rises by 2,
// else it falls by 1, and the lighting moves from 3 on: two findings in consecutive frames (one
// finding alone moved the still scenes' noisy windows about one frame in twenty: static +40% relMSE
// at 128x128, two in a row +11%; Shaders/Reblur/README.md). While it says the lighting moves, the history keeps MOVING_HISTORY frames before this
// frame's sample, the history fix does not run (it would spread the lines) and the blur and post-blur
// radii are scaled by MOVING_RADIUS_SCALE.
#define REBLUR_CHANGE_MIN_TAPS 12.0
#define REBLUR_CHANGE_THRESHOLD 0.25
#define REBLUR_CHANGE_MIN_RESIDUAL 0.5
#define REBLUR_MOVING_HISTORY 1.0
#define REBLUR_MOVING_RADIUS_SCALE 0.2

// Debt texture (R8 UNORM, per signal): diffuse radiance, the lighting change record and this frame's
// residual at the pixel (the change test above, with or without a confidence input); specular and
// the occlusion signals, the confidence debt / REBLUR_DEBT_SCALE (0 without a confidence input).
#define _NRD_LIGHTING_CHANGE_RISE 2u
#define _NRD_LIGHTING_CHANGE_MOVING 3u
#include "LightingChange.glsl"

//==================================================================================================
// Inputs.
//==================================================================================================

// Sanitized input: non-finite or negative radiance reads as 0, non-finite hit distance as 1 (no
// hit: the open sky is not occluded), hit distance clamped to [0, 1].
vec4 _Reblur_Sanitize(vec4 s)
{
    vec3 radiance = clamp(_NRD_Sanitize(s.rgb, 0.0), vec3(0.0), vec3(REBLUR_MAX_RADIANCE));
    return vec4(radiance, clamp(_NRD_Sanitize(s.w, 1.0), 0.0, 1.0));
}

vec4 _Reblur_LoadInput(texture2D t, ivec2 pixel)
{
    vec4 s = texelFetch(sampler2D(t, gNearestClamp), pixel, 0);
#if REBLUR_OCCLUSION
    s = vec4(0.0, 0.0, 0.0, s.x);
#endif
    return _Reblur_Sanitize(s);
}

// The value a temporal / spatial pass compares: luminance, or the hit distance (occlusion).
float _Reblur_Luma(vec4 s)
{
#if REBLUR_OCCLUSION
    return s.w;
#else
    return _NRD_Luminance(s.rgb);
#endif
}

// Scales the radiance so that its luminance becomes 'luma' (luminance-only stabilization).
vec4 _Reblur_WithLuma(vec4 s, float luma)
{
#if REBLUR_OCCLUSION
    s.w = luma;
#else
    float current = _NRD_Luminance(s.rgb);
    s.rgb = current > 1e-8 ? s.rgb * (luma / current) : s.rgb;
#endif
    return s;
}

// World-space hit distance per unit of normalized hit distance (HitDistanceParameters, shared with
// the front end); diffuse signals are normalized with roughness 1.
float _Reblur_HitDistNormalization(float viewZ, float roughness)
{
#if !REBLUR_SPECULAR
    roughness = 1.0;
#endif
    return _NRD_GetHitDistNormalization(viewZ, gHitDistParams, roughness);
}

bool _Reblur_IsTraced(ivec2 pixel)
{
    return gCheckerboard == 0u || uint((pixel.x + pixel.y) & 1) == gCheckerboard - 1u;
}

bool _Reblur_IsSkyTile(texture2D tiles, ivec2 pixel)
{
    return texelFetch(sampler2D(tiles, gNearestClamp), pixel / REBLUR_TILE_SIZE, 0).x < 0.5;
}

//==================================================================================================
// Geometry.
//==================================================================================================

struct ReblurSurface
{
    vec3 Xv;       // view-space position
    vec3 Nv;       // view-space normal
    vec3 N;        // world-space normal
    float roughness;
    float viewZ;
};

ReblurSurface _Reblur_Surface(texture2D normalRoughness, ivec2 pixel, float viewZ)
{
    ReblurSurface s;
    vec4 nr = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(normalRoughness, gNearestClamp), pixel, 0));
    s.N = nr.xyz;
    s.roughness = nr.w;
    s.Nv = normalize(transpose(mat3(gViewToWorld)) * s.N);
    s.Xv = _NRD_ViewPosition(_NRD_PixelUv(pixel), viewZ);
    s.viewZ = viewZ;
    return s;
}

// Half-angle of the specular lobe that holds most of its energy (radians), from linear roughness.
float _Reblur_LobeHalfAngle(float roughness)
{
    float a = roughness * roughness;
    return atan(a * 0.75); // ~75% of the GGX energy lies within atan(0.75 a) of the dominant direction
}

// Spatial weight of a neighbour: plane distance, normal (lobe-aware for specular), roughness.
float _Reblur_GeometryWeight(ReblurSurface c, vec3 Xs, vec3 Ns, float roughnessS)
{
    float planeDistance = abs(dot(c.Nv, Xs - c.Xv));
    float w = clamp(1.0 - planeDistance / (gPlaneDistanceSensitivity * c.viewZ), 0.0, 1.0);
    float cosAngle = clamp(dot(c.Nv, Ns), -1.0, 1.0);
#if REBLUR_SPECULAR
    float maxAngle = max(_Reblur_LobeHalfAngle(c.roughness) * gLobeAngleFraction, 0.02);
    w *= clamp(1.0 - acos(cosAngle) / maxAngle, 0.0, 1.0);
    w *= clamp(1.0 - abs(c.roughness - roughnessS) / (gRoughnessFraction * max(c.roughness, 0.05)), 0.0, 1.0);
#else
    w *= smoothstep(0.5, 0.95, cosAngle);
#endif
    return w;
}

//==================================================================================================
// Colour compression of the spatial passes: radiance / (1 + k * luminance) before weighting and
// its inverse after, so a single bright sample cannot dominate the weighted sum; k grows for
// smooth specular (narrow lobes, where fireflies are spikiest) and is small for rough / diffuse.
//==================================================================================================

float _Reblur_CompressionK(float roughness)
{
#if REBLUR_OCCLUSION
    return 0.0;
#elif REBLUR_SPECULAR
    return gColorCompression * (1.0 - roughness);
#else
    return gColorCompression * 0.25;
#endif
}

vec4 _Reblur_Compress(vec4 s, float k)
{
    return vec4(s.rgb / (1.0 + k * _NRD_Luminance(s.rgb)), s.w);
}

vec4 _Reblur_Decompress(vec4 s, float k)
{
    float l = _NRD_Luminance(s.rgb);
    return vec4(s.rgb / max(1.0 - k * l, 1e-3), s.w);
}

//==================================================================================================
// Blur radius rules: widest on short history, far hits (diffuse: wide indirect light) and rough
// lobes (specular); a mirror is not blurred.
//==================================================================================================

float _Reblur_HitDistFactor(float normHitDist, float viewZ, float roughness)
{
    float hitDist = normHitDist * _Reblur_HitDistNormalization(viewZ, roughness);
    return clamp(hitDist / (hitDist + abs(viewZ) * 0.1 + 1e-4), 0.1, 1.0);
}

float _Reblur_BlurRadius(float historyLength, float normHitDist, float viewZ, float roughness)
{
    // Checkerboard: the length counts samples, one every other frame, and the radius follows the
    // samples, whose noise it filters (static, NVIDIA H100, relMSE against the full rate: specular
    // 1.93x -> 1.59x at 64x64; diffuse 1.84x -> 1.49x at 128x128 and 1.97x -> 1.43x at 256x256,
    // but 1.86x -> 1.97x at 64x64, where the wider radius blurs contact shadows of a few pixels).
    float historyScale = 1.0 / (1.0 + historyLength);
    float r = gBlurRadius * historyScale * _Reblur_HitDistFactor(normHitDist, viewZ, roughness);
#if REBLUR_SPECULAR
    float lobe = clamp(roughness * 2.0, 0.0, 1.0);
    r *= lobe;
    return max(r, gMinBlurRadius * lobe);
#else
    return max(r, gMinBlurRadius);
#endif
}

// Per-pixel, per-frame, per-pass rotation of the sparse kernel.
float _Reblur_KernelAngle(ivec2 pixel, uint salt)
{
    uint seed = uint(pixel.x) * 0x9e3779b1u ^ uint(pixel.y) * 0x85ebca77u ^ (gFrameIndex * 3u + salt) * 0xc2b2ae3du;
    return _NRD_Random01(seed) * (2.0 * NRD_PI);
}

//==================================================================================================
// Reprojection (shared by the temporal passes).
//==================================================================================================

struct ReblurReprojection
{
    NrdReprojection surface;
    NrdReprojection virtual_; // Specular only; equals 'surface' otherwise.
    float virtualAmount;      // Blend of the virtual history, [0, 1].
    float expectedViewZ;      // Previous viewZ of the surface point, and the viewZ tolerance of its taps.
    float tolerance;
    float parallax;           // Angle (radians) between the point's view directions of this frame and the previous one.
};

// Drops the footprint taps whose previous surface point lies off the plane of the reprojected
// point (its previous view-space position and normal): a viewZ tolerance that admits slanted
// planes (it grows with the slope) also admits other surfaces a few pixels deep behind or in
// front, which on detailed geometry (gaps between small parts) blends unrelated lighting into the
// history at every frame. The plane test is exact on planes of any slope.
void _Reblur_PlaneTest(inout NrdReprojection r, vec4 prevViewZ, vec3 XvPrev, vec3 NvPrev, float tolerance)
{
    for (int k = 0; k < 4; k++)
    {
        if (r.weights[k] <= 0.0)
            continue;
        vec2 uvTap = (vec2(r.footprint.origin + ivec2(k & 1, k >> 1)) + 0.5) * gInvResourceSize;
        vec3 Xt = _NRD_ViewPosition(uvTap, prevViewZ[k]);
        if (abs(dot(NvPrev, Xt - XvPrev)) > tolerance)
            r.weights[k] = 0.0;
    }
    float before = r.footprintWeight;
    r.footprintWeight = dot(r.weights, vec4(1.0));
    r.isCatmullRomAllowed = r.isCatmullRomAllowed && r.footprintWeight >= before;
}

ReblurReprojection _Reblur_Reproject(texture2D prevViewZ, ivec2 pixel, ReblurSurface s, vec3 mv, float normHitDist)
{
    vec2 uv = _NRD_PixelUv(pixel);
    vec3 X = (gViewToWorld * vec4(s.Xv, 1.0)).xyz;
    vec3 Xprev;
    vec2 uvPrev = _NRD_PreviousUv(uv, X, mv, Xprev);
    float expectedViewZ = _NRD_PreviousViewZ(Xprev);
    float NoV = abs(dot(s.Nv, normalize(s.Xv)));
    float tolerance = _NRD_DisocclusionTolerance(s.viewZ, expectedViewZ, NoV, gDisocclusionThreshold, gProjectY);
    ivec2 size = ivec2(gResourceSize);
    ReblurReprojection r;
    r.expectedViewZ = expectedViewZ;
    r.tolerance = tolerance;
    // View parallax: the direction from the camera to the point now and in the previous frame (the
    // previous camera position from the previous world -> view matrix).
    vec3 cameraPrev = -(transpose(mat3(gWorldToViewPrev)) * gWorldToViewPrev[3].xyz);
    // (2 asin of half the chord between the unit directions: acos of their dot product is off by
    // 5e-4 radians near 0 in 32-bit floats, parallax enough to limit smooth specular on a still view.)
    vec3 Vprev = Xprev - cameraPrev;
    vec3 chord = normalize(X - _NRD_CameraPosition()) - Vprev / max(length(Vprev), NRD_EPS);
    r.parallax = 2.0 * asin(clamp(_NRD_Sanitize(length(chord), 0.0) * 0.5, 0.0, 1.0));
    NrdFootprint f = _NRD_Footprint(uvPrev, vec2(size));
    vec4 prevZ = _NRD_GatherFootprint(prevViewZ, f.origin, size);
    r.surface = _NRD_Reprojection(uvPrev, size, prevZ, expectedViewZ, tolerance);
    vec3 XvPrev = (gWorldToViewPrev * vec4(Xprev, 1.0)).xyz;
    vec3 NvPrev = normalize(mat3(gWorldToViewPrev) * s.N);
    float planeTolerance = REBLUR_PLANE_TOLERANCE * gDisocclusionThreshold * abs(expectedViewZ);
    // 2D motion: the previous position of a moving surface is unknown (only the viewZ test applies).
    bool isPrevPositionKnown = gMotionVectorScale.w != 0.0 || (gMotionVectorScale.x == 0.0 && gMotionVectorScale.y == 0.0);
#if !REBLUR_SPECULAR
    // Diffuse only: the specular history of a rejected tap still holds the same reflection (the
    // virtual motion decides there), and rejecting it only shortens the history.
    if (isPrevPositionKnown)
        _Reblur_PlaneTest(r.surface, prevZ, XvPrev, NvPrev, planeTolerance);
#endif
    if (gResetHistory != 0u)
        r.surface.weights = vec4(0.0), r.surface.footprintWeight = 0.0, r.surface.isCatmullRomAllowed = false;
    r.surface.catmullRomOuterTaps =
        r.surface.isCatmullRomAllowed ? _NRD_CatmullRomOuterTaps(prevViewZ, r.surface.footprint, size, expectedViewZ, tolerance) : 0u;
    r.virtual_ = r.surface;
    r.virtualAmount = 0.0;
#if REBLUR_SPECULAR
    // The virtual image moves with the surface (world motion where known) and is seen through the
    // previous camera; its viewZ test uses the surface's own depth (the history stores surfaces).
    float hitDist = normHitDist * _Reblur_HitDistNormalization(s.viewZ, s.roughness);
    vec3 motion = Xprev - X;
    vec2 uvVirtual = _NRD_VirtualPreviousUv(X, motion, _NRD_CameraPosition(), hitDist, s.roughness, gWorldToClipPrev);
    if (gMotionVectorScale.w == 0.0 && (gMotionVectorScale.x != 0.0 || gMotionVectorScale.y != 0.0))
        uvVirtual += uvPrev - _NRD_ProjectPrev(X, gWorldToClipPrev); // 2D motion: add the object's part
    NrdFootprint fv = _NRD_Footprint(uvVirtual, vec2(size));
    r.virtual_ = _NRD_Reprojection(uvVirtual, size, _NRD_GatherFootprint(prevViewZ, fv.origin, size), expectedViewZ,
                                   tolerance * 2.0);
    if (gResetHistory != 0u)
        r.virtual_.weights = vec4(0.0), r.virtual_.footprintWeight = 0.0, r.virtual_.isCatmullRomAllowed = false;
    r.virtual_.catmullRomOuterTaps =
        r.virtual_.isCatmullRomAllowed ? _NRD_CatmullRomOuterTaps(prevViewZ, r.virtual_.footprint, size, expectedViewZ, tolerance * 2.0) : 0u;
    float d = _NRD_SpecularDominantFactor(s.roughness);
    float vw = d * r.virtual_.footprintWeight;
    float sw = (1.0 - d) * r.surface.footprintWeight;
    r.virtualAmount = vw + sw > 1e-6 ? vw / (vw + sw) : 0.0;
    // Without parallax both land on the same texels: prefer the surface footprint (sharper validity).
    if (_NRD_ParallaxInPixels(uvPrev, uvVirtual, vec2(size)) < 0.01)
        r.virtualAmount = 0.0;
#endif
    return r;
}

// History fetched along a reprojection: Catmull-Rom where the footprint is whole, else bilinear.
vec4 _Reblur_FetchHistory(texture2D history, NrdReprojection r)
{
    if (r.footprintWeight <= 0.0)
        return vec4(0.0);
    if (r.isCatmullRomAllowed)
    {
        vec4 cr = _NRD_CatmullRomHistory(history, r.footprint, ivec2(gResourceSize), r.catmullRomOuterTaps);
        vec4 bl = _NRD_BilinearHistory(history, r);
        // Catmull-Rom rings next to edges: soften it slightly towards bilinear, never negative.
        return max(mix(bl, cr, 0.85), vec4(0.0));
    }
    return _NRD_BilinearHistory(history, r);
}

#endif
