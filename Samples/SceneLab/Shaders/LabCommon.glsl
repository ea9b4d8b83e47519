// LabCommon.glsl - random numbers, sampling and BRDF of the scene lab's path tracer.
//
// References (facts only):
//   - PCG hash: Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 2020.
//   - Orthonormal basis: Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017.
//   - GGX visible-normal sampling: Heitz, "Sampling the GGX Distribution of Visible Normals",
//     JCGT 2018. Height-correlated Smith masking-shadowing: Heitz, JCGT 2014.
//   - Specular directional albedo: Karis, "Physically Based Shading on Mobile" (2014), analytic fit.
#ifndef LAB_COMMON_GLSL
#define LAB_COMMON_GLSL

#define LAB_PI 3.14159265358979
#define LAB_TWO_PI 6.28318530717959

float Luminance(vec3 c)
{
    return dot(c, vec3(0.2126, 0.7152, 0.0722));
}

//==================================================================================================
// Random numbers: a PCG hash chain seeds a per-sample state; Next01 steps it.
//==================================================================================================

uint Pcg(uint v)
{
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The random sequence of one (pixel, frame, sample, seed, stream): equal inputs, equal numbers.
uint InitRng(uvec2 pixel, uint frame, uint sampleIndex, uint seed, uint stream)
{
    uint h = Pcg(seed ^ Pcg(stream));
    h = Pcg(h ^ frame);
    h = Pcg(h ^ sampleIndex);
    h = Pcg(h ^ pixel.x);
    h = Pcg(h ^ (pixel.y * 0x9E3779B9u));
    return h;
}

float Next01(inout uint rng)
{
    rng = Pcg(rng);
    return float(rng >> 8u) * (1.0 / 16777216.0); // [0, 1)
}

vec2 Next2(inout uint rng)
{
    float a = Next01(rng);
    float b = Next01(rng);
    return vec2(a, b);
}

//==================================================================================================
// Frames and sampling
//==================================================================================================

// Columns T, B, N of a right-handed basis around unit N.
mat3 BasisFromNormal(vec3 N)
{
    float s = N.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + N.z);
    float b = N.x * N.y * a;
    vec3 T = vec3(1.0 + s * N.x * N.x * a, s * b, -s * N.x);
    vec3 B = vec3(b, s + N.y * N.y * a, -N.y);
    return mat3(T, B, N);
}

// Cosine-weighted direction around +Z (pdf = cos / pi).
vec3 SampleCosine(vec2 u)
{
    float r = sqrt(u.x);
    float phi = LAB_TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)));
}

// Uniform direction in the cone of half-angle acos(cosMax) around +Z (pdf = 1 / solid angle).
vec3 SampleCone(vec2 u, float cosMax)
{
    float cosTheta = 1.0 - u.x * (1.0 - cosMax);
    float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));
    float phi = LAB_TWO_PI * u.y;
    return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

//==================================================================================================
// GGX (alpha = linearRoughness^2)
//==================================================================================================

// Smallest alpha: below it the lobe is a mirror for all practical purposes.
#define LAB_MIN_ALPHA 1e-4

// Path regularization: next-event estimation on a near-mirror lobe produces rare, huge samples
// that keep the ground truth from converging. The GGX lobe used for direct light is therefore at
// least this rough: roughness 0.25 at the primary surface, 0.5 at bounce hits (seen through a
// random bounce ray, where a small highlight is found only by chance).
#define LAB_DIRECT_MIN_ALPHA 0.0625
#define LAB_SECONDARY_MIN_ALPHA 0.25

vec3 FresnelSchlick(vec3 F0, float VoH)
{
    float f = pow(1.0 - clamp(VoH, 0.0, 1.0), 5.0);
    return F0 + (1.0 - F0) * f;
}

// Smith Lambda for GGX (isotropic) at cos(theta) = NoX.
float SmithLambda(float NoX, float alpha)
{
    float c2 = max(NoX * NoX, 1e-8);
    float tan2 = max(0.0, 1.0 - c2) / c2;
    return 0.5 * (-1.0 + sqrt(1.0 + alpha * alpha * tan2));
}

float GgxD(float NoH, float alpha)
{
    float a2 = alpha * alpha;
    float d = NoH * NoH * (a2 - 1.0) + 1.0;
    return a2 / (LAB_PI * d * d);
}

// Visible normal around +Z for view Ve (tangent space, Ve.z > 0).
vec3 SampleGgxVndf(vec3 Ve, float alpha, vec2 u)
{
    vec3 Vh = normalize(vec3(alpha * Ve.x, alpha * Ve.y, Ve.z));
    float lensq = Vh.x * Vh.x + Vh.y * Vh.y;
    vec3 T1 = lensq > 0.0 ? vec3(-Vh.y, Vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 T2 = cross(Vh, T1);
    float r = sqrt(u.x);
    float phi = LAB_TWO_PI * u.y;
    float t1 = r * cos(phi);
    float t2 = r * sin(phi);
    float s = 0.5 * (1.0 + Vh.z);
    t2 = (1.0 - s) * sqrt(max(0.0, 1.0 - t1 * t1)) + s * t2;
    vec3 Nh = t1 * T1 + t2 * T2 + sqrt(max(0.0, 1.0 - t1 * t1 - t2 * t2)) * Vh;
    return normalize(vec3(alpha * Nh.x, alpha * Nh.y, max(0.0, Nh.z)));
}

// Directional albedo of the specular lobe (split-sum scale and bias applied to F0).
vec3 SpecularAlbedo(vec3 F0, float NoV, float linearRoughness)
{
    const vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022);
    const vec4 c1 = vec4(1.0, 0.0425, 1.04, -0.04);
    vec4 r = linearRoughness * c0 + c1;
    float a004 = min(r.x * r.x, exp2(-9.28 * NoV)) * r.x + r.y;
    vec2 ab = vec2(-1.04, 1.04) * a004 + r.zw;
    return clamp(F0 * ab.x + ab.y, vec3(0.01), vec3(1.0));
}

// GGX specular BRDF (Schlick Fresnel, height-correlated Smith), without the cosine.
vec3 EvalSpecular(vec3 N, vec3 V, vec3 L, vec3 F0, float alpha)
{
    float NoL = dot(N, L);
    float NoV = dot(N, V);
    if (NoL <= 0.0 || NoV <= 0.0)
        return vec3(0.0);
    vec3 H = normalize(V + L);
    float NoH = max(dot(N, H), 0.0);
    float G2 = 1.0 / (1.0 + SmithLambda(NoV, alpha) + SmithLambda(NoL, alpha));
    return FresnelSchlick(F0, dot(V, H)) * (GgxD(NoH, alpha) * G2 / (4.0 * NoV * NoL));
}

// Lambert + GGX (Schlick Fresnel, height-correlated Smith) times cos(N, L).
vec3 EvalBrdfCos(vec3 N, vec3 V, vec3 L, vec3 diffuseAlbedo, vec3 F0, float alpha)
{
    float NoL = dot(N, L);
    float NoV = dot(N, V);
    if (NoL <= 0.0 || NoV <= 0.0)
        return vec3(0.0);
    vec3 H = normalize(V + L);
    float NoH = max(dot(N, H), 0.0);
    float G2 = 1.0 / (1.0 + SmithLambda(NoV, alpha) + SmithLambda(NoL, alpha));
    vec3 F = FresnelSchlick(F0, dot(V, H));
    vec3 spec = F * (GgxD(NoH, alpha) * G2 / (4.0 * NoV));
    return diffuseAlbedo * (NoL / LAB_PI) + spec;
}

#endif
