// SIGMA: helpers shared by the passes (document 004, SIGMA). Include after the pass's
// .resources.h and CommonFrame.glsl: the helpers read the NRD_COMMON_CONSTANTS and SIGMA_CONSTANTS.
//
// Signal: SIGMA_SHADOW denoises the visibility IN_SHADOWDATA.x (a float);
// SIGMA_SHADOW_TRANSLUCENCY denoises IN_SHADOW_TRANSLUCENCY (.x shadow, .yzw translucency, a vec4)
// with the same weights. IN_SHADOWDATA.y is the penumbra radius divided by viewZ, or NRD_FP16_MAX
// where the light is visible ("unknown": the penumbra comes from the occluded neighbours).
#ifndef SIGMA_COMMON_GLSL
#define SIGMA_COMMON_GLSL

#if SIGMA_TRANSLUCENCY
#define SIGMA_TYPE vec4
#else
#define SIGMA_TYPE float
#endif

// One workgroup of the filtering passes covers exactly one tile of gIn_Tiles.
#define SIGMA_TILE_SIZE 16

// Largest kernel radius in pixels (blur and classification agree on it).
#define SIGMA_MAX_PIXEL_RADIUS 32.0

// Pixels a pass reads beyond its kernel radius (dense window 2, temporal statistics 2, rounding).
#define SIGMA_TILE_REACH_MARGIN 5.0

// gIn_Tiles.x values; .y is the largest kernel radius in pixels of the tile's occluded pixels.
#define SIGMA_TILE_UNIFORM 0.0
#define SIGMA_TILE_MIXED 1.0
#define SIGMA_TILE_SKY 2.0

// What a workgroup does (uniform over the group, see _Sigma_GroupTileMode).
#define SIGMA_MODE_SKY 0u      // Only sky pixels: nothing to write.
#define SIGMA_MODE_COPY 1u     // Uniform input in the reach of every kernel: copying is exact.
#define SIGMA_MODE_DENOISE 2u

// Penumbra marker of lit (or invalid) pixels in the internal penumbra textures.
#define SIGMA_UNKNOWN_PENUMBRA (-1.0)

//==================================================================================================
// Inputs, sanitized: non-finite visibility reads as lit, non-finite penumbra as unknown.
//==================================================================================================

float _Sigma_Signal01(float x) { return clamp(_NRD_Sanitize(x, 1.0), 0.0, 1.0); }
vec4 _Sigma_Signal01(vec4 x) { return clamp(_NRD_Sanitize(x, 1.0), vec4(0.0), vec4(1.0)); }

float _Sigma_MaxComponent(float x) { return x; }
float _Sigma_MaxComponent(vec4 x) { return max(max(x.x, x.y), max(x.z, x.w)); }

// Penumbra radius in pixels from IN_SHADOWDATA.y (radius / viewZ), or SIGMA_UNKNOWN_PENUMBRA.
float _Sigma_PenumbraPixels(float penumbraOverViewZ)
{
    // NaN fails the first test; lit pixels carry NRD_FP16_MAX (finite penumbrae stay below half of it).
    if (!(penumbraOverViewZ >= 0.0) || penumbraOverViewZ >= NRD_FP16_MAX * 0.75)
        return SIGMA_UNKNOWN_PENUMBRA;
    return min(penumbraOverViewZ * gProjectY, 16384.0);
}

// Kernel radius in pixels of a penumbra radius in pixels.
float _Sigma_KernelRadius(float penumbraPixels) { return min(penumbraPixels * gBlurRadiusScale, SIGMA_MAX_PIXEL_RADIUS); }

//==================================================================================================
// Tiles.
//==================================================================================================

// Tile modes are stored in an R8 texture (Sigma_SmoothTiles) as mode / 2.
float _Sigma_EncodeTileMode(uint mode) { return float(mode) * 0.5; }

// What this 16x16 workgroup does: one fetch, the same for every invocation of the group.
uint _Sigma_GroupTileMode(texture2D tileModes)
{
    float encoded = texelFetch(sampler2D(tileModes, gNearestClamp), ivec2(gl_WorkGroupID.xy), 0).x;
    return uint(encoded * 2.0 + 0.5);
}

