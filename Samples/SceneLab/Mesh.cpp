// Mesh.cpp - see Mesh.h.
#include "Mesh.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <glm/geometric.hpp>
#include <glm/common.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>

namespace nrdlab
{

namespace
{

constexpr uint32_t kBinNum = 16;
constexpr uint32_t kLeafMax = 4;   // A larger leaf only where no split is cheaper.
constexpr uint32_t kLeafHardMax = 16;
constexpr uint32_t kMedianDepth = 32;
constexpr float kTraversalCost = 1.0f; // Relative to one triangle test.

struct Aabb
{
    glm::vec3 lo = glm::vec3(INFINITY), hi = glm::vec3(-INFINITY);

    void Grow(const glm::vec3& p)
    {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void Grow(const Aabb& b)
    {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    float Area() const
    {
        glm::vec3 e = glm::max(hi - lo, glm::vec3(0.0f));
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
};

uint64_t Fnv1a(const void* data, size_t size, uint64_t h)
{
    const auto* p = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < size; i++)
        h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

// Moller-Trumbore; t in (tMin, tMax), both faces.
bool IntersectTriangle(const MeshTriangle& tri, const glm::vec3& o, const glm::vec3& d, float tMin, float tMax,
                       float& t, float& u, float& v)
{
    const glm::vec3 e1 = tri.p[1] - tri.p[0];
    const glm::vec3 e2 = tri.p[2] - tri.p[0];
    const glm::vec3 pv = glm::cross(d, e2);
    const float det = glm::dot(e1, pv);
    if (det == 0.0f)
        return false;
    const float invDet = 1.0f / det;
    const glm::vec3 s = o - tri.p[0];
    u = glm::dot(s, pv) * invDet;
    if (u < 0.0f || u > 1.0f)
        return false;
    const glm::vec3 q = glm::cross(s, e1);
    v = glm::dot(d, q) * invDet;
    if (v < 0.0f || u + v > 1.0f)
        return false;
    t = glm::dot(e2, q) * invDet;
    return t > tMin && t < tMax;
}

bool IntersectBox(const BvhNode& n, const glm::vec3& o, const glm::vec3& invD, float tMin, float tMax)
{
    const glm::vec3 t0 = (n.boundsMin - o) * invD;
    const glm::vec3 t1 = (n.boundsMax - o) * invD;
    const glm::vec3 tn = glm::min(t0, t1), tf = glm::max(t0, t1);
    const float enter = std::max(std::max(tn.x, tn.y), std::max(tn.z, tMin));
    const float exit = std::min(std::min(tf.x, tf.y), std::min(tf.z, tMax));
    return enter <= exit;
}

} // namespace

void BuildBvh(MeshData& mesh)
{
    const auto start = std::chrono::steady_clock::now();
    const uint32_t n = uint32_t(mesh.triangles.size());
    std::vector<Aabb> boxes(n);
    std::vector<glm::vec3> centres(n);
    std::vector<uint32_t> order(n);
    for (uint32_t i = 0; i < n; i++)
    {
        for (const glm::vec3& p : mesh.triangles[i].p)
            boxes[i].Grow(p);
        centres[i] = 0.5f * (boxes[i].lo + boxes[i].hi);
        order[i] = i;
    }

    mesh.nodes.clear();
    mesh.depth = 0;
    mesh.nodes.reserve(n > 0 ? 2 * n : 1);
    mesh.nodes.push_back(BvhNode());
    struct Task
    {
        uint32_t node, first, count, depth;
    };
    std::vector<Task> stack = {{0, 0, n, 0}};
    while (!stack.empty())
    {
        const Task task = stack.back();
        stack.pop_back();
        Aabb bounds, centroidBounds;
        for (uint32_t i = task.first; i < task.first + task.count; i++)
        {
            bounds.Grow(boxes[order[i]]);
            centroidBounds.Grow(centres[order[i]]);
        }
        BvhNode& node = mesh.nodes[task.node];
        node.boundsMin = task.count > 0 ? bounds.lo : glm::vec3(0.0f);
        node.boundsMax = task.count > 0 ? bounds.hi : glm::vec3(0.0f);
        node.first = task.first;
        node.count = task.count;
        if (task.count <= 1)
            continue;

        // Binned SAH over the axis-aligned planes between centroid bins, on all three axes.
        float bestCost = INFINITY;
        int bestAxis = -1;
        uint32_t bestBin = 0;
        const glm::vec3 extent = centroidBounds.hi - centroidBounds.lo;
        for (int axis = 0; axis < 3; axis++)
        {
            if (!(extent[axis] > 0.0f))
                continue;
            Aabb binBox[kBinNum];
            uint32_t binCount[kBinNum] = {};
            const float scale = float(kBinNum) / extent[axis];
            for (uint32_t i = task.first; i < task.first + task.count; i++)
            {
                uint32_t b = std::min(kBinNum - 1, uint32_t((centres[order[i]][axis] - centroidBounds.lo[axis]) * scale));
                binBox[b].Grow(boxes[order[i]]);
                binCount[b]++;
            }
            float rightArea[kBinNum];
            uint32_t rightCount[kBinNum];
            Aabb acc;
            uint32_t count = 0;
            for (uint32_t b = kBinNum - 1; b > 0; b--)
            {
                acc.Grow(binBox[b]);
                count += binCount[b];
                rightArea[b] = acc.Area();
                rightCount[b] = count;
            }
            acc = Aabb();
            count = 0;
            for (uint32_t b = 0; b + 1 < kBinNum; b++)
            {
                acc.Grow(binBox[b]);
                count += binCount[b];
                if (count == 0 || rightCount[b + 1] == 0)
                    continue;
                float cost = acc.Area() * float(count) + rightArea[b + 1] * float(rightCount[b + 1]);
                if (cost < bestCost)
                {
                    bestCost = cost;
                    bestAxis = axis;
                    bestBin = b;
                }
            }
        }
        const float parentArea = bounds.Area();
        const float splitCost = parentArea > 0.0f ? kTraversalCost + bestCost / parentArea : INFINITY;
        uint32_t* begin = order.data() + task.first;
        uint32_t* end = begin + task.count;
        uint32_t* middle = nullptr;
        if (bestAxis >= 0 && (splitCost < float(task.count) || task.count > kLeafMax))
        {
            const float scale = float(kBinNum) / extent[bestAxis];
            middle = std::partition(begin, end, [&](uint32_t t) {
                uint32_t b = std::min(kBinNum - 1,
                                      uint32_t((centres[t][bestAxis] - centroidBounds.lo[bestAxis]) * scale));
                return b <= bestBin;
            });
        }
        else if (task.count > kLeafHardMax)
        {
            // All centroids in one point (or no usable split): halves by index keep leaves small.
            middle = begin + task.count / 2;
        }
        if (middle && task.depth >= kMedianDepth)
        {
            // Deep chains of lopsided SAH splits: median splits from here bound the depth (and the
            // traversal stack) by kMedianDepth + log2(triangles).
            const glm::vec3 e = bounds.hi - bounds.lo;
            const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
            middle = begin + task.count / 2;
            std::nth_element(begin, middle, end, [&](uint32_t a, uint32_t b) { return centres[a][axis] < centres[b][axis]; });
        }
        if (!middle || middle == begin || middle == end)
            continue; // Leaf.
        const uint32_t leftCount = uint32_t(middle - begin);
        const uint32_t left = uint32_t(mesh.nodes.size());
        mesh.nodes.push_back(BvhNode());
        mesh.nodes.push_back(BvhNode());
        mesh.nodes[task.node].first = left;
        mesh.nodes[task.node].count = 0;
        stack.push_back({left, task.first, leftCount, task.depth + 1});
        stack.push_back({left + 1, task.first + leftCount, task.count - leftCount, task.depth + 1});
        mesh.depth = std::max(mesh.depth, task.depth + 1);
    }

    std::vector<MeshTriangle> sorted(n);
    for (uint32_t i = 0; i < n; i++)
        sorted[i] = mesh.triangles[order[i]];
    mesh.triangles = std::move(sorted);
    mesh.boundsMin = mesh.nodes[0].boundsMin;
    mesh.boundsMax = mesh.nodes[0].boundsMax;
    mesh.hash = Fnv1a(mesh.triangles.data(), mesh.triangles.size() * sizeof(MeshTriangle), 0xcbf29ce484222325ull);
    mesh.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::string GetModelsDirectory()
{
    const char* env = std::getenv("NRDLAB_MODELS_DIR");
    return env && *env ? std::string(env) : std::string("/usr/share/assimp/models");
}

bool LoadMesh(const std::string& path, const glm::vec3& scale, MeshData& out, std::string& error)
{
    auto fail = [&](const std::string& why) {
        error = "'" + path + "': " + why;
        return false;
    };
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return fail(std::filesystem::exists(path, ec) ? "not a regular file" : "no such file");
    if (!(std::isfinite(scale.x) && std::isfinite(scale.y) && std::isfinite(scale.z)) || scale.x == 0.0f ||
        scale.y == 0.0f || scale.z == 0.0f)
        return fail("scale must be finite and non-zero");
    try
    {
        Assimp::Importer importer;
        // Node transforms are baked into the vertices; points and lines are skipped below.
        const unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType |
                               aiProcess_GenSmoothNormals;
        const aiScene* scene = importer.ReadFile(path, flags);
        if (!scene)
        {
            std::string why = importer.GetErrorString();
            return fail("not a readable model (" + (why.empty() ? std::string("unknown format") : why) + ")");
        }
        if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
            return fail("incomplete model (truncated or unsupported content)");
        MeshData mesh;
        mesh.file = path;
        for (unsigned m = 0; m < scene->mNumMeshes; m++)
        {
            const aiMesh* am = scene->mMeshes[m];
            if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE))
                continue;
            for (unsigned v = 0; v < am->mNumVertices; v++)
            {
                const aiVector3D& p = am->mVertices[v];
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                    return fail("non-finite vertex position (mesh " + std::to_string(m) + ", vertex " +
                                std::to_string(v) + ")");
            }
            for (unsigned f = 0; f < am->mNumFaces; f++)
            {
                const aiFace& face = am->mFaces[f];
                if (face.mNumIndices != 3)
                    continue;
                MeshTriangle tri;
                bool valid = true;
                for (int k = 0; k < 3; k++)
                {
                    unsigned idx = face.mIndices[k];
                    if (idx >= am->mNumVertices)
                    {
                        valid = false;
                        break;
                    }
                    const aiVector3D& p = am->mVertices[idx];
                    tri.p[k] = glm::vec3(p.x, p.y, p.z) * scale;
                    glm::vec3 nrm(0.0f);
                    if (am->mNormals)
                    {
                        const aiVector3D& an = am->mNormals[idx];
                        // Normals transform with the inverse transpose of the scale.
                        nrm = glm::vec3(an.x, an.y, an.z) / scale;
                    }
                    tri.n[k] = nrm;
                }
                if (!valid)
                    return fail("vertex index out of range (mesh " + std::to_string(m) + ", face " +
                                std::to_string(f) + ")");
                const glm::vec3 ng = glm::cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]);
                const float ngLen = glm::length(ng);
                if (!(ngLen > 0.0f))
                    continue; // Degenerate: no area, never hit.
                for (glm::vec3& nrm : tri.n)
                {
                    const float len = glm::length(nrm);
                    // Missing, zero or non-finite normals: the face normal (flat shading there).
                    nrm = std::isfinite(len) && len > 0.0f ? nrm / len : ng / ngLen;
                }
                mesh.triangles.push_back(tri);
            }
        }
        if (mesh.triangles.empty())
            return fail("no triangles (the model holds only points, lines or degenerate faces)");
        BuildBvh(mesh);
        out = std::move(mesh);
        return true;
    }
    catch (const std::exception& e)
    {
        return fail(std::string("error while reading: ") + e.what());
    }
}

std::shared_ptr<const MeshData> LoadMeshShared(const std::string& path, const glm::vec3& scale, std::string& error)
{
    static std::mutex mutex;
    static std::map<std::string, std::shared_ptr<const MeshData>> cache;
    std::error_code ec;
    const auto time = std::filesystem::last_write_time(path, ec);
    const std::string key = path + "|" + std::to_string(scale.x) + "," + std::to_string(scale.y) + "," +
                            std::to_string(scale.z) + "|" +
                            std::to_string(ec ? 0 : (long long)time.time_since_epoch().count());
    {
        std::lock_guard<std::mutex> lock(mutex);
        auto it = cache.find(key);
        if (it != cache.end())
            return it->second;
    }
    auto mesh = std::make_shared<MeshData>();
    if (!LoadMesh(path, scale, *mesh, error))
        return nullptr;
    std::lock_guard<std::mutex> lock(mutex);
    return cache.emplace(key, std::move(mesh)).first->second;
}

MeshHit IntersectMesh(const MeshData& mesh, const glm::vec3& o, const glm::vec3& d, float tMin, float tMax,
                      bool useBvh)
{
    MeshHit hit;
    float t, u, v;
    if (!useBvh)
    {
        for (size_t i = 0; i < mesh.triangles.size(); i++)
        {
            if (IntersectTriangle(mesh.triangles[i], o, d, tMin, tMax, t, u, v))
            {
                tMax = t;
                hit = {int(i), t, u, v};
            }
        }
        return hit;
    }
    if (mesh.nodes.empty())
        return hit;
    const glm::vec3 invD = 1.0f / d;
    uint32_t stack[kMaxBvhDepth + 1];
    uint32_t top = 0;
    stack[top++] = 0;
    while (top > 0)
    {
        const BvhNode& node = mesh.nodes[stack[--top]];
        if (!IntersectBox(node, o, invD, tMin, tMax))
            continue;
        if (node.count > 0)
        {
            for (uint32_t i = node.first; i < node.first + node.count; i++)
            {
                if (IntersectTriangle(mesh.triangles[i], o, d, tMin, tMax, t, u, v))
                {
                    tMax = t;
                    hit = {int(i), t, u, v};
                }
            }
        }
        else if (top + 2 <= kMaxBvhDepth + 1)
        {
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
        }
    }
    return hit;
}

} // namespace nrdlab
