// LabScene.glsl - scene buffers, ray intersection (brute force over a small primitive list, each
// mesh through its BVH), light
// sampling and the per-sample estimators shared by every lab pass, so the noisy input, the ground
// truth and the temporal gradients evaluate exactly the same functions.
//
// "slot" selects the scene state: 0 = this frame, 1 = previous frame (transforms, lights, camera).
#ifndef LAB_SCENE_GLSL
#define LAB_SCENE_GLSL

#include "LabShared.glsl"
#include "LabCommon.glsl"

// Variant of the pass (see LabShared.glsl).
#ifndef LAB_BOUNCES
#  define LAB_BOUNCES 1
#endif
#ifndef LAB_DIRECT
#  define LAB_DIRECT 1
#endif
#include "NRD.glsl"

layout(set = 0, binding = LAB_BINDING_CONSTANTS, std140) uniform LabConstantsBlock
{
    LabConstants c;
};
// The scene lives in uniform buffers: every lane of a group reads the same object at the same
// time, which uniform (scalar) loads serve best, on GPUs and on CPU implementations alike.
layout(set = 0, binding = LAB_BINDING_OBJECTS, std140) uniform LabObjectsBlock
{
    LabObject gObjects[LAB_MAX_OBJECTS];
};
layout(set = 0, binding = LAB_BINDING_MATERIALS, std140) uniform LabMaterialsBlock
{
    LabMaterial gMaterials[LAB_MAX_OBJECTS];
};
layout(set = 0, binding = LAB_BINDING_LIGHTS, std140) uniform LabLightsBlock
{
    LabLight gLights[LAB_MAX_LIGHTS];
};

// Meshes: read by whichever lane hits them, in no common order (storage buffers).
layout(set = 0, binding = LAB_BINDING_BVH_NODES, std430) readonly buffer LabBvhNodesBlock
{
    LabBvhNode gBvhNodes[];
};
layout(set = 0, binding = LAB_BINDING_TRIANGLES, std430) readonly buffer LabTrianglesBlock
{
    LabTriangle gTriangles[];
};

#define LAB_NO_HIT 3.0e38

struct Hit
{
    float t;       // Ray distance, LAB_NO_HIT on a miss.
    int object;    // -1 on a miss.
    vec3 pos;      // World position.
    vec3 N;        // World normal, facing the incoming ray.
    vec3 localPos; // Object-space position (identifies the surface point across frames).
};

struct Surface
{
    vec3 pos;
    vec3 N;
    vec3 diffuseAlbedo;
    vec3 F0;
    float linearRoughness;
    vec3 emission;
};

//==================================================================================================
// Transforms
//==================================================================================================

vec3 ToLocalPoint(uint o, uint slot, vec3 p)
{
    vec4 r0 = gObjects[o].xform[slot * 3u + 0u];
    vec4 r1 = gObjects[o].xform[slot * 3u + 1u];
    vec4 r2 = gObjects[o].xform[slot * 3u + 2u];
    vec3 d = p - vec3(r0.w, r1.w, r2.w);
    // Inverse rotation = transpose: local = R^T d, the rows of R weighted by d.
    return r0.xyz * d.x + r1.xyz * d.y + r2.xyz * d.z;
}

vec3 ToLocalVector(uint o, uint slot, vec3 v)
{
    vec4 r0 = gObjects[o].xform[slot * 3u + 0u];
    vec4 r1 = gObjects[o].xform[slot * 3u + 1u];
    vec4 r2 = gObjects[o].xform[slot * 3u + 2u];
    return r0.xyz * v.x + r1.xyz * v.y + r2.xyz * v.z;
}

vec3 ToWorldPoint(uint o, uint slot, vec3 p)
{
    vec4 r0 = gObjects[o].xform[slot * 3u + 0u];
    vec4 r1 = gObjects[o].xform[slot * 3u + 1u];
    vec4 r2 = gObjects[o].xform[slot * 3u + 2u];
    return vec3(dot(r0.xyz, p) + r0.w, dot(r1.xyz, p) + r1.w, dot(r2.xyz, p) + r2.w);
}

vec3 ToWorldVector(uint o, uint slot, vec3 v)
{
    return vec3(dot(gObjects[o].xform[slot * 3u + 0u].xyz, v), dot(gObjects[o].xform[slot * 3u + 1u].xyz, v),
                dot(gObjects[o].xform[slot * 3u + 2u].xyz, v));
}

