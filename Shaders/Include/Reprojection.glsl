// History reprojection shared by the radiance denoisers (REBLUR, RELAX) and the shadow methods:
// bilinear footprint, Catmull-Rom weights, per-tap disocclusion by plane distance, history fetches,
// virtual motion of specular reflections from hit-distance parallax, history length storage.
//
// The math takes everything it needs as arguments (no pass constants), so it can be evaluated
// anywhere and compared with a CPU evaluation (Tests/ReprojectionTests.cpp). The history fetches
// use gNearestClamp: include Bindings.glsl (or declare it) first.
#ifndef NRD_REPROJECTION_GLSL
#define NRD_REPROJECTION_GLSL

#include "Common.glsl"

//==================================================================================================
// Footprint and weights.
//==================================================================================================

// The outer taps of a Catmull-Rom footprint lie up to 2 pixels from the reprojected point: on a
// slanted surface their depth differs by up to twice what the bilinear taps' may.
#define NRD_CATMULL_ROM_OUTER_TOLERANCE 2.0
// The 8 outer taps of the 4x4 Catmull-Rom footprint (bit 4 j + i of texel (i, j); the corners are
// left out, the inner 2x2 are the bilinear taps).
#define NRD_CATMULL_ROM_OUTER_TAPS 0x6996u

// Bilinear footprint of 'uv' in a texture of 'size' texels: texel 'origin' and the one right, below
// and diagonal of it, with fraction 'f' in [0, 1).
struct NrdFootprint
{
    ivec2 origin;
    vec2 f;
};

// A still view reprojects onto the texel centres only up to the rounding of uv * size (2.7e-5 of a
// texel at x = 226): a fraction within NRD_FOOTPRINT_SNAP of a texel's centre snaps to it, so that a
// still pixel's history is its own texel's. Without the snap, the lit texel beside a still hard
// shadow lent it 3e-5 a frame, which the history accumulated to 1e-4 where the truth and every
// sample are 0 (SIGMA_SHADOW on venetian_blinds at 256x256). Motion slower than the snap (1/512
// texel a frame) is not followed; a history of NRD_HISTORY_LENGTH_MAX frames would then lag
// half a texel at most.
#define NRD_FOOTPRINT_SNAP (1.0 / 512.0)

// Whether 'uvPrev' is the centre of 'pixel' within NRD_FOOTPRINT_SNAP: a still view's pixel, whose
// footprint is its own texel (false for NaN).
bool _NRD_IsOwnTexel(vec2 uvPrev, ivec2 pixel, vec2 size)
{
    return all(lessThan(abs(uvPrev * size - (vec2(pixel) + 0.5)), vec2(NRD_FOOTPRINT_SNAP)));
}

NrdFootprint _NRD_Footprint(vec2 uv, vec2 size)
{
    vec2 p = uv * size - 0.5;
    vec2 r = floor(p + 0.5);
    p = mix(p, r, lessThan(abs(p - r), vec2(NRD_FOOTPRINT_SNAP)));
    vec2 o = floor(p);
    NrdFootprint footprint;
    footprint.origin = ivec2(clamp(o, vec2(-65536.0), vec2(65536.0)));
    footprint.f = p - o;
    return footprint;
}

// Bilinear weights of the taps origin + (0, 0), (1, 0), (0, 1), (1, 1), in this order.
vec4 _NRD_BilinearWeights(vec2 f)
{
    return vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
}

// Catmull-Rom weights of the texels at -1, 0, 1, 2 around fraction 't' (they sum to 1).
vec4 _NRD_CatmullRomWeights(float t)
{
    return vec4(t * (-0.5 + t * (1.0 - 0.5 * t)), 1.0 + t * t * (-2.5 + 1.5 * t), t * (0.5 + t * (2.0 - 1.5 * t)),
                t * t * (-0.5 + 0.5 * t));
}

//==================================================================================================
// Disocclusion.
//==================================================================================================

