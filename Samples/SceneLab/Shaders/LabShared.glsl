// LabShared.glsl - the scene lab's GPU data layout, read by the shaders AND by SceneLab.cpp, so the
// constant block, the scene buffers and the binding numbers cannot drift apart. Only vec4 / uvec4 /
// mat4 members (same offsets in std140, std430 and C++).
#ifndef LAB_SHARED_GLSL
#define LAB_SHARED_GLSL

#ifdef __cplusplus
namespace nrdlab
{
namespace gpu
{
struct vec4 { float x, y, z, w; };
struct uvec4 { uint32_t x, y, z, w; };
struct mat4 { float m[16]; }; // Column-major, as GLSL.
#endif

// Primitive types (LabObject.info.x), LightType (LabLight.info.x): same values as the C++ enums.
#define LAB_PRIM_SPHERE 0
#define LAB_PRIM_BOX 1
#define LAB_PRIM_PLANE 2
#define LAB_PRIM_QUAD 3
#define LAB_PRIM_MESH 4
#define LAB_LIGHT_SUN 0
#define LAB_LIGHT_SPHERE 1
#define LAB_LIGHT_POINT 2

// Signal bits. Each pass is compiled once per signal (LAB_SIGNAL, 0 = the G-buffer pass), and the
// diffuse / specular / gradient passes once per LAB_BOUNCES (1, 2) and LAB_DIRECT (0, 1): a CPU
// implementation runs both sides of a branch on a uniform value, compile-time constants cost nothing.
#define LAB_SIGNAL_SHADOW 2
#define LAB_SIGNAL_TRANSLUCENCY 4
#define LAB_SIGNAL_DIFFUSE 8
#define LAB_SIGNAL_SPECULAR 16
#define LAB_SIGNAL_GRADIENTS 32

// Random number streams: each signal has its own, so the value of one signal does not depend on
// which other signals are rendered with it.
#define LAB_STREAM_SHADOW 1
#define LAB_STREAM_TRANSLUCENCY 2
#define LAB_STREAM_DIFFUSE 3
#define LAB_STREAM_SPECULAR 4
#define LAB_STREAM_STRATUM 5

// viewZ written for sky pixels (> any sane denoisingRange; the denoiser skips them).
#define LAB_SKY_VIEWZ 1e7

// Workgroup of every per-pixel pass. The primary pass packs 8x4 shadow tiles: two per group.
#define LAB_GROUP_X 8
#define LAB_GROUP_Y 8

// Scene size limits (uniform buffer arrays: 128 objects of 128 bytes = 16 KiB, the smallest
// maxUniformBufferRange Vulkan allows).
#define LAB_MAX_OBJECTS 128
#define LAB_MAX_LIGHTS 8

// Set 0 bindings (one set per pipeline; each pass uses a subset).
#define LAB_BINDING_CONSTANTS 0      // uniform LabConstants
#define LAB_BINDING_OBJECTS 1        // uniform LabObject[LAB_MAX_OBJECTS]
#define LAB_BINDING_MATERIALS 2      // uniform LabMaterial[LAB_MAX_OBJECTS]
#define LAB_BINDING_LIGHTS 3         // uniform LabLight[LAB_MAX_LIGHTS]
// LabPrimary outputs (rgba32f unless noted)
#define LAB_BINDING_GBUFFER0 4       // viewZ, mv2d.x, mv2d.y, hit object index (-1 sky)
#define LAB_BINDING_NORMAL_ROUGHNESS 5 // NRD_FrontEnd_PackNormalAndRoughness
#define LAB_BINDING_MV3D 6           // posPrev - pos, 0
#define LAB_BINDING_ALBEDO 7         // diffuse albedo rgb, 0
#define LAB_BINDING_SPEC_ALBEDO 8    // specular directional albedo rgb (demodulation factor), 0
#define LAB_BINDING_SHADOW 9         // shadowData.xy (SIGMA_FrontEnd_PackShadow), visibility, distanceToOccluder
#define LAB_BINDING_TRANSLUCENCY 10  // shadowTranslucency (SIGMA_FrontEnd_MultiLightEnd)
#define LAB_BINDING_TRANSLUCENCY_DATA 11 // shadowData.xy of MultiLightEnd, 0, 0
#define LAB_BINDING_DIFFUSE 12       // radiance rgb, normalized hit distance
#define LAB_BINDING_SPECULAR 13      // radiance rgb, normalized hit distance
#define LAB_BINDING_HIT_MASK 14      // r32ui, ceil(w / 8) x ceil(h / 4): bit (x % 8) + 8 (y % 4) = lit
// LabTruth accumulators (rgba32f, read-write), per signal:
//   shadow:       A = (sum visibility, 0, 0, 0)
//   translucency: A = (sum L rgb, sum mean-over-lights visibility), B = (sum L * V rgb, 0)
//   diffuse, specular: A = (sum radiance rgb, 0), B = (0, sum normalized hit distance, 0, 0)
#define LAB_BINDING_ACC_A 15
#define LAB_BINDING_ACC_B 16
// LabGradients output (rgba32f), ceil(w / 3) x ceil(h / 3)
#define LAB_BINDING_GRADIENTS 17     // |dLum| diffuse, max lum diffuse, |dLum| specular, max lum specular
// Triangle meshes (readonly storage buffers, every pass; one dummy element when the scene has none)
#define LAB_BINDING_BVH_NODES 18     // LabBvhNode[], the BVHs of every mesh one after the other
#define LAB_BINDING_TRIANGLES 19     // LabTriangle[], in BVH leaf order
#define LAB_BINDING_RAY_LIST 20     // uint[]: the rays to trace (nrd::BufferContent::RAY_LIST entries)
#define LAB_BINDING_RAY_ARGS 21     // uint[4]: indirect dispatch (groups, 1, 1), ray count
// LabRayQuery (tests of the traversal): rays in, hits out (storage buffers)
#define LAB_BINDING_RAYS 22          // LabRay[]
#define LAB_BINDING_RAY_HITS 23      // LabRayHit[]
#define LAB_BINDING_NUM 24

// Traversal stack of the mesh BVH: Mesh.h kMaxBvhDepth + 1.
#define LAB_BVH_STACK 64

struct LabConstants
{
    mat4 gWorldToView;     // This frame (column-major, see Scene.h FrameCamera).
    mat4 gViewToClip;
    mat4 gWorldToViewPrev; // Previous frame.
    mat4 gViewToClipPrev;
    vec4 gCameraPos;       // xyz world position, w unused.
    vec4 gCameraPosPrev;
    vec4 gSkyZenith;       // rgb
    vec4 gSkyHorizon;
    vec4 gSkyGround;
    uvec4 gSize;           // width, height, frame index, seed
    uvec4 gCounts;         // objects, lights, shadow light index, 0
    uvec4 gOptions;        // 0, has previous frame (0/1), 0, 0
    vec4 gHitDistParams;   // nrd::HitDistanceParameters (A, B, C, D) of the diffuse / specular .w.
};

// Push constants of LabTruth: which samples this dispatch adds.
struct LabTruthChunk
{
    uvec4 gChunk; // first sample index, sample count, 0, 0
};

// One primitive. World-from-local = rotation | translation, rows in xform[slot * 3 + row]
// (slot 0: this frame, slot 1: previous frame).
struct LabObject
{
    uvec4 info;     // type, material index, 1 if the transform is the same in both slots,
                    // mesh: index of its BVH root in LabBvhNode[]
    vec4 size;      // sphere: radius; box: half extents; quad: half width (x), half depth (z)
    vec4 xform[6];
};

struct LabMaterial
{
    vec4 albedoRoughness;  // albedo rgb, linear roughness
    vec4 emissionMetalness; // emission rgb, metalness
};

// slot 0: this frame, slot 1: previous frame.
struct LabLight
{
    uvec4 info;        // type, enabled (slot 0), enabled (slot 1), 0
    vec4 posDir[2];    // sun: unit direction towards the light, w = cos(angular radius);
                       // sphere / point: position, w = radius (0 for point)
    vec4 intensity[2]; // rgb (0 if disabled), w = tan(angular radius) (sun)
};

// One BVH node in object space. w components hold uints (floatBitsToUint): interior nodes have
// count 0 and children first, first + 1 (indices into LabBvhNode[]); leaves hold triangles
// [first, first + count) of LabTriangle[].
struct LabBvhNode
{
    vec4 boundsMinFirst;
    vec4 boundsMaxCount;
};

// One triangle in object space: p0, edges p1 - p0 and p2 - p0 (Moller-Trumbore), and the unit
// vertex normals (smooth shading).
struct LabTriangle
{
    vec4 p0;
    vec4 e1;
    vec4 e2;
    vec4 n0;
    vec4 n1;
    vec4 n2;
};

// LabRayQuery: one object-space ray against one mesh's BVH, t in (0, tMax).
struct LabRay
{
    vec4 originTMax;
    vec4 direction; // w: 1 = any hit (stop at the first triangle found), 0 = closest hit
};

// LabRayQuery result.
struct LabRayHit
{
    uvec4 triangle; // x: index in LabTriangle[], 0xFFFFFFFF on a miss
    vec4 tUv;       // t, barycentrics of p1 and p2 (0 on a miss)
};

// LabRayQuery push constants: ray count, root node of the mesh, 0, 0.
struct LabRayQuery
{
    uvec4 gQuery;
};

#ifdef __cplusplus
static_assert(sizeof(LabRay) == 32, "LabRay layout");
static_assert(sizeof(LabRayHit) == 32, "LabRayHit layout");
static_assert(sizeof(LabBvhNode) == 32, "LabBvhNode layout");
static_assert(sizeof(LabTriangle) == 96, "LabTriangle layout");
static_assert(sizeof(LabConstants) == 4 * 64 + 6 * 16 + 3 * 16, "LabConstants layout");
static_assert(sizeof(LabObject) == 128, "LabObject layout");
static_assert(sizeof(LabMaterial) == 32, "LabMaterial layout");
static_assert(sizeof(LabLight) == 80, "LabLight layout");
static_assert(sizeof(LabObject) * LAB_MAX_OBJECTS <= 16384, "objects must fit the smallest uniform range");
} // namespace gpu
} // namespace nrdlab
#endif

#endif