//==================================================================================================
// Intersection (object space; transforms are rigid, so distances are the same in world space)
//==================================================================================================

// Returns t in (tMin, tMax) or LAB_NO_HIT, and the local normal (not yet facing the ray).
float IntersectLocal(uint type, vec4 size, vec3 o, vec3 d, float tMin, float tMax, out vec3 n)
{
    n = vec3(0.0, 1.0, 0.0);
    if (type == LAB_PRIM_SPHERE)
    {
        float r = size.x;
        float b = dot(o, d);
        float cc = dot(o, o) - r * r;
        float disc = b * b - cc;
        if (disc < 0.0)
            return LAB_NO_HIT;
        float s = sqrt(disc);
        float t = -b - s;
        if (t <= tMin)
            t = -b + s;
        if (t <= tMin || t >= tMax)
            return LAB_NO_HIT;
        n = (o + t * d) / r;
        return t;
    }
    if (type == LAB_PRIM_BOX)
    {
        vec3 inv = 1.0 / d; // +-Inf for axis-parallel rays: the slab test still works.
        vec3 t0 = (-size.xyz - o) * inv;
        vec3 t1 = (size.xyz - o) * inv;
        vec3 tn = min(t0, t1);
        vec3 tf = max(t0, t1);
        float tNear = max(max(tn.x, tn.y), tn.z);
        float tFar = min(min(tf.x, tf.y), tf.z);
        if (tNear > tFar)
            return LAB_NO_HIT;
        float t = tNear;
        if (t <= tMin)
            t = tFar;
        if (t <= tMin || t >= tMax)
            return LAB_NO_HIT;
        vec3 p = (o + t * d) / size.xyz;
        vec3 a = abs(p);
        if (a.x >= a.y && a.x >= a.z)
            n = vec3(sign(p.x), 0.0, 0.0);
        else if (a.y >= a.z)
            n = vec3(0.0, sign(p.y), 0.0);
        else
            n = vec3(0.0, 0.0, sign(p.z));
        return t;
    }
    // Plane and quad: y = 0 in local space.
    if (abs(d.y) < 1e-12)
        return LAB_NO_HIT;
    float t = -o.y / d.y;
    if (t <= tMin || t >= tMax)
        return LAB_NO_HIT;
    if (type == LAB_PRIM_QUAD)
    {
        vec3 p = o + t * d;
        if (abs(p.x) > size.x || abs(p.z) > size.z)
            return LAB_NO_HIT;
    }
    return t;
}

// Entry distance of the ray into a BVH node's box within [0, tMax], LAB_NO_HIT if it misses.
float BvhNodeEntry(uint node, vec3 o, vec3 invD, float tMax)
{
    vec3 t0 = (gBvhNodes[node].boundsMinFirst.xyz - o) * invD;
    vec3 t1 = (gBvhNodes[node].boundsMaxCount.xyz - o) * invD;
    vec3 tn = min(t0, t1);
    vec3 tf = max(t0, t1);
    float enter = max(max(tn.x, tn.y), max(tn.z, 0.0));
    float exit = min(min(tf.x, tf.y), min(tf.z, tMax));
    return enter <= exit ? enter : LAB_NO_HIT;
}

#ifdef LAB_TRACE_TRIANGLE
// LabRayQuery.comp only: the triangle (index in gTriangles, -1 on a miss) and barycentrics of the
// last IntersectMesh call. Other passes compile without it (their SPIR-V does not change).
int gTracedTriangle;
vec2 gTracedUv;
#endif