// Largest |previous viewZ - expected viewZ| of a tap that still holds the same surface: a relative
// part ('threshold' of the depth) plus the depth change over the one pixel that separates a tap
// from the reprojected point on a surface seen at a grazing angle. 'NoV' = |N.V| of the surface,
// 'projectY' = pixels per unit of size / viewZ (CommonConstants.h, gProjectY).
float _NRD_DisocclusionTolerance(float viewZ, float expectedViewZ, float NoV, float threshold, float projectY)
{
    float tanTheta = min(sqrt(max(1.0 - NoV * NoV, 0.0)) / max(NoV, 0.05), 5.0);
    return threshold * abs(expectedViewZ) + abs(viewZ) / max(projectY, NRD_EPS) * tanTheta;
}

// 1 per bilinear tap (order of _NRD_BilinearWeights) that lies inside [0, size) and whose previous
// viewZ is within 'tolerance' of the expected one, else 0. NaN viewZ never matches.
vec4 _NRD_TapValidity(ivec2 origin, ivec2 size, vec4 prevViewZ, float expectedViewZ, float tolerance)
{
    vec4 valid = vec4(lessThanEqual(abs(prevViewZ - expectedViewZ), vec4(tolerance)));
    ivec4 x = origin.xxxx + ivec4(0, 1, 0, 1);
    ivec4 y = origin.yyyy + ivec4(0, 0, 1, 1);
    valid *= vec4(greaterThanEqual(x, ivec4(0))) * vec4(lessThan(x, ivec4(size.x)));
    valid *= vec4(greaterThanEqual(y, ivec4(0))) * vec4(lessThan(y, ivec4(size.y)));
    return valid;
}

// Reprojection of one pixel: validity-masked bilinear weights (not renormalized), their sum (the
// part of the footprint on the same surface, 0 = disoccluded) and whether Catmull-Rom resampling
// may be used (the whole bilinear footprint is valid; its outer taps are clamped to the image).
struct NrdReprojection
{
    NrdFootprint footprint;
    vec4 weights;
    float footprintWeight;
    bool isCatmullRomAllowed;
    uint catmullRomOuterTaps; // _NRD_CatmullRomOuterTaps where the caller tested them.
};

NrdReprojection _NRD_Reprojection(vec2 uvPrev, ivec2 size, vec4 prevViewZ, float expectedViewZ, float tolerance)
{
    // A non-finite uv (bad motion) lands off screen, where no tap is valid.
    bool isFinite = !any(isnan(uvPrev)) && !any(isinf(uvPrev));
    NrdReprojection r;
    r.footprint = _NRD_Footprint(isFinite ? uvPrev : vec2(-1.0), vec2(size));
    vec4 valid = _NRD_TapValidity(r.footprint.origin, size, prevViewZ, expectedViewZ, tolerance);
    r.weights = _NRD_BilinearWeights(r.footprint.f) * valid;
    r.footprintWeight = dot(r.weights, vec4(1.0));
    r.isCatmullRomAllowed = all(greaterThan(valid, vec4(0.5)));
    r.catmullRomOuterTaps = NRD_CATMULL_ROM_OUTER_TAPS;
    return r;
}

//==================================================================================================
// History fetches (texelFetch through gNearestClamp; previous textures hold garbage where history
// is invalid, so taps are sanitized before weighting).
//==================================================================================================

// .x of the four footprint taps (texels outside the image read as NaN: never valid).
vec4 _NRD_GatherFootprint(texture2D t, ivec2 origin, ivec2 size)
{
    vec4 v;
    for (int k = 0; k < 4; k++)
    {
        ivec2 q = origin + ivec2(k & 1, k >> 1);
        bool isInside = all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size));
        v[k] = isInside ? texelFetch(sampler2D(t, gNearestClamp), q, 0).x : uintBitsToFloat(0x7FC00000u);
    }
    return v;
}

// Weighted bilinear history with the reprojection's masked weights, renormalized (0 if none).
vec4 _NRD_BilinearHistory(texture2D history, NrdReprojection r)
{
    vec4 sum = vec4(0.0);
    for (int k = 0; k < 4; k++)
    {
        if (r.weights[k] > 0.0)
            sum += _NRD_Sanitize(texelFetch(sampler2D(history, gNearestClamp), r.footprint.origin + ivec2(k & 1, k >> 1), 0),
                                 0.0) * r.weights[k];
    }
    return r.footprintWeight > 0.0 ? sum / r.footprintWeight : vec4(0.0);
}

