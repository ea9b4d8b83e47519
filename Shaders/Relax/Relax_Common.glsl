// RELAX: helpers shared by the family's passes (include after the pass's .resources.h and
// CommonFrame.glsl). SVGF (Schied et al. 2017, "Spatiotemporal Variance-Guided Filtering") with the
// fast-history clamping of document 004.
#ifndef RELAX_COMMON_GLSL
#define RELAX_COMMON_GLSL

#define RELAX_TILE_SIZE 8

// Diffuse with a confidence input: a cut history keeps at least this many frames (specular:
// NRD_CONFIDENCE_MIN_HISTORY, 4; REBLUR diffuse: REBLUR_DIFFUSE_CONFIDENCE_MIN_HISTORY, 6). The mean clamp moves them to this frame's lighting; with 4
// each new sample weighs a fifth where the shadow of fast_occluder's box sweeps the floor without
// motion vectors (relMSE with / without confidence, lavapipe 128x128: fast_occluder 1.0043x ->
// 0.990x, mesh_thin 1.0004x -> 0.9995x; Shaders/Confidence/README.md).
#define RELAX_DIFFUSE_CONFIDENCE_MIN_HISTORY 6.0

// Diffuse with a confidence input: the mean clamp's distance is multiplied by (c / this)^2 where the
// confidence c is below it (_NRD_ConfidenceNarrowing). The confidence itself (the distance times c)
// moved the still histories under moving shadow edges, whose confidence dips a little frame after
// frame, by their 5x5 mean's noise (venetian_blinds, relMSE with / without confidence summed over
// seeds, NVIDIA H200: 1.0065x at 128x128 and 1.029x at 256x256 with c, 0.994x and 0.999x with this);
// squared, a lamp's pixels are still moved at once (toggling_light 64x64: trailing light 4 -> 0
// frames; linear with a knee of 0.7: 4 -> 4; Shaders/Confidence/README.md).
#define RELAX_DIFFUSE_CONFIDENCE_NARROWING_KNEE 0.6

// Every pass but the classification runs 8x8 groups aligned with the tiles: a group whose tile
// holds only sky returns before any load.
bool Relax_IsTileSkipped(texture2D tiles) { return texelFetch(tiles, ivec2(gl_WorkGroupID.xy), 0).x == 0.0; }

bool Relax_IsInImage(ivec2 p) { return all(greaterThanEqual(p, ivec2(0))) && all(lessThan(p, ivec2(gResourceSize))); }

// Input radiance + normalized hit distance: non-finite values become 0, radiance is kept in
// [0, FP16 max], the hit distance in [0, 1].
vec4 Relax_SanitizeSignal(vec4 s)
{
    s = _NRD_Sanitize(s, 0.0);
    return clamp(s, vec4(0.0), vec4(vec3(NRD_FP16_MAX), 1.0));
}

// A sample whose radiance is not finite (NaN, Inf) is a missing sample: it is not accumulated, not
// used for reconstruction and left out of the neighbourhood statistics, so that the history survives
// a frame of broken input unchanged.
bool Relax_IsSample(vec4 s) { return _NRD_IsFinite(vec4(s.rgb, 0.0)); }

// Surface of a pixel as the stoppers need it: view-space position and normal, world-space normal,
// linear roughness. Normal tests between two pixels are dot products of the world-space normals
// (no rotation per tap); the tangent-plane distance takes the centre's view-space normal.
struct RelaxSurface
{
    vec3 X;      // View-space position.
    vec3 N;      // View-space normal (Relax_LoadSurface only).
    vec3 Nw;     // World-space normal.
    float z;     // viewZ (0: sky or outside the image).
    float roughness;
};

// A neighbour's surface: everything but the view-space normal (left (0, 0, 1)).
RelaxSurface Relax_LoadNeighbour(texture2D normalRoughness, texture2D viewZ, ivec2 p)
{
    RelaxSurface s;
    s.z = 0.0;
    s.X = vec3(0.0);
    s.N = vec3(0.0, 0.0, 1.0);
    s.Nw = vec3(0.0, 0.0, 1.0);
    s.roughness = 1.0;
    if (!Relax_IsInImage(p))
        return s;
    float z = texelFetch(viewZ, p, 0).x;
    if (_NRD_IsSky(z))
        return s;
    vec4 nr = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(normalRoughness, p, 0));
    s.z = z;
    s.X = _NRD_ViewPosition(_NRD_PixelUv(p), z);
    s.Nw = nr.xyz;
    s.roughness = nr.w;
    return s;
}