// Closest triangle of the BVH at 'root' along o + t d (object space), t in (0, tMax); with
// 'anyHit' the first one found. Returns t or LAB_NO_HIT and, on a hit, the interpolated vertex
// normal turned to the side of the face the ray comes from. Children are visited nearest first;
// the far one waits on the stack with its entry distance, skipped if a closer hit was found since.
// Same triangle test as Mesh.cpp IntersectMesh (the tests compare them).
float IntersectMesh(uint root, vec3 o, vec3 d, float tMax, bool anyHit, out vec3 n)
{
    n = vec3(0.0, 1.0, 0.0);
#ifdef LAB_TRACE_TRIANGLE
    gTracedTriangle = -1;
#endif
    vec3 invD = 1.0 / d;
    float best = tMax;
    int bestTri = -1;
    vec2 bestUv = vec2(0.0);
    uint stackNode[LAB_BVH_STACK];
    float stackEntry[LAB_BVH_STACK];
    uint top = 0u;
    uint node = root;
    float entry = BvhNodeEntry(root, o, invD, best);
    if (entry >= LAB_NO_HIT)
        return LAB_NO_HIT;
    while (true)
    {
        uint first = floatBitsToUint(gBvhNodes[node].boundsMinFirst.w);
        uint count = floatBitsToUint(gBvhNodes[node].boundsMaxCount.w);
        bool descend = false;
        if (count == 0u)
        {
            float tl = BvhNodeEntry(first, o, invD, best);
            float tr = BvhNodeEntry(first + 1u, o, invD, best);
            uint near = tl <= tr ? first : first + 1u;
            float nearEntry = min(tl, tr);
            float farEntry = max(tl, tr);
            if (farEntry < LAB_NO_HIT && top < uint(LAB_BVH_STACK))
            {
                stackNode[top] = near == first ? first + 1u : first;
                stackEntry[top] = farEntry;
                top++;
            }
            if (nearEntry < LAB_NO_HIT)
            {
                node = near;
                descend = true;
            }
        }
        else
        {
            for (uint i = first; i < first + count; i++)
            {
                vec3 p0 = gTriangles[i].p0.xyz;
                vec3 e1 = gTriangles[i].e1.xyz;
                vec3 e2 = gTriangles[i].e2.xyz;
                vec3 pv = cross(d, e2);
                float det = dot(e1, pv);
                if (det == 0.0)
                    continue;
                float invDet = 1.0 / det;
                vec3 s = o - p0;
                float u = dot(s, pv) * invDet;
                if (u < 0.0 || u > 1.0)
                    continue;
                vec3 q = cross(s, e1);
                float v = dot(d, q) * invDet;
                if (v < 0.0 || u + v > 1.0)
                    continue;
                float t = dot(e2, q) * invDet;
                if (t > 0.0 && t < best)
                {
                    best = t;
                    bestTri = int(i);
                    bestUv = vec2(u, v);
                }
            }
            if (anyHit && bestTri >= 0)
                break;
        }
        if (descend)
            continue;
        // Pop the nearest pending node that can still hold a closer hit.
        bool found = false;
        while (top > 0u && !found)
        {
            top--;
            if (stackEntry[top] < best)
            {
                node = stackNode[top];
                found = true;
            }
        }
        if (!found)
            break;
    }
#ifdef LAB_TRACE_TRIANGLE
    gTracedTriangle = bestTri;
    gTracedUv = bestUv;
#endif
    if (bestTri < 0)
        return LAB_NO_HIT;
    uint i = uint(bestTri);
    vec3 ns = gTriangles[i].n0.xyz * (1.0 - bestUv.x - bestUv.y) + gTriangles[i].n1.xyz * bestUv.x +
              gTriangles[i].n2.xyz * bestUv.y;
    ns = normalize(ns);
    vec3 ng = cross(gTriangles[i].e1.xyz, gTriangles[i].e2.xyz);
    n = dot(ng, d) > 0.0 ? -ns : ns;
    return best;
}