//==================================================================================================
// Kernel.
//==================================================================================================

// Per-pixel, per-frame rotation of the sparse kernel (decorrelates the pattern spatially and over
// time, so temporal stabilization averages different sample sets).
float _Sigma_KernelAngle(ivec2 pixel, uint salt)
{
    uint seed = uint(pixel.x) * 0x8da6b343u ^ uint(pixel.y) * 0xd8163841u ^ (gFrameIndex + salt) * 0xcb1ab31fu;
    return _NRD_Random01(seed) * (2.0 * NRD_PI);
}

// Vogel (golden angle) disk of radius 1: sample i at radius sqrt((i + 0.5) / 8), angle i * 2.39996;
// .z = _Sigma_KernelWeight(r^2), precomputed. With the dense taps around the center, 8 sparse
// samples per pass match 16 in quality after temporal stabilization at half the cost.
const vec3 kSigmaDisk8[8] = vec3[8](
    vec3(0.250000, 0.000000, 0.829029), vec3(-0.319290, 0.292496, 0.569783), vec3(0.048872, -0.556877, 0.391606),
    vec3(0.402444, 0.524918, 0.269146), vec3(-0.738535, -0.130636, 0.184981), vec3(0.699605, -0.445031, 0.127136),
    vec3(-0.234004, 0.870484, 0.087379), vec3(-0.446271, -0.859268, 0.060055));

// Gaussian falloff over the kernel, 'r2' = squared distance in units of the kernel radius.
float _Sigma_KernelWeight(float r2) { return exp(-3.0 * r2); }

// Plane distance of the neighbours of a pixel in 3 MADs each: a neighbour at pixel offset (i, j)
// with viewZ z lies at z * ray(i, j), and dot(Nv, ray(i, j)) is linear in (i, j).
struct SigmaPlane
{
    vec3 k;      // dot(Nv, ray(i, j)) = k.x + k.y * i + k.z * j
    float d;     // dot(Nv, Xv) of the center
    float invTolerance;
};

SigmaPlane _Sigma_Plane(vec2 uv, float viewZ, vec3 Nv)
{
    vec2 ndc = uv * 2.0 - 1.0;
    SigmaPlane p;
    p.k.x = Nv.x * (ndc.x * gFrustum.x + gFrustum.y) + Nv.y * (ndc.y * gFrustum.z + gFrustum.w) + Nv.z * gViewZSign;
    p.k.y = Nv.x * gFrustum.x * 2.0 * gInvResourceSize.x;
    p.k.z = Nv.y * gFrustum.z * 2.0 * gInvResourceSize.y;
    p.d = viewZ * p.k.x;
    p.invTolerance = 1.0 / (gPlaneDistanceSensitivity * viewZ);
    return p;
}

float _Sigma_NeighbourPlaneWeight(SigmaPlane p, int i, int j, float z)
{
    return clamp(1.0 - abs(z * (p.k.x + p.k.y * float(i) + p.k.z * float(j)) - p.d) * p.invTolerance, 0.0, 1.0);
}

float _Sigma_NormalWeight(vec3 centerNormal, vec3 sampleNormal) { return smoothstep(0.5, 0.9, dot(centerNormal, sampleNormal)); }

