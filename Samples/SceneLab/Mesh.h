// Mesh.h - triangle meshes of the scene lab: loading (glTF 2.0, OBJ and the other formats assimp
// reads), a binned-SAH bounding volume hierarchy built on the CPU, and the flattened layout the
// lab's shaders traverse (LabShared.glsl: LabBvhNode, LabTriangle).
//
// References: I. Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies" (2007) for
// the binned SAH build; T. Moller, B. Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection"
// (1997) for the triangle test.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace nrdlab
{

// One node of the flattened BVH. Interior nodes: 'count' = 0, children at 'first' and 'first' + 1.
// Leaves: triangles [first, first + count) of MeshData::triangles (BVH order).
struct BvhNode
{
    glm::vec3 boundsMin = glm::vec3(0.0f);
    uint32_t first = 0;
    glm::vec3 boundsMax = glm::vec3(0.0f);
    uint32_t count = 0;
};

// Bound on the BVH depth, so that a traversal stack of kMaxBvhDepth + 1 entries (LAB_BVH_STACK in
// the shaders) never overflows: 32 SAH levels then median splits, up to 2^31 triangles.
constexpr uint32_t kMaxBvhDepth = 63;

struct MeshTriangle
{
    glm::vec3 p[3]; // Object-space positions (scale applied).
    glm::vec3 n[3]; // Unit per-vertex normals (smooth shading).
};

struct MeshData
{
    std::string file;                    // Resolved path it was loaded from.
    std::vector<MeshTriangle> triangles; // In BVH order.
    std::vector<BvhNode> nodes;          // nodes[0] is the root.
    glm::vec3 boundsMin = glm::vec3(0.0f), boundsMax = glm::vec3(0.0f);
    uint64_t hash = 0;                   // Of the triangles (cache keys).
    double buildMs = 0.0;                // BVH build time.
    uint32_t depth = 0;                  // Of the deepest leaf (root: 0), at most kMaxBvhDepth.
};

// Builds the BVH over 'triangles' (reordered in place) with binned SAH (16 bins per axis, at most
// 4 triangles per leaf unless splitting does not pay). Fills nodes, bounds, hash and buildMs.
void BuildBvh(MeshData& mesh);

// Loads every triangle of the model at 'path' (node transforms applied, 'scale' per axis applied
// after them) and builds its BVH. Returns false and a message naming the file on failure: missing
// or unreadable, not a model assimp can read (including truncated files), no triangles, or
// non-finite positions. Never throws.
bool LoadMesh(const std::string& path, const glm::vec3& scale, MeshData& out, std::string& error);

// Same, shared: a model loaded once with the same path and scale is reused (the lab loads scenes
// many times). The result is never modified after it is returned.
std::shared_ptr<const MeshData> LoadMeshShared(const std::string& path, const glm::vec3& scale, std::string& error);

// Directory searched for model files given by a relative path that is not found next to the scene
// file: NRDLAB_MODELS_DIR from the environment if set, else the folder of Debian's
// assimp-testmodels package (/usr/share/assimp/models).
std::string GetModelsDirectory();

// Closest hit of o + t d, t in (tMin, tMax), in object space. Returns the triangle index (BVH
// order) and t, barycentrics u, v of p1 and p2; -1 on a miss. 'useBvh' false tests every triangle
// (the reference the traversal is checked against).
struct MeshHit
{
    int triangle = -1;
    float t = 0.0f, u = 0.0f, v = 0.0f;
};
MeshHit IntersectMesh(const MeshData& mesh, const glm::vec3& o, const glm::vec3& d, float tMin, float tMax,
                      bool useBvh);

} // namespace nrdlab