// World-space intersection of object i (state 'slot') with o + t d, t in (0, tMax): returns t or
// LAB_NO_HIT and, on a hit, the local normal, local origin and local direction. Spheres and planes
// are tested in world space (no transform of the ray), boxes and quads in object space.
float IntersectObject(uint i, uint slot, vec3 o, vec3 d, float tMax, out vec3 ln, out vec3 lo, out vec3 ld)
{
    uint type = gObjects[i].info.x;
    vec4 size = gObjects[i].size;
    ln = vec3(0.0, 1.0, 0.0);
    lo = vec3(0.0);
    ld = vec3(0.0);
    if (type == LAB_PRIM_SPHERE)
    {
        vec3 centre = vec3(gObjects[i].xform[slot * 3u + 0u].w, gObjects[i].xform[slot * 3u + 1u].w,
                           gObjects[i].xform[slot * 3u + 2u].w);
        vec3 oc = o - centre;
        float b = dot(oc, d);
        float cc = dot(oc, oc) - size.x * size.x;
        float disc = b * b - cc;
        if (disc < 0.0)
            return LAB_NO_HIT;
        float s = sqrt(disc);
        float t = -b - s;
        if (t <= 0.0)
            t = -b + s;
        if (t <= 0.0 || t >= tMax)
            return LAB_NO_HIT;
        // The local frame is only needed on a hit (normal, motion, identity of the point).
        lo = ToLocalPoint(i, slot, o);
        ld = ToLocalVector(i, slot, d);
        ln = (lo + t * ld) / size.x;
        return t;
    }
    if (type == LAB_PRIM_PLANE)
    {
        vec4 r0 = gObjects[i].xform[slot * 3u + 0u];
        vec4 r1 = gObjects[i].xform[slot * 3u + 1u];
        vec4 r2 = gObjects[i].xform[slot * 3u + 2u];
        vec3 n = vec3(r0.y, r1.y, r2.y); // local +Y in world space
        float dn = dot(d, n);
        if (abs(dn) < 1e-12)
            return LAB_NO_HIT;
        float t = dot(vec3(r0.w, r1.w, r2.w) - o, n) / dn;
        if (t <= 0.0 || t >= tMax)
            return LAB_NO_HIT;
        lo = ToLocalPoint(i, slot, o);
        ld = ToLocalVector(i, slot, d);
        return t;
    }
    lo = ToLocalPoint(i, slot, o);
    ld = ToLocalVector(i, slot, d);
    if (type == LAB_PRIM_MESH)
        return IntersectMesh(gObjects[i].info.w, lo, ld, tMax, false, ln);
    return IntersectLocal(type, size, lo, ld, 0.0, tMax, ln);
}

// Closest hit along o + t d, t in (0, tMax), d normalized.
Hit TraceClosest(vec3 o, vec3 d, float tMax, uint slot)
{
    Hit h;
    h.t = LAB_NO_HIT;
    h.object = -1;
    vec3 bestLocalN = vec3(0.0, 1.0, 0.0);
    vec3 bestLocalO = vec3(0.0);
    vec3 bestLocalD = vec3(0.0);
    float best = tMax;
    uint n = c.gCounts.x;
    for (uint i = 0u; i < n; i++)
    {
        vec3 ln, lo, ld;
        float t = IntersectObject(i, slot, o, d, best, ln, lo, ld);
        if (t < best)
        {
            best = t;
            h.object = int(i);
            bestLocalN = ln;
            bestLocalO = lo;
            bestLocalD = ld;
        }
    }
    if (h.object >= 0)
    {
        uint i = uint(h.object);
        h.t = best;
        h.localPos = bestLocalO + best * bestLocalD;
        h.pos = o + best * d;
        vec3 N = normalize(ToWorldVector(i, slot, bestLocalN));
        // Two-sided: face the incoming ray. Mesh normals already face it by their triangle's side
        // (a smooth normal may lean away from the ray near silhouettes and must keep its side).
        if (gObjects[i].info.x != LAB_PRIM_MESH)
            N = dot(N, d) > 0.0 ? -N : N;
        h.N = N;
    }
    return h;
}

// True if anything lies along o + t d, t in (0, tMax) (stops at the first hit found).
bool TraceAny(vec3 o, vec3 d, float tMax, uint slot)
{
    uint n = c.gCounts.x;
    for (uint i = 0u; i < n; i++)
    {
        vec3 ln, lo, ld;
        if (gObjects[i].info.x == LAB_PRIM_MESH)
        {
            // Any triangle will do: the traversal stops at the first one.
            if (IntersectMesh(gObjects[i].info.w, ToLocalPoint(i, slot, o), ToLocalVector(i, slot, d), tMax, true,
                              ln) < tMax)
                return true;
        }
        else if (IntersectObject(i, slot, o, d, tMax, ln, lo, ld) < tMax)
            return true;
    }
    return false;
}

Surface GetSurface(Hit h)
{
    LabMaterial m = gMaterials[gObjects[uint(h.object)].info.y];
    Surface s;
    s.pos = h.pos;
    s.N = h.N;
    float metalness = m.emissionMetalness.w;
    s.diffuseAlbedo = m.albedoRoughness.xyz * (1.0 - metalness);
    s.F0 = mix(vec3(0.04), m.albedoRoughness.xyz, metalness);
    s.linearRoughness = m.albedoRoughness.w;
    s.emission = m.emissionMetalness.xyz;
    return s;
}