// The outer taps (NRD_CATMULL_ROM_OUTER_TAPS bits) of the Catmull-Rom footprint around 'footprint',
// clamped to the image like the fetches, that hold the surface of the bilinear taps: previous viewZ
// within NRD_CATMULL_ROM_OUTER_TOLERANCE x 'tolerance' of 'expectedViewZ'. The others hold another
// surface's history or none (sky, texels no pass wrote: their content is undefined).
uint _NRD_CatmullRomOuterTaps(texture2D prevViewZ, NrdFootprint footprint, ivec2 size, float expectedViewZ, float tolerance)
{
    uint valid = 0u;
    for (int j = 0; j < 4; j++)
    {
        for (int i = 0; i < 4; i++)
        {
            uint bit = 1u << uint(4 * j + i);
            if ((NRD_CATMULL_ROM_OUTER_TAPS & bit) == 0u)
                continue;
            ivec2 q = clamp(footprint.origin + ivec2(i - 1, j - 1), ivec2(0), size - 1);
            float z = texelFetch(sampler2D(prevViewZ, gNearestClamp), q, 0).x;
            valid |= abs(z - expectedViewZ) <= NRD_CATMULL_ROM_OUTER_TOLERANCE * tolerance ? bit : 0u;
        }
    }
    return valid;
}

// Catmull-Rom history over the 4x4 texels around the footprint, the 4 corners (tiny weights) left
// out and the rest renormalized; taps outside the image are clamped to it. Where the bilinear
// footprint holds one surface (NrdReprojection::isCatmullRomAllowed); an outer tap not in
// 'outerValid' (_NRD_CatmullRomOuterTaps) reads the inner tap next to it instead, as the image's
// border does. Can ring: clamp the result to the range the signal allows.
vec4 _NRD_CatmullRomHistory(texture2D history, NrdFootprint footprint, ivec2 size, uint outerValid)
{
    vec4 wx = _NRD_CatmullRomWeights(footprint.f.x);
    vec4 wy = _NRD_CatmullRomWeights(footprint.f.y);
    vec4 sum = vec4(0.0);
    float weightSum = 0.0;
    for (int j = 0; j < 4; j++)
    {
        for (int i = 0; i < 4; i++)
        {
            if ((i == 0 || i == 3) && (j == 0 || j == 3))
                continue;
            float w = wx[i] * wy[j];
            bool isReplaced = (NRD_CATMULL_ROM_OUTER_TAPS & ~outerValid & (1u << uint(4 * j + i))) != 0u;
            ivec2 k = isReplaced ? clamp(ivec2(i, j), ivec2(1), ivec2(2)) : ivec2(i, j);
            ivec2 q = clamp(footprint.origin + k - 1, ivec2(0), size - 1);
            sum += _NRD_Sanitize(texelFetch(sampler2D(history, gNearestClamp), q, 0), 0.0) * w;
            weightSum += w;
        }
    }
    return sum / weightSum;
}

//==================================================================================================
// Specular virtual motion (hit-distance parallax).
//
// A mirror shows the hit point at its virtual image, 'hitDist' behind the surface along the view
// ray; under camera motion the reflection moves with that image, not with the surface. Glossy
// lobes sit between the two: the dominant direction of a GGX lobe turns from the mirror direction
// towards the normal as roughness grows, and so does the apparent position of the reflection.
//==================================================================================================

// Virtual world position of the reflection seen at surface point 'X' from camera 'cameraPos'.
vec3 _NRD_VirtualWorldPosition(vec3 X, vec3 cameraPos, float hitDist)
{
    vec3 V = X - cameraPos;
    float len = length(V);
    return len > NRD_EPS ? X + V * (max(hitDist, 0.0) / len) : X;
}

// How much of the reflection follows the virtual image, 1 for a mirror, towards 0 for rough
// lobes (the dominant-direction factor of GGX, smoothness * (sqrt(smoothness) + roughness)).
float _NRD_SpecularDominantFactor(float linearRoughness)
{
    float r = clamp(linearRoughness, 0.0, 1.0);
    float s = 1.0 - r;
    return s * (sqrt(s) + r);
}