// Tangent-plane axes (view space) scaled to the kernel's world radius. A penumbra is a world-space
// footprint on the receiver, so the kernel lives on the surface: grazing surfaces get the
// foreshortened screen footprint for free. With a known infinite light the kernel is stretched
// along the light direction projected on the surface, where penumbrae stretch by 1 / cos(N, L).
void _Sigma_KernelBasis(vec3 Nv, float worldRadius, out vec3 T, out vec3 B)
{
    vec3 up = abs(Nv.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    T = normalize(cross(up, Nv));
    B = cross(Nv, T);
    float stretch = 1.0;
    if (gLightDirectionView.w != 0.0)
    {
        vec3 t = cross(gLightDirectionView.xyz, Nv);
        if (dot(t, t) > 1e-6)
        {
            T = normalize(t);
            B = cross(Nv, T);
            stretch = 1.0 / mix(0.4, 1.0, abs(dot(Nv, gLightDirectionView.xyz)));
        }
    }
    T *= worldRadius;
    B *= worldRadius * stretch;
}

// The dense taps of the kernel on the surface. On a surface seen at a grazing angle one pixel row
// spans many pixels' worth of surface, and weighting the dense taps by their pixel distance blurred
// a shadow a pixel thin across the rows (grazing_floor at 960x540: relMSE above the input's). A tap
// at pixel offset (i, j) with viewZ z weighs by its pixel distance or by 0.32 of its distance on the
// tangent plane (in units of the kernel's radius, stretched along the light as the sparse disk),
// whichever is larger: only taps foreshortened more than 3x are weighed by the surface, elsewhere
// the dense window keeps its screen-space support.
struct SigmaDenseKernel
{
    vec3 center;  // Xv
    vec3 ray;     // Xv / viewZ
    vec2 rayStep; // change of the ray per pixel in x and y
    vec3 t;       // T / |T|^2 (T, B: _Sigma_KernelBasis)
    vec3 b;       // B / |B|^2
    bool isGrazing; // foreshortened more than 3x (|N.V| < 0.32): elsewhere the pixel distance is larger
};

SigmaDenseKernel _Sigma_DenseKernel(vec3 Xv, float viewZ, vec3 Nv, float worldRadius)
{
    vec3 T, B;
    _Sigma_KernelBasis(Nv, worldRadius, T, B);
    SigmaDenseKernel k;
    k.center = Xv;
    k.ray = Xv / viewZ;
    k.rayStep = vec2(gFrustum.x * 2.0 * gInvResourceSize.x, gFrustum.z * 2.0 * gInvResourceSize.y);
    k.t = T / max(dot(T, T), 1e-30);
    k.b = B / max(dot(B, B), 1e-30);
    k.isGrazing = abs(dot(Nv, normalize(Xv))) < 0.32;
    return k;
}

// Squared distance in units of the kernel's radius: 'pixelDistance2' (the tap's squared pixel
// distance / radius^2) or 0.1 of the squared tangent-plane distance, whichever is larger.
float _Sigma_DenseDistance2(float pixelDistance2, SigmaDenseKernel k, int i, int j, float z)
{
    if (!k.isGrazing)
        return pixelDistance2;
    vec3 d = z * (k.ray + vec3(k.rayStep.x * float(i), k.rayStep.y * float(j), 0.0)) - k.center;
    float u = dot(d, k.t);
    float v = dot(d, k.b);
    return max(pixelDistance2, 0.1 * (u * u + v * v));
}

// The sparse kernel of a pixel in clip space: a sample at disk offset (x, y) is the view position
// Xv + T' x + B' y, whose clip position is linear in (x, y). The per-pixel rotation is applied to
// the axes once instead of to every sample.
struct SigmaKernel
{
    vec4 clipCenter;
    vec4 clipT;
    vec4 clipB;
};

SigmaKernel _Sigma_Kernel(vec3 Xv, vec3 Nv, float worldRadius, float angle)
{
    vec3 T, B;
    _Sigma_KernelBasis(Nv, worldRadius, T, B);
    float c = cos(angle), s = sin(angle);
    SigmaKernel k;
    k.clipCenter = gViewToClip * vec4(Xv, 1.0);
    k.clipT = gViewToClip * vec4(T * c + B * s, 0.0);
    k.clipB = gViewToClip * vec4(B * c - T * s, 0.0);
    return k;
}

// Pixel of the kernel sample at disk offset 'o', false if it is behind the camera or off the image.
bool _Sigma_KernelSamplePixel(SigmaKernel k, vec2 o, out ivec2 pixel)
{
    vec4 clip = k.clipCenter + k.clipT * o.x + k.clipB * o.y;
    pixel = ivec2(0);
    if (!(clip.w > NRD_EPS))
        return false;
    vec2 p = floor(((clip.xy / clip.w) * 0.5 + 0.5) * vec2(gResourceSize));
    if (any(lessThan(p, vec2(0.0))) || any(greaterThanEqual(p, vec2(gResourceSize))))
        return false;
    pixel = ivec2(p);
    return true;
}

vec3 _Sigma_ViewNormal(vec3 N) { return normalize(transpose(mat3(gViewToWorld)) * N); }

#endif