// Ray origin pushed off the surface against self-intersection (scaled with the magnitude of p).
vec3 OffsetRay(vec3 p, vec3 N)
{
    float m = max(max(abs(p.x), abs(p.y)), abs(p.z));
    return p + N * (2e-4 * (1.0 + m));
}

//==================================================================================================
// Camera
//==================================================================================================

// Primary ray through the centre of 'pixel' of the camera of 'slot' (no jitter).
void PrimaryRay(uvec2 pixel, uint slot, out vec3 origin, out vec3 dir)
{
    mat4 V = slot == 0u ? c.gWorldToView : c.gWorldToViewPrev;
    mat4 P = slot == 0u ? c.gViewToClip : c.gViewToClipPrev;
    vec2 uv = (vec2(pixel) + 0.5) / vec2(c.gSize.xy);
    vec2 ndc = uv * 2.0 - 1.0;
    vec3 dv = vec3(ndc.x / P[0][0], ndc.y / P[1][1], 1.0);
    // World direction = R^T dv, the rows of R are V's rows.
    vec3 r = vec3(V[0][0], V[1][0], V[2][0]);
    vec3 dn = vec3(V[0][1], V[1][1], V[2][1]);
    vec3 f = vec3(V[0][2], V[1][2], V[2][2]);
    dir = normalize(r * dv.x + dn * dv.y + f * dv.z);
    origin = slot == 0u ? c.gCameraPos.xyz : c.gCameraPosPrev.xyz;
}

float ViewZ(vec3 pos, uint slot)
{
    mat4 V = slot == 0u ? c.gWorldToView : c.gWorldToViewPrev;
    return (V * vec4(pos, 1.0)).z;
}

// uv of a world point (w = 1) or direction (w = 0) in the camera of 'slot'; false behind it.
bool ProjectUv(vec4 p, uint slot, out vec2 uv)
{
    mat4 V = slot == 0u ? c.gWorldToView : c.gWorldToViewPrev;
    mat4 P = slot == 0u ? c.gViewToClip : c.gViewToClipPrev;
    vec4 clip = P * (V * p);
    uv = vec2(0.0);
    if (clip.w <= 1e-8)
        return false;
    uv = clip.xy / clip.w * 0.5 + 0.5;
    return true;
}

//==================================================================================================
// Sky and lights
//==================================================================================================

vec3 SkyRadiance(vec3 d)
{
    return d.y >= 0.0 ? mix(c.gSkyHorizon.rgb, c.gSkyZenith.rgb, d.y) : mix(c.gSkyHorizon.rgb, c.gSkyGround.rgb, -d.y);
}

struct LightSample
{
    vec3 L;          // Unit direction towards the sampled light point.
    float distance;  // To the sampled point (LAB_NO_HIT for the sun).
    vec3 E;          // Unshadowed irradiance estimate: Le * cos * (1 / pdf); 0 if facing away.
    float tanAngularRadius; // As seen from the shaded point (SIGMA_FrontEnd_PackShadow).
    bool enabled;
};

// One sample of light 'li' (state 'slot') from a point with normal N.
LightSample SampleLight(uint li, uint slot, vec3 pos, vec3 N, vec2 u)
{
    LabLight l = gLights[li];
    LightSample s;
    s.enabled = (slot == 0u ? l.info.y : l.info.z) != 0u;
    vec4 pd = l.posDir[slot];
    vec4 I = l.intensity[slot];
    uint type = l.info.x;
    if (type == LAB_LIGHT_SUN)
    {
        // Uniform in the sun's cone; intensity is the irradiance at normal incidence, so
        // Le = I / solidAngle and Le * cos / pdf = I * cos.
        s.L = BasisFromNormal(pd.xyz) * SampleCone(u, pd.w);
        s.distance = LAB_NO_HIT;
        s.E = I.rgb * max(dot(N, s.L), 0.0);
        s.tanAngularRadius = I.w;
    }
    else
    {
        vec3 toLight = pd.xyz - pos;
        float d2 = dot(toLight, toLight);
        float d = sqrt(d2);
        float r = pd.w;
        if (type == LAB_LIGHT_SPHERE && d > r * 1.0001)
        {
            // Uniform in the cone the sphere subtends; Le = I / (pi r^2).
            float sin2Max = r * r / d2;
            float cosMax = sqrt(max(0.0, 1.0 - sin2Max));
            vec3 L = BasisFromNormal(toLight / d) * SampleCone(u, cosMax);
            // Distance to the sphere surface along L.
            float b = dot(L, toLight);
            float cc = d2 - r * r;
            float tHit = b - sqrt(max(0.0, b * b - cc));
            float solidAngle = LAB_TWO_PI * (1.0 - cosMax);
            s.L = L;
            s.distance = tHit;
            s.E = I.rgb / (LAB_PI * r * r) * max(dot(N, L), 0.0) * solidAngle;
            s.tanAngularRadius = r / sqrt(max(cc, 1e-12));
        }
        else
        {
            // Point light (or inside a sphere light: treated as its centre).
            s.L = toLight / max(d, 1e-8);
            s.distance = d;
            s.E = I.rgb * max(dot(N, s.L), 0.0) / max(d2, 1e-8);
            s.tanAngularRadius = 0.0;
        }
    }
    return s;
}