// World -> view: the transpose of viewToWorld's rotation (rigid camera).
vec3 Relax_ViewNormal(vec3 Nw) { return normalize(transpose(mat3(gViewToWorld)) * Nw); }

RelaxSurface Relax_LoadSurface(texture2D normalRoughness, texture2D viewZ, ivec2 p)
{
    RelaxSurface s = Relax_LoadNeighbour(normalRoughness, viewZ, p);
    if (s.z != 0.0)
        s.N = Relax_ViewNormal(s.Nw);
    return s;
}

// Half-angle of the specular lobe (radians) holding most of its energy, for linear roughness r:
// atan(3 r^2) (the GGX lobe of alpha = r^2 holds 75% of its energy within tan = 3 alpha). Diffuse
// uses r = 1.
float Relax_LobeHalfAngle(float roughness) { return atan(3.0 * roughness * roughness); }

// acos(x) within 6.8e-5 radians (Abramowitz and Stegun 4.4.45, a polynomial times sqrt(1 - |x|)):
// cheaper than the built-in per a-trous tap.
float Relax_Acos(float x)
{
    float ax = abs(x);
    float a = sqrt(1.0 - ax) * (1.5707288 + ax * (-0.2121144 + ax * (0.0742610 - 0.0187293 * ax)));
    return x < 0.0 ? 3.14159265 - a : a;
}

// Stopper weights, each exactly 0 beyond its threshold so that hard edges stay hard.
float Relax_NormalWeight(vec3 Nc, vec3 Ni, float maxAngle)
{
    float cosAngle = clamp(dot(Nc, Ni), -1.0, 1.0);
    return clamp(1.0 - Relax_Acos(cosAngle) / maxAngle, 0.0, 1.0);
}

float Relax_PlaneWeight(RelaxSurface c, vec3 Xi, float relativeThreshold)
{
    float distance = abs(dot(c.N, Xi - c.X));
    return clamp(1.0 - distance / (relativeThreshold * c.z), 0.0, 1.0);
}

float Relax_RoughnessWeight(float rc, float ri, float fraction)
{
    return clamp(1.0 - abs(rc - ri) / (fraction * rc + 0.01), 0.0, 1.0);
}

// History length texture (RG8, per signal):
// - .x: the history length in frames (0..63) and, times 64 above it, the confidence debt (the frames a
//   confidence input took, 0..3: historyFixFrameNum's range);
// - .y: the lighting change record and, in its 5-bit value, this frame's residual at the pixel (the
//   diffuse temporal accumulation's change test, Relax_TemporalAccumulation.comp), packed by
//   Shaders/Include/LightingChange.glsl. RELAX: the record rises by 2 where the test found a change
//   and falls by 1 where it did not, and the lighting moves from 2 on (one frame where the test
//   fires; longer where it keeps firing).
#define _NRD_LIGHTING_CHANGE_RISE 2u
#define _NRD_LIGHTING_CHANGE_MOVING 2u
#include "LightingChange.glsl"

#define RELAX_HISTORY_LENGTH_LIMIT 63.0

// The variance estimation's scale where the lighting moves (Relax_SpatialVariance.comp).
#define RELAX_MOVING_VARIANCE_SCALE 0.25

float Relax_PackLengthAndDebt(float historyLength, float debt)
{
    return (clamp(floor(historyLength + 0.5), 0.0, RELAX_HISTORY_LENGTH_LIMIT) + 64.0 * clamp(floor(debt + 0.5), 0.0, 3.0)) / 255.0;
}

// (history length, confidence debt) from the .x channel.
vec2 Relax_UnpackLengthAndDebt(float packed)
{
    float v = floor(clamp(_NRD_Sanitize(packed, 0.0), 0.0, 1.0) * 255.0 + 0.5);
    float debt = floor(v / 64.0);
    return vec2(v - 64.0 * debt, debt);
}

#endif