// Previous uv of a position through a previous world -> clip matrix; (-1, -1) behind the camera.
vec2 _NRD_ProjectPrev(vec3 worldPosPrev, mat4 worldToClipPrev)
{
    vec4 clip = worldToClipPrev * vec4(worldPosPrev, 1.0);
    if (!(clip.w > NRD_EPS))
        return vec2(-1.0);
    return (clip.xy / clip.w) * 0.5 + 0.5;
}

// Previous uv of the reflection of surface point 'X' (moved by 'surfaceMotion' in world space since
// the previous frame): the virtual image is carried along with the surface and seen through the
// previous camera. 'hitDist' is the world-space hit distance, scaled by the dominant factor.
vec2 _NRD_VirtualPreviousUv(vec3 X, vec3 surfaceMotion, vec3 cameraPos, float hitDist, float linearRoughness,
                            mat4 worldToClipPrev)
{
    vec3 Xvirtual = _NRD_VirtualWorldPosition(X, cameraPos, hitDist * _NRD_SpecularDominantFactor(linearRoughness));
    return _NRD_ProjectPrev(Xvirtual + surfaceMotion, worldToClipPrev);
}

// Parallax of the reflection between the frames in pixels: how far apart the surface and the
// virtual reprojections land (0 without camera motion or for hitDist 0). Large parallax means the
// surface history shows another part of the reflection.
float _NRD_ParallaxInPixels(vec2 uvPrevSurface, vec2 uvPrevVirtual, vec2 size)
{
    return length((uvPrevVirtual - uvPrevSurface) * size);
}

//==================================================================================================
// History length storage: a length in [0, maxLength] in a UNORM8 channel (REBLUR, RELAX).
//==================================================================================================

#define NRD_HISTORY_LENGTH_MAX 255.0

float _NRD_PackHistoryLength(float n) { return clamp(n, 0.0, NRD_HISTORY_LENGTH_MAX) / NRD_HISTORY_LENGTH_MAX; }
float _NRD_UnpackHistoryLength(float packed) { return floor(_NRD_Sanitize(packed, 0.0) * NRD_HISTORY_LENGTH_MAX + 0.5); }

//==================================================================================================
// Confidence input (IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE, REBLUR and RELAX).
//==================================================================================================

// The history length that a confidence c in [0, 1] leaves (REBLUR diffuse, RELAX): c times the
// length, but no shorter than 'minFrames' (nor longer than it was); NRD_CONFIDENCE_MIN_HISTORY frames
// unless a consumer measured otherwise (RELAX diffuse: RELAX_DIFFUSE_CONFIDENCE_MIN_HISTORY). The consumers' own clamps and
// anti-lag move the few frames kept to this frame's lighting; a restart to 0 frames costs more
// noise than the light left in them costs bias where a light toggles every few frames (scene lab,
// 64x64, CONFIDENCE at sensitivity 1, relMSE against the run without confidence, restart -> kept 4:
// toggling_light REBLUR_DIFFUSE 1.04x -> 0.94x, RELAX_DIFFUSE 1.06x -> 0.96x; moving_light
// RELAX_SPECULAR 1.07x -> 0.88x; Shaders/Confidence/README.md).
#define NRD_CONFIDENCE_MIN_HISTORY 4.0

float _NRD_ConfidenceHistoryLength(float historyLength, float confidence, float minFrames)
{
    return max(historyLength * confidence, min(historyLength, minFrames));
}

// The factor by which a confidence c narrows a consumer's tolerance of a change (REBLUR diffuse's
// anti-lag correction, RELAX diffuse's mean clamp): min(c / knee, 1)^power, at least 0.05. A
// confidence at or above 'knee' leaves the tolerance as without confidence: moving shadow edges dip
// the confidence a little over whole regions frame after frame, and a narrowed tolerance there moves
// still history by its neighbourhood's noise on every frame; a switched lamp's pixels fall far below
// any knee.
float _NRD_ConfidenceNarrowing(float confidence, float knee, int power)
{
    float n = min(confidence / knee, 1.0), f = n;
    for (int i = 1; i < power; ++i)
        f *= n;
    return max(f, 0.05);
}

#endif