// Distance from 'pos' to the first occluder towards the light sample, NRD_FP16_MAX if visible.
// Surfaces facing away from the sample (and disabled lights) count as occluded at distance 0.
float OccluderDistance(LightSample s, vec3 pos, vec3 N, uint slot)
{
    if (!s.enabled || dot(N, s.L) <= 0.0)
        return 0.0;
    float tMax = s.distance >= LAB_NO_HIT ? LAB_NO_HIT : s.distance * 0.9999;
    Hit h = TraceClosest(OffsetRay(pos, N), s.L, tMax, slot);
    return h.object >= 0 ? h.t : NRD_FP16_MAX;
}

// 1 if the light sample is visible from 'pos', else 0 (same rules as OccluderDistance).
float Visibility(LightSample s, vec3 pos, vec3 N, uint slot)
{
    if (!s.enabled || dot(N, s.L) <= 0.0)
        return 0.0;
    float tMax = s.distance >= LAB_NO_HIT ? LAB_NO_HIT : s.distance * 0.9999;
    return TraceAny(OffsetRay(pos, N), s.L, tMax, slot) ? 0.0 : 1.0;
}

// Direct light at a surface from every light (one sample each) times the BRDF: next-event
// estimation. Lights are not geometry: rays never hit them.
vec3 DirectLight(Surface s, vec3 V, uint slot, inout uint rng)
{
    vec3 sum = vec3(0.0);
    float alpha = max(s.linearRoughness * s.linearRoughness, LAB_SECONDARY_MIN_ALPHA);
    for (uint li = 0u; li < c.gCounts.y; li++)
    {
        LightSample ls = SampleLight(li, slot, s.pos, s.N, Next2(rng));
        if (dot(ls.E, ls.E) <= 0.0)
            continue;
        vec3 f = EvalBrdfCos(s.N, V, ls.L, s.diffuseAlbedo, s.F0, alpha) / max(dot(s.N, ls.L), 1e-8);
        if (dot(f, f) <= 0.0)
            continue;
        sum += f * ls.E * Visibility(ls, s.pos, s.N, slot);
    }
    return sum;
}

//==================================================================================================
// Estimators (one sample each). The noisy input, the truth and the gradients call these.
//==================================================================================================

// Radiance arriving at 'from' along 'dir' (unit): emission + direct light at the hit (+ one more
// diffuse bounce if LAB_BOUNCES >= 2) or the sky. Returns the hit distance in 'hitDistance'
// (NRD_FP16_MAX for the sky).
vec3 IncomingRadiance(vec3 from, vec3 fromN, vec3 dir, uint slot, inout uint rng, out float hitDistance)
{
    Hit h = TraceClosest(OffsetRay(from, fromN), dir, LAB_NO_HIT, slot);
    if (h.object < 0)
    {
        hitDistance = NRD_FP16_MAX;
        return SkyRadiance(dir);
    }
    hitDistance = h.t;
    Surface s = GetSurface(h);
    vec3 L = s.emission + DirectLight(s, -dir, slot, rng);
#if LAB_BOUNCES >= 2
    // Second bounce: cosine-sampled, weight = diffuse albedo (Lambert only).
    vec3 d2 = BasisFromNormal(s.N) * SampleCosine(Next2(rng));
    Hit h2 = TraceClosest(OffsetRay(s.pos, s.N), d2, LAB_NO_HIT, slot);
    vec3 L2;
    if (h2.object < 0)
        L2 = SkyRadiance(d2);
    else
    {
        Surface s2 = GetSurface(h2);
        L2 = s2.emission + DirectLight(s2, -d2, slot, rng);
    }
    L += s.diffuseAlbedo * L2;
#endif
    return L;
}

// Direct light at the primary surface from every light (one sample and one shadow ray each),
// demodulated: diffuse part / diffuse albedo (x) and specular part / specular albedo (y).
// Specular uses alpha >= LAB_DIRECT_MIN_ALPHA (next-event estimation of a near-mirror lobe would
// not converge); the reflection ray of SpecularSample never sees lights.
vec3 DirectDiffuse(Surface s, uint slot, inout uint rng)
{
    vec3 sum = vec3(0.0);
    for (uint li = 0u; li < c.gCounts.y; li++)
    {
        LightSample ls = SampleLight(li, slot, s.pos, s.N, Next2(rng));
        if (dot(ls.E, ls.E) > 0.0)
            sum += ls.E * (Visibility(ls, s.pos, s.N, slot) / LAB_PI);
    }
    return sum;
}

vec3 DirectSpecular(Surface s, vec3 V, uint slot, inout uint rng)
{
    vec3 sum = vec3(0.0);
    float alpha = max(s.linearRoughness * s.linearRoughness, LAB_DIRECT_MIN_ALPHA);
    for (uint li = 0u; li < c.gCounts.y; li++)
    {
        LightSample ls = SampleLight(li, slot, s.pos, s.N, Next2(rng));
        vec3 f = EvalSpecular(s.N, V, ls.L, s.F0, alpha);
        if (dot(ls.E, ls.E) > 0.0 && dot(f, f) > 0.0)
            sum += f * ls.E * Visibility(ls, s.pos, s.N, slot);
    }
    float NoV = max(dot(s.N, V), 1e-4);
    return sum / SpecularAlbedo(s.F0, NoV, s.linearRoughness);
}

// Diffuse: direct light (if LAB_DIRECT) + one cosine-sampled ray; the Lambert weight
// (albedo) is left out (demodulated), so the value is irradiance / pi in expectation.
vec4 DiffuseSample(Surface s, uint slot, inout uint rng)
{
    vec3 direct = LAB_DIRECT != 0 ? DirectDiffuse(s, slot, rng) : vec3(0.0);
    vec3 dir = BasisFromNormal(s.N) * SampleCosine(Next2(rng));
    float hitDistance;
    vec3 L = IncomingRadiance(s.pos, s.N, dir, slot, rng, hitDistance);
    return vec4(direct + L, hitDistance);
}

// Specular: direct light (if LAB_DIRECT) + one GGX VNDF-sampled reflection, weight
// F * G2 / G1, all divided by the specular directional albedo (demodulated). Reflections that end
// below the horizon contribute 0 (hit distance NRD_FP16_MAX).
vec4 SpecularSample(Surface s, vec3 V, uint slot, inout uint rng)
{
    vec3 direct = LAB_DIRECT != 0 ? DirectSpecular(s, V, slot, rng) : vec3(0.0);
    float alpha = max(s.linearRoughness * s.linearRoughness, LAB_MIN_ALPHA);
    mat3 tbn = BasisFromNormal(s.N);
    vec3 Ve = V * tbn; // tangent space (transpose multiply)
    vec2 u = Next2(rng);
    if (Ve.z <= 1e-6)
        return vec4(direct, NRD_FP16_MAX);
    vec3 H = tbn * SampleGgxVndf(Ve, alpha, u);
    vec3 L = reflect(-V, H);
    float NoL = dot(s.N, L);
    if (NoL <= 0.0)
        return vec4(direct, NRD_FP16_MAX);
    float NoV = Ve.z;
    float lambdaV = SmithLambda(NoV, alpha);
    float weightG = (1.0 + lambdaV) / (1.0 + lambdaV + SmithLambda(NoL, alpha));
    vec3 weight = FresnelSchlick(s.F0, dot(V, H)) * weightG / SpecularAlbedo(s.F0, NoV, s.linearRoughness);
    float hitDistance;
    vec3 Li = IncomingRadiance(s.pos, s.N, L, slot, rng, hitDistance);
    return vec4(direct + Li * weight, hitDistance);
}

#endif
