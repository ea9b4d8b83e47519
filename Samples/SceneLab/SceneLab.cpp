// SceneLab.cpp - runs the lab's path tracer (Shaders/Lab*.comp) through nrd::rhi and reads the
// results back: scene upload, one dispatch for the G-buffer + noisy signals, one for the temporal
// gradients, chunked dispatches for the ground truth, and the disk cache in front of all of them.
#include "SceneLab.h"

#include "FrameCache.h"
#include "LabShaders.h"
#include "Mesh.h"
#include "RHI.h"
#include "VulkanContext.h"

#include <cstdint>
#include <cstring>

#include "Shaders/LabShared.glsl"

static_assert(nrdlab::kMaxObjects == LAB_MAX_OBJECTS && nrdlab::kMaxLights == LAB_MAX_LIGHTS,
              "Scene.h limits must match the shaders'");

#include <algorithm>
#include <chrono>
#include <map>
#include <cmath>
#include <cstdlib>

namespace nrdlab
{

namespace rhi = nrd::rhi;

namespace
{

// Bump when the meaning of cached data changes without a shader change.
constexpr const char* kCacheVersion = "nrdlab-cache-2";

constexpr uint32_t kMaxSize = 8192;

// Parts of a frame, each cached on its own so that methods needing different signals share them.
enum Part : uint32_t
{
    PART_GBUFFER,
    PART_SHADOW,
    PART_TRANSLUCENCY,
    PART_DIFFUSE,
    PART_SPECULAR,
    PART_GRADIENTS,
    PART_SHADOW_TRUTH,
    PART_TRANSLUCENCY_TRUTH,
    PART_DIFFUSE_TRUTH,
    PART_SPECULAR_TRUTH,
    PART_NUM
};

const char* const kPartNames[PART_NUM] = {"gbuffer",        "shadow",          "translucency",
                                          "diffuse",        "specular",        "gradients",
                                          "shadow_truth",   "translucency_truth", "diffuse_truth",
                                          "specular_truth"};

struct NamedImage
{
    const char* name;
    Image FrameData::*member;
};

// The images of each part (the shadow hit mask travels as an extra image, see below).
std::vector<NamedImage> PartImages(Part part)
{
    switch (part)
    {
    case PART_GBUFFER:
        return {{"viewZ", &FrameData::viewZ},
                {"normalRoughness", &FrameData::normalRoughness},
                {"motion2d", &FrameData::motion2d},
                {"motion3d", &FrameData::motion3d},
                {"albedo", &FrameData::albedo},
                {"specularAlbedo", &FrameData::specularAlbedo},
                {"objectIndex", &FrameData::objectIndex}};
    case PART_SHADOW:
        return {{"shadowData", &FrameData::shadowData}, {"shadowVisibility", &FrameData::shadowVisibility}};
    case PART_TRANSLUCENCY:
        return {{"translucency", &FrameData::translucency},
                {"translucencyShadowData", &FrameData::translucencyShadowData}};
    case PART_DIFFUSE:
        return {{"diffuse", &FrameData::diffuse}};
    case PART_SPECULAR:
        return {{"specular", &FrameData::specular}};
    case PART_GRADIENTS:
        return {{"gradients", &FrameData::gradients}, {"gradientsRaw", &FrameData::gradientsRaw}};
    case PART_SHADOW_TRUTH:
        return {{"shadowTruth", &FrameData::shadowTruth}};
    case PART_TRANSLUCENCY_TRUTH:
        return {{"translucencyTruth", &FrameData::translucencyTruth}};
    case PART_DIFFUSE_TRUTH:
        return {{"diffuseTruth", &FrameData::diffuseTruth}};
    case PART_SPECULAR_TRUTH:
        return {{"specularTruth", &FrameData::specularTruth}};
    default:
        return {};
    }
}

uint32_t DivideUp(uint32_t x, uint32_t y)
{
    return (x + y - 1) / y;
}

// Channels [first, first + num) of an RGBA float readback as an Image.
Image Extract(const float* rgba, uint32_t w, uint32_t h, uint32_t first, uint32_t num)
{
    Image img(w, h, num);
    for (size_t p = 0; p < img.pixelCount(); p++)
        for (uint32_t ch = 0; ch < num; ch++)
            img.pixels[p * num + ch] = rgba[p * 4 + first + ch];
    return img;
}

LightInfo MakeLightInfo(const LightState& s)
{
    LightInfo info;
    info.type = s.type;
    info.enabled = s.enabled;
    if (s.type == LightType::SUN)
    {
        info.direction[0] = s.direction.x;
        info.direction[1] = s.direction.y;
        info.direction[2] = s.direction.z;
        info.tanOfLightAngularRadius = s.tanAngularRadius;
    }
    info.position[0] = s.position.x;
    info.position[1] = s.position.y;
    info.position[2] = s.position.z;
    info.radius = s.radius;
    info.intensity[0] = s.intensity.x;
    info.intensity[1] = s.intensity.y;
    info.intensity[2] = s.intensity.z;
    return info;
}

void CopyMatrix(gpu::mat4& dst, const float src[16])
{
    std::memcpy(dst.m, src, sizeof(dst.m));
}

gpu::vec4 Vec4(const glm::vec3& v, float w)
{
    return {v.x, v.y, v.z, w};
}


struct Texture
{
    rhi::Texture* texture = nullptr;
    rhi::TextureState state = {};
    uint32_t width = 0, height = 0;
};

// Every texture the lab writes: the noisy outputs and, per signal, the truth accumulators (layouts
// in LabShared.glsl). Created at the frame size on first use.
enum Slot : uint32_t
{
    SLOT_GBUFFER0,
    SLOT_NORMAL_ROUGHNESS,
    SLOT_MV3D,
    SLOT_ALBEDO,
    SLOT_SPEC_ALBEDO,
    SLOT_SHADOW,
    SLOT_HIT_MASK,
    SLOT_TRANSLUCENCY,
    SLOT_TRANSLUCENCY_DATA,
    SLOT_DIFFUSE,
    SLOT_SPECULAR,
    SLOT_GRADIENTS,
    SLOT_ACC_SHADOW_A,
    SLOT_ACC_TRANSLUCENCY_A,
    SLOT_ACC_TRANSLUCENCY_B,
    SLOT_ACC_DIFFUSE_A,
    SLOT_ACC_DIFFUSE_B,
    SLOT_ACC_SPECULAR_A,
    SLOT_ACC_SPECULAR_B,
    SLOT_NUM
};

struct Output
{
    uint32_t binding;
    Slot slot;
};

// One dispatch: a shader variant and where its outputs go.
struct Pass
{
    std::string shader;
    std::vector<Output> outputs;
    bool isTruth = false; // Takes LabTruthChunk push constants.
    bool isRayList = false; // Reads the ray list and its arguments (LabRays.comp).
};

std::string VariantSuffix(const RenderParams& p)
{
    return "_b" + std::to_string(p.bounces) + "d" + std::to_string(p.directLighting ? 1 : 0);
}

// The noisy pass of 'signal' (0 = G-buffer).
Pass NoisyPass(uint32_t signal, const RenderParams& p)
{
    switch (signal)
    {
    case 0:
        return {"LabPrimary_GBuffer",
                {{LAB_BINDING_GBUFFER0, SLOT_GBUFFER0},
                 {LAB_BINDING_NORMAL_ROUGHNESS, SLOT_NORMAL_ROUGHNESS},
                 {LAB_BINDING_MV3D, SLOT_MV3D},
                 {LAB_BINDING_ALBEDO, SLOT_ALBEDO},
                 {LAB_BINDING_SPEC_ALBEDO, SLOT_SPEC_ALBEDO}}};
    case SIGNAL_SHADOW:
        return {"LabPrimary_Shadow", {{LAB_BINDING_SHADOW, SLOT_SHADOW}, {LAB_BINDING_HIT_MASK, SLOT_HIT_MASK}}};
    case SIGNAL_TRANSLUCENCY:
        return {"LabPrimary_Translucency",
                {{LAB_BINDING_TRANSLUCENCY, SLOT_TRANSLUCENCY},
                 {LAB_BINDING_TRANSLUCENCY_DATA, SLOT_TRANSLUCENCY_DATA}}};
    case SIGNAL_DIFFUSE:
        return {"LabPrimary_Diffuse" + VariantSuffix(p), {{LAB_BINDING_DIFFUSE, SLOT_DIFFUSE}}};
    case SIGNAL_SPECULAR:
        return {"LabPrimary_Specular" + VariantSuffix(p), {{LAB_BINDING_SPECULAR, SLOT_SPECULAR}}};
    default:
        return {"LabGradients" + VariantSuffix(p), {{LAB_BINDING_GRADIENTS, SLOT_GRADIENTS}}};
    }
}

Pass TruthPass(uint32_t signal, const RenderParams& p)
{
    Pass pass;
    pass.isTruth = true;
    switch (signal)
    {
    case SIGNAL_SHADOW:
        pass.shader = "LabTruth_Shadow";
        pass.outputs = {{LAB_BINDING_ACC_A, SLOT_ACC_SHADOW_A}};
        break;
    case SIGNAL_TRANSLUCENCY:
        pass.shader = "LabTruth_Translucency";
        pass.outputs = {{LAB_BINDING_ACC_A, SLOT_ACC_TRANSLUCENCY_A}, {LAB_BINDING_ACC_B, SLOT_ACC_TRANSLUCENCY_B}};
        break;
    case SIGNAL_DIFFUSE:
        pass.shader = "LabTruth_Diffuse" + VariantSuffix(p);
        pass.outputs = {{LAB_BINDING_ACC_A, SLOT_ACC_DIFFUSE_A}, {LAB_BINDING_ACC_B, SLOT_ACC_DIFFUSE_B}};
        break;
    default:
        pass.shader = "LabTruth_Specular" + VariantSuffix(p);
        pass.outputs = {{LAB_BINDING_ACC_A, SLOT_ACC_SPECULAR_A}, {LAB_BINDING_ACC_B, SLOT_ACC_SPECULAR_B}};
        break;
    }
    return pass;
}

const uint32_t kTruthSignals[] = {SIGNAL_SHADOW, SIGNAL_TRANSLUCENCY, SIGNAL_DIFFUSE, SIGNAL_SPECULAR};
} // namespace

std::string GetDefaultCacheDirectory()
{
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && *xdg)
        return std::string(xdg) + "/nrd-lab";
    const char* home = std::getenv("HOME");
    if (home && *home)
        return std::string(home) + "/.cache/nrd-lab";
    return "/tmp/nrd-lab";
}

uint64_t HashImage(const Image& image)
{
    uint32_t header[3] = {image.width, image.height, image.channels};
    uint64_t h = Fnv1a64(header, sizeof(header));
    return Fnv1a64(image.pixels.data(), image.pixels.size() * sizeof(float), h);
}

uint64_t HashFrame(const FrameData& f)
{
    const Image* images[] = {&f.viewZ,          &f.normalRoughness,  &f.motion2d,
                             &f.motion3d,       &f.albedo,           &f.specularAlbedo,
                             &f.objectIndex,    &f.shadowData,       &f.shadowVisibility,
                             &f.shadowTruth,    &f.translucency,     &f.translucencyShadowData,
                             &f.translucencyTruth, &f.diffuse,       &f.diffuseTruth,
                             &f.specular,       &f.specularTruth,    &f.gradients,
                             &f.gradientsRaw};
    uint64_t h = 0xcbf29ce484222325ull;
    for (const Image* img : images)
    {
        uint64_t ih = HashImage(*img);
        h = Fnv1a64(&ih, sizeof(ih), h);
    }
    return Fnv1a64(f.shadowHitMask.data(), f.shadowHitMask.size() * sizeof(uint32_t), h);
}

Image SurfaceIds(const FrameData& frame)
{
    const uint32_t w = frame.width, h = frame.height;
    if (!frame.viewZ.isValid() || !frame.motion3d.isValid() || !frame.objectIndex.isValid() ||
        frame.viewZ.width != w || frame.viewZ.height != h)
        return Image();
    const float* V = frame.camera.worldToView;   // column-major: m[column * 4 + row]
    const float* P = frame.camera.viewToClip;
    const float* Vp = frame.camera.worldToViewPrev;
    Image ids(w, h, 3);
    for (uint32_t y = 0; y < h; y++)
    {
        for (uint32_t x = 0; x < w; x++)
        {
            const float z = frame.viewZ.at(x, y, 0);
            ids.at(x, y, 0) = frame.objectIndex.at(x, y, 0);
            ids.at(x, y, 1) = z;
            ids.at(x, y, 2) = z;
            if (z >= kSkyViewZ)
                continue;
            // View-space point (as LabScene.glsl PrimaryRay), to world: camera + R^T v.
            const float ndcX = (float(x) + 0.5f) / float(w) * 2.0f - 1.0f;
            const float ndcY = (float(y) + 0.5f) / float(h) * 2.0f - 1.0f;
            const float v[3] = {ndcX / P[0] * z, ndcY / P[5] * z, z};
            float posPrev[3];
            for (int k = 0; k < 3; k++)
                posPrev[k] = frame.camera.position[k] + V[k * 4 + 0] * v[0] + V[k * 4 + 1] * v[1] +
                             V[k * 4 + 2] * v[2] + frame.motion3d.at(x, y, uint32_t(k));
            ids.at(x, y, 2) = Vp[2] * posPrev[0] + Vp[6] * posPrev[1] + Vp[10] * posPrev[2] + Vp[14];
        }
    }
    return ids;
}

bool IsLitInHitMask(const FrameData& frame, int32_t x, int32_t y)
{
    if (x < 0 || y < 0 || uint32_t(x) >= frame.width || uint32_t(y) >= frame.height)
        return true;
    uint32_t tx = uint32_t(x) / 8, ty = uint32_t(y) / 4;
    if (tx >= frame.shadowHitMaskWidth || ty >= frame.shadowHitMaskHeight)
        return true;
    uint32_t bits = frame.shadowHitMask[size_t(ty) * frame.shadowHitMaskWidth + tx];
    return (bits >> ((uint32_t(x) % 8) + 8 * (uint32_t(y) % 4))) & 1u;
}


// ------------------------------------------------------------------------------------------------

struct SceneLab::Impl
{
    rhi::Device& device;
    SceneLabDesc desc;
    FrameCache cache;
    std::string error;
    std::string shaderHash; // Part of every cache key: a shader change invalidates the cache.

    std::map<std::string, rhi::Pipeline*> pipelines; // By variant name, created on first use.
    rhi::DescriptorPool* descriptorPool = nullptr;
    rhi::CommandBuffer* commandBuffer = nullptr;
    rhi::Buffer* constants = nullptr; // LabConstants
    rhi::Buffer* objects = nullptr;   // LabObject[LAB_MAX_OBJECTS]
    rhi::Buffer* materials = nullptr; // LabMaterial[LAB_MAX_OBJECTS]
    rhi::Buffer* lights = nullptr;    // LabLight[LAB_MAX_LIGHTS]
    rhi::Buffer* bvhNodes = nullptr;  // LabBvhNode[] of every mesh in 'meshes'
    rhi::Buffer* triangles = nullptr; // LabTriangle[]
    std::vector<std::shared_ptr<const MeshData>> meshes; // What bvhNodes / triangles hold, in order.
    std::vector<uint32_t> meshRoots;  // Root node of each of 'meshes'.
    rhi::Buffer* readback = nullptr;
    uint64_t readbackSize = 0;
    rhi::Buffer* rayList = nullptr;   // uint[]: TraceSpecularRays' ray list
    uint64_t rayListSize = 0;
    rhi::Buffer* rayArgs = nullptr;   // uint[4]: its indirect arguments and ray count
    Texture textures[SLOT_NUM];
    bool isValid = false;

    explicit Impl(rhi::Device& d) : device(d)
    {
    }

    ~Impl()
    {
        device.WaitIdle();
        for (Texture& t : textures)
            device.DestroyTexture(t.texture);
        for (auto& p : pipelines)
            device.DestroyPipeline(p.second);
        device.DestroyDescriptorPool(descriptorPool);
        device.DestroyCommandBuffer(commandBuffer);
        for (rhi::Buffer* b : {constants, objects, materials, lights, bvhNodes, triangles, readback, rayList, rayArgs})
            device.DestroyBuffer(b);
    }

    bool Check(rhi::Result r, const char* what)
    {
        if (r == rhi::Result::SUCCESS)
            return true;
        error = std::string(what) + " failed: " + rhi::GetResultString(r);
        return false;
    }

    bool Create()
    {
        uint32_t count = 0;
        const LabShaderBlob* blobs = GetLabShaders(count);
        uint64_t h = 0xcbf29ce484222325ull;
        for (uint32_t i = 0; i < count; i++)
        {
            // Variants that write nothing the cache holds: the ray lists (TraceSpecularRays is never
            // cached) and the traversal query of the tests (TraceMeshRays).
            if (std::strncmp(blobs[i].name, "LabRays_", 8) == 0 || std::strcmp(blobs[i].name, "LabRayQuery") == 0)
                continue;
            h = Fnv1a64(blobs[i].words, blobs[i].size, h);
        }
        char hex[17];
        std::snprintf(hex, sizeof(hex), "%016llx", (unsigned long long)h);
        shaderHash = hex;

        // Enough for every pass of one Render call (sets are freed at the start of the next).
        rhi::DescriptorPoolDesc pool;
        pool.setsMaxNum = 16;
        pool.descriptorsMaxNum[(size_t)rhi::DescriptorType::UNIFORM_BUFFER] = 4 * 16;
        pool.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_TEXTURE] = 5 * 16;
        pool.descriptorsMaxNum[(size_t)rhi::DescriptorType::BUFFER] = 2 * 16;
        if (!Check(device.CreateDescriptorPool(pool, descriptorPool), "CreateDescriptorPool") ||
            !Check(device.CreateCommandBuffer(commandBuffer), "CreateCommandBuffer"))
            return false;

        auto makeBuffer = [&](uint64_t size, const char* name, rhi::Buffer*& out) {
            rhi::BufferDesc bd;
            bd.size = size;
            bd.usage = rhi::BUFFER_USAGE_UNIFORM;
            bd.location = rhi::MemoryLocation::HOST_UPLOAD;
            bd.name = name;
            return Check(device.CreateBuffer(bd, out), "CreateBuffer");
        };
        isValid = makeBuffer(sizeof(gpu::LabConstants), "LabConstants", constants) &&
                  makeBuffer(sizeof(gpu::LabObject) * LAB_MAX_OBJECTS, "LabObjects", objects) &&
                  makeBuffer(sizeof(gpu::LabMaterial) * LAB_MAX_OBJECTS, "LabMaterials", materials) &&
                  makeBuffer(sizeof(gpu::LabLight) * LAB_MAX_LIGHTS, "LabLights", lights) &&
                  UploadMeshes(Scene()) &&
                  GetPipeline(NoisyPass(0, RenderParams())) != nullptr; // compiles the G-buffer pass
        return isValid;
    }

    rhi::Pipeline* GetPipeline(const Pass& pass)
    {
        auto it = pipelines.find(pass.shader);
        if (it != pipelines.end())
            return it->second;
        uint32_t count = 0;
        const LabShaderBlob* blobs = GetLabShaders(count);
        const LabShaderBlob* blob = nullptr;
        for (uint32_t i = 0; i < count && !blob; i++)
            if (pass.shader == blobs[i].name)
                blob = &blobs[i];
        if (!blob)
        {
            error = "no shader variant " + pass.shader;
            return nullptr;
        }
        std::vector<rhi::DescriptorBindingDesc> bindings;
        for (uint32_t b : {LAB_BINDING_CONSTANTS, LAB_BINDING_OBJECTS, LAB_BINDING_MATERIALS, LAB_BINDING_LIGHTS})
            bindings.push_back({b, rhi::DescriptorType::UNIFORM_BUFFER, 1, nullptr});
        for (uint32_t b : {LAB_BINDING_BVH_NODES, LAB_BINDING_TRIANGLES})
            bindings.push_back({b, rhi::DescriptorType::BUFFER, 1, nullptr});
        if (pass.isRayList)
            for (uint32_t b : {LAB_BINDING_RAY_LIST, LAB_BINDING_RAY_ARGS})
                bindings.push_back({b, rhi::DescriptorType::BUFFER, 1, nullptr});
        for (const Output& o : pass.outputs)
            bindings.push_back({o.binding, rhi::DescriptorType::STORAGE_TEXTURE, 1, nullptr});
        rhi::DescriptorSetDesc set = {bindings.data(), uint32_t(bindings.size())};
        rhi::ComputePipelineDesc pd;
        pd.spirv = blob->words;
        pd.spirvSize = blob->size;
        pd.sets = &set;
        pd.setsNum = 1;
        pd.pushConstantsSize = pass.isTruth ? uint32_t(sizeof(gpu::LabTruthChunk)) : 0;
        pd.name = blob->name;
        rhi::Pipeline* pipeline = nullptr;
        if (!Check(device.CreateComputePipeline(pd, pipeline), "CreateComputePipeline"))
            return nullptr;
        pipelines[pass.shader] = pipeline;
        return pipeline;
    }

    static bool IsUint(Slot slot)
    {
        return slot == SLOT_HIT_MASK;
    }

    static void SlotSize(Slot slot, uint32_t w, uint32_t h, uint32_t& outW, uint32_t& outH)
    {
        outW = w;
        outH = h;
        if (slot == SLOT_HIT_MASK)
        {
            outW = DivideUp(w, 8);
            outH = DivideUp(h, 4);
        }
        else if (slot == SLOT_GRADIENTS)
        {
            outW = DivideUp(w, 3);
            outH = DivideUp(h, 3);
        }
    }

    bool EnsureTexture(Slot slot, uint32_t w, uint32_t h)
    {
        uint32_t tw, th;
        SlotSize(slot, w, h, tw, th);
        Texture& t = textures[slot];
        if (t.texture && t.width == tw && t.height == th)
            return true;
        device.DestroyTexture(t.texture);
        t = {};
        rhi::TextureDesc td;
        td.format = IsUint(slot) ? rhi::Format::R32_UINT : rhi::Format::RGBA32_SFLOAT;
        td.width = tw;
        td.height = th;
        td.usage = rhi::TEXTURE_USAGE_STORAGE | rhi::TEXTURE_USAGE_COPY_SOURCE | rhi::TEXTURE_USAGE_COPY_DESTINATION;
        td.name = "LabOutput";
        if (!Check(device.CreateTexture(td, t.texture), "CreateTexture"))
            return false;
        t.width = tw;
        t.height = th;
        return true;
    }

    // Records barriers moving 'slots' to 'after'.
    void Transition(const std::vector<Slot>& slots, rhi::TextureState after)
    {
        std::vector<rhi::TextureBarrier> barriers;
        for (Slot s : slots)
        {
            barriers.push_back({textures[s].texture, textures[s].state, after});
            textures[s].state = after;
        }
        rhi::BarrierDesc bd;
        bd.textures = barriers.data();
        bd.texturesNum = uint32_t(barriers.size());
        device.CmdBarrier(*commandBuffer, bd);
    }

    static std::vector<Slot> SlotsOf(const std::vector<Pass>& passes)
    {
        std::vector<Slot> slots;
        for (const Pass& pass : passes)
            for (const Output& o : pass.outputs)
                slots.push_back(o.slot);
        return slots;
    }

    // Creates the pipelines and textures of 'passes' and a descriptor set for each.
    bool PreparePasses(const std::vector<Pass>& passes, uint32_t w, uint32_t h, std::vector<rhi::DescriptorSet*>& sets)
    {
        sets.clear();
        for (const Pass& pass : passes)
        {
            rhi::Pipeline* pipeline = GetPipeline(pass);
            if (!pipeline)
                return false;
            for (const Output& o : pass.outputs)
                if (!EnsureTexture(o.slot, w, h))
                    return false;
            rhi::DescriptorSet* set = nullptr;
            if (!Check(device.AllocateDescriptorSet(*descriptorPool, *pipeline, 0, set), "AllocateDescriptorSet"))
                return false;
            std::vector<rhi::DescriptorWrite> writes;
            rhi::Buffer* buffers[] = {constants, objects, materials, lights};
            uint32_t bufferBindings[] = {LAB_BINDING_CONSTANTS, LAB_BINDING_OBJECTS, LAB_BINDING_MATERIALS,
                                         LAB_BINDING_LIGHTS};
            for (int i = 0; i < 4; i++)
            {
                rhi::DescriptorWrite wr;
                wr.binding = bufferBindings[i];
                wr.type = rhi::DescriptorType::UNIFORM_BUFFER;
                wr.buffer = buffers[i];
                writes.push_back(wr);
            }
            std::vector<std::pair<uint32_t, rhi::Buffer*>> storage = {{uint32_t(LAB_BINDING_BVH_NODES), bvhNodes},
                                                                      {uint32_t(LAB_BINDING_TRIANGLES), triangles}};
            if (pass.isRayList)
            {
                storage.push_back({uint32_t(LAB_BINDING_RAY_LIST), rayList});
                storage.push_back({uint32_t(LAB_BINDING_RAY_ARGS), rayArgs});
            }
            for (auto [binding, buffer] : storage)
            {
                rhi::DescriptorWrite wr;
                wr.binding = binding;
                wr.type = rhi::DescriptorType::BUFFER;
                wr.buffer = buffer;
                writes.push_back(wr);
            }
            for (const Output& o : pass.outputs)
            {
                rhi::DescriptorWrite wr;
                wr.binding = o.binding;
                wr.type = rhi::DescriptorType::STORAGE_TEXTURE;
                wr.texture = textures[o.slot].texture;
                writes.push_back(wr);
            }
            device.UpdateDescriptorSet(*set, writes.data(), uint32_t(writes.size()));
            sets.push_back(set);
        }
        return true;
    }

    void RecordDispatch(const Pass& pass, rhi::DescriptorSet& set, uint32_t gridW, uint32_t gridH,
                        const gpu::LabTruthChunk* chunk)
    {
        rhi::Pipeline& pipeline = *pipelines[pass.shader];
        device.CmdBindPipeline(*commandBuffer, pipeline);
        device.CmdBindDescriptorSet(*commandBuffer, pipeline, 0, set);
        if (chunk)
            device.CmdPushConstants(*commandBuffer, pipeline, chunk, sizeof(*chunk));
        device.CmdDispatch(*commandBuffer, DivideUp(gridW, LAB_GROUP_X), DivideUp(gridH, LAB_GROUP_Y), 1);
    }

    // Records copies of 'slots' into the readback buffer (grown first if needed; only between
    // submissions) and returns each one's byte offset.
    bool RecordReadback(const std::vector<Slot>& slots, std::vector<uint64_t>& offsets)
    {
        uint64_t total = 0;
        offsets.clear();
        for (Slot s : slots)
        {
            offsets.push_back(total);
            // Copy offsets must be multiples of the texel size: keep every region 16-byte aligned.
            total += (uint64_t(textures[s].width) * textures[s].height * (IsUint(s) ? 4 : 16) + 15) & ~uint64_t(15);
        }
        if (total == 0)
            return true;
        if (total > readbackSize)
        {
            device.DestroyBuffer(readback);
            readback = nullptr;
            readbackSize = 0;
            rhi::BufferDesc bd;
            bd.size = total;
            bd.usage = rhi::BUFFER_USAGE_COPY_DESTINATION;
            bd.location = rhi::MemoryLocation::HOST_READBACK;
            bd.name = "LabReadback";
            if (!Check(device.CreateBuffer(bd, readback), "CreateBuffer (readback)"))
                return false;
            readbackSize = total;
        }
        // Compute writes -> copy reads.
        Transition(slots, {rhi::ACCESS_COPY_SOURCE, rhi::Layout::COPY_SOURCE});
        for (size_t i = 0; i < slots.size(); i++)
            device.CmdCopyTextureToBuffer(*commandBuffer, *readback, offsets[i], *textures[slots[i]].texture);
        // Copy writes -> host reads after the submission completed.
        rhi::BufferBarrier bb = {readback, rhi::ACCESS_COPY_DESTINATION, rhi::ACCESS_HOST_READ};
        rhi::BarrierDesc bd;
        bd.buffers = &bb;
        bd.buffersNum = 1;
        device.CmdBarrier(*commandBuffer, bd);
        return true;
    }

    const float* ReadbackFloats(uint64_t offset)
    {
        return reinterpret_cast<const float*>(static_cast<const uint8_t*>(device.MapBuffer(*readback)) + offset);
    }

    bool UploadMeshes(const Scene& scene);
    bool TraceMeshRays(const Scene& scene, uint32_t objectIndex, const std::vector<SceneLab::MeshRay>& rays,
                       std::vector<MeshHit>& hits);
    void Upload(const Scene& scene, const SceneState& cur, const SceneState& prev, const FrameCamera& cam,
                const RenderParams& p, uint32_t seed);
    void StoreNoisy(Slot slot, const float* d, uint32_t w, uint32_t h, FrameData& out);
    std::string CheckParams(const Scene& scene, const RenderParams& p) const;
    bool Render(const Scene& scene, const RenderParams& p, FrameData& out, std::string& err);
    bool TraceSpecularRays(const Scene& scene, const RenderParams& p, const std::vector<uint32_t>& rays, Image& out,
                           std::string& err);
};

// The meshes of 'scene' -> bvhNodes / triangles, concatenated (node and triangle indices offset);
// kept while the next scene uses the same meshes. Without meshes the buffers hold one zero element.
bool SceneLab::Impl::UploadMeshes(const Scene& scene)
{
    std::vector<std::shared_ptr<const MeshData>> wanted;
    for (const Object& o : scene.objects)
        if (o.type == PrimitiveType::MESH && o.mesh && std::find(wanted.begin(), wanted.end(), o.mesh) == wanted.end())
            wanted.push_back(o.mesh);
    if (bvhNodes && wanted == meshes)
        return true;
    size_t nodeNum = 0, triangleNum = 0;
    for (const auto& m : wanted)
    {
        nodeNum += m->nodes.size();
        triangleNum += m->triangles.size();
    }
    device.WaitIdle();
    device.DestroyBuffer(bvhNodes);
    device.DestroyBuffer(triangles);
    bvhNodes = triangles = nullptr;
    meshes.clear();
    meshRoots.clear();
    auto makeBuffer = [&](uint64_t size, const char* name, rhi::Buffer*& out) {
        rhi::BufferDesc bd;
        bd.size = size;
        bd.usage = rhi::BUFFER_USAGE_STORAGE;
        bd.location = rhi::MemoryLocation::HOST_UPLOAD;
        bd.name = name;
        return Check(device.CreateBuffer(bd, out), "CreateBuffer");
    };
    if (!makeBuffer(sizeof(gpu::LabBvhNode) * std::max<size_t>(nodeNum, 1), "LabBvhNodes", bvhNodes) ||
        !makeBuffer(sizeof(gpu::LabTriangle) * std::max<size_t>(triangleNum, 1), "LabTriangles", triangles))
        return false;
    auto* nodes = static_cast<gpu::LabBvhNode*>(device.MapBuffer(*bvhNodes));
    auto* tris = static_cast<gpu::LabTriangle*>(device.MapBuffer(*triangles));
    std::memset(nodes, 0, sizeof(gpu::LabBvhNode));
    std::memset(tris, 0, sizeof(gpu::LabTriangle));
    auto bits = [](uint32_t u) {
        float f;
        std::memcpy(&f, &u, sizeof(f));
        return f;
    };
    uint32_t nodeBase = 0, triangleBase = 0;
    for (const auto& m : wanted)
    {
        for (const BvhNode& n : m->nodes)
        {
            uint32_t first = n.first + (n.count > 0 ? triangleBase : nodeBase);
            *nodes++ = {{n.boundsMin.x, n.boundsMin.y, n.boundsMin.z, bits(first)},
                        {n.boundsMax.x, n.boundsMax.y, n.boundsMax.z, bits(n.count)}};
        }
        for (const MeshTriangle& t : m->triangles)
        {
            const glm::vec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0]; // as Mesh.cpp IntersectMesh
            *tris++ = {{t.p[0].x, t.p[0].y, t.p[0].z, 0.0f}, {e1.x, e1.y, e1.z, 0.0f}, {e2.x, e2.y, e2.z, 0.0f},
                       {t.n[0].x, t.n[0].y, t.n[0].z, 0.0f}, {t.n[1].x, t.n[1].y, t.n[1].z, 0.0f},
                       {t.n[2].x, t.n[2].y, t.n[2].z, 0.0f}};
        }
        meshRoots.push_back(nodeBase);
        nodeBase += uint32_t(m->nodes.size());
        triangleBase += uint32_t(m->triangles.size());
    }
    meshes = std::move(wanted);
    return true;
}

bool SceneLab::Impl::TraceMeshRays(const Scene& scene, uint32_t objectIndex, const std::vector<SceneLab::MeshRay>& rays,
                                   std::vector<MeshHit>& hits)
{
    hits.clear();
    if (objectIndex >= scene.objects.size() || scene.objects[objectIndex].type != PrimitiveType::MESH ||
        !scene.objects[objectIndex].mesh)
    {
        error = "TraceMeshRays: object " + std::to_string(objectIndex) + " is not a mesh";
        return false;
    }
    if (rays.empty())
        return true;
    if (!UploadMeshes(scene))
        return false;
    const size_t mesh =
        size_t(std::find(meshes.begin(), meshes.end(), scene.objects[objectIndex].mesh) - meshes.begin());
    uint32_t triangleBase = 0;
    for (size_t m = 0; m < mesh; m++)
        triangleBase += uint32_t(meshes[m]->triangles.size());

    const char* kName = "LabRayQuery";
    rhi::Pipeline* pipeline = pipelines.count(kName) ? pipelines[kName] : nullptr;
    if (!pipeline)
    {
        uint32_t count = 0;
        const LabShaderBlob* blobs = GetLabShaders(count);
        const LabShaderBlob* blob = nullptr;
        for (uint32_t i = 0; i < count && !blob; i++)
            if (std::strcmp(blobs[i].name, kName) == 0)
                blob = &blobs[i];
        if (!blob)
        {
            error = std::string("no shader variant ") + kName;
            return false;
        }
        std::vector<rhi::DescriptorBindingDesc> bindings;
        for (uint32_t b : {LAB_BINDING_CONSTANTS, LAB_BINDING_OBJECTS, LAB_BINDING_MATERIALS, LAB_BINDING_LIGHTS})
            bindings.push_back({b, rhi::DescriptorType::UNIFORM_BUFFER, 1, nullptr});
        for (uint32_t b : {LAB_BINDING_BVH_NODES, LAB_BINDING_TRIANGLES, LAB_BINDING_RAYS})
            bindings.push_back({b, rhi::DescriptorType::BUFFER, 1, nullptr});
        bindings.push_back({LAB_BINDING_RAY_HITS, rhi::DescriptorType::STORAGE_BUFFER, 1, nullptr});
        rhi::DescriptorSetDesc set = {bindings.data(), uint32_t(bindings.size())};
        rhi::ComputePipelineDesc pd;
        pd.spirv = blob->words;
        pd.spirvSize = blob->size;
        pd.sets = &set;
        pd.setsNum = 1;
        pd.pushConstantsSize = uint32_t(sizeof(gpu::LabRayQuery));
        pd.name = kName;
        if (!Check(device.CreateComputePipeline(pd, pipeline), "CreateComputePipeline"))
            return false;
        pipelines[kName] = pipeline;
    }

    // Rays in (host upload), hits out (host readback), in a descriptor pool of their own.
    rhi::Buffer* rayBuffer = nullptr;
    rhi::Buffer* hitBuffer = nullptr;
    rhi::DescriptorPool* pool = nullptr;
    auto cleanUp = [&]()
    {
        device.WaitIdle();
        device.DestroyBuffer(rayBuffer);
        device.DestroyBuffer(hitBuffer);
        device.DestroyDescriptorPool(pool);
    };
    rhi::BufferDesc bd;
    bd.size = sizeof(gpu::LabRay) * rays.size();
    bd.usage = rhi::BUFFER_USAGE_STORAGE;
    bd.location = rhi::MemoryLocation::HOST_UPLOAD;
    bd.name = "LabRays";
    rhi::BufferDesc hd = bd;
    hd.size = sizeof(gpu::LabRayHit) * rays.size();
    hd.location = rhi::MemoryLocation::HOST_READBACK;
    hd.name = "LabRayHits";
    rhi::DescriptorPoolDesc poolDesc;
    poolDesc.setsMaxNum = 1;
    poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::UNIFORM_BUFFER] = 4;
    poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::BUFFER] = 3;
    poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_BUFFER] = 1;
    rhi::DescriptorSet* set = nullptr;
    if (!Check(device.CreateBuffer(bd, rayBuffer), "CreateBuffer (rays)") ||
        !Check(device.CreateBuffer(hd, hitBuffer), "CreateBuffer (ray hits)") ||
        !Check(device.CreateDescriptorPool(poolDesc, pool), "CreateDescriptorPool") ||
        !Check(device.AllocateDescriptorSet(*pool, *pipeline, 0, set), "AllocateDescriptorSet"))
    {
        cleanUp();
        return false;
    }
    auto* gpuRays = static_cast<gpu::LabRay*>(device.MapBuffer(*rayBuffer));
    for (size_t i = 0; i < rays.size(); i++)
        gpuRays[i] = {{rays[i].origin.x, rays[i].origin.y, rays[i].origin.z, rays[i].tMax},
                      {rays[i].direction.x, rays[i].direction.y, rays[i].direction.z, rays[i].anyHit ? 1.0f : 0.0f}};
    std::vector<rhi::DescriptorWrite> writes;
    const std::pair<uint32_t, rhi::Buffer*> uniforms[] = {{LAB_BINDING_CONSTANTS, constants},
                                                          {LAB_BINDING_OBJECTS, objects},
                                                          {LAB_BINDING_MATERIALS, materials},
                                                          {LAB_BINDING_LIGHTS, lights}};
    for (const auto& [binding, buffer] : uniforms)
    {
        rhi::DescriptorWrite wr;
        wr.binding = binding;
        wr.type = rhi::DescriptorType::UNIFORM_BUFFER;
        wr.buffer = buffer;
        writes.push_back(wr);
    }
    const std::pair<uint32_t, rhi::Buffer*> storage[] = {
        {LAB_BINDING_BVH_NODES, bvhNodes}, {LAB_BINDING_TRIANGLES, triangles}, {LAB_BINDING_RAYS, rayBuffer}};
    for (const auto& [binding, buffer] : storage)
    {
        rhi::DescriptorWrite wr;
        wr.binding = binding;
        wr.type = rhi::DescriptorType::BUFFER;
        wr.buffer = buffer;
        writes.push_back(wr);
    }
    rhi::DescriptorWrite out;
    out.binding = LAB_BINDING_RAY_HITS;
    out.type = rhi::DescriptorType::STORAGE_BUFFER;
    out.buffer = hitBuffer;
    writes.push_back(out);
    device.UpdateDescriptorSet(*set, writes.data(), uint32_t(writes.size()));

    const uint32_t meshRoot = meshRoots[mesh];
    bool ok = Check(device.BeginCommandBuffer(*commandBuffer), "BeginCommandBuffer");
    if (ok)
    {
        device.CmdBindPipeline(*commandBuffer, *pipeline);
        device.CmdBindDescriptorSet(*commandBuffer, *pipeline, 0, *set);
        gpu::LabRayQuery query = {{uint32_t(rays.size()), meshRoot, 0u, 0u}};
        device.CmdPushConstants(*commandBuffer, *pipeline, &query, sizeof(query));
        device.CmdDispatch(*commandBuffer, DivideUp(uint32_t(rays.size()), 64), 1, 1);
        // Shader writes -> host reads after the submission completed.
        rhi::BufferBarrier bb = {hitBuffer, rhi::ACCESS_SHADER_READ_WRITE, rhi::ACCESS_HOST_READ};
        rhi::BarrierDesc barrier;
        barrier.buffers = &bb;
        barrier.buffersNum = 1;
        device.CmdBarrier(*commandBuffer, barrier);
        ok = Check(device.EndCommandBuffer(*commandBuffer), "EndCommandBuffer") &&
             Check(device.SubmitAndWait(*commandBuffer), "SubmitAndWait");
    }
    if (ok)
    {
        const auto* gpuHits = static_cast<const gpu::LabRayHit*>(device.MapBuffer(*hitBuffer));
        hits.resize(rays.size());
        for (size_t i = 0; i < rays.size(); i++)
        {
            const gpu::LabRayHit& g = gpuHits[i];
            if (g.triangle.x != 0xFFFFFFFFu)
                hits[i] = {int(g.triangle.x - triangleBase), g.tUv.x, g.tUv.y, g.tUv.z};
        }
    }
    cleanUp();
    return ok;
}

void SceneLab::Impl::Upload(const Scene& scene, const SceneState& cur, const SceneState& prev, const FrameCamera& cam,
                            const RenderParams& p, uint32_t seed)
{
    gpu::LabConstants k = {};
    CopyMatrix(k.gWorldToView, cam.worldToView);
    CopyMatrix(k.gViewToClip, cam.viewToClip);
    CopyMatrix(k.gWorldToViewPrev, cam.worldToViewPrev);
    CopyMatrix(k.gViewToClipPrev, cam.viewToClipPrev);
    k.gCameraPos = {cam.position[0], cam.position[1], cam.position[2], 0.0f};
    k.gCameraPosPrev = {cam.positionPrev[0], cam.positionPrev[1], cam.positionPrev[2], 0.0f};
    k.gSkyZenith = Vec4(scene.sky.zenith, 0.0f);
    k.gSkyHorizon = Vec4(scene.sky.horizon, 0.0f);
    k.gSkyGround = Vec4(scene.sky.ground, 0.0f);
    k.gSize = {p.width, p.height, p.frameIndex, seed};
    k.gCounts = {uint32_t(scene.objects.size()), uint32_t(scene.lights.size()), p.lightIndex, 0u};
    k.gOptions = {0u, p.frameIndex > 0 ? 1u : 0u, 0u, 0u};
    const nrd::HitDistanceParameters& hd = p.hitDistanceParameters;
    k.gHitDistParams = {hd.A, hd.B, hd.C, hd.D};
    std::memcpy(device.MapBuffer(*constants), &k, sizeof(k));

    auto* objs = static_cast<gpu::LabObject*>(device.MapBuffer(*objects));
    auto* mats = static_cast<gpu::LabMaterial*>(device.MapBuffer(*materials));
    for (size_t i = 0; i < scene.objects.size(); i++)
    {
        const Object& o = scene.objects[i];
        gpu::LabObject g = {};
        g.info = {uint32_t(o.type), uint32_t(i), 0u, 0u};
        if (o.type == PrimitiveType::MESH)
            g.info.w = meshRoots[size_t(std::find(meshes.begin(), meshes.end(), o.mesh) - meshes.begin())];
        if (o.type == PrimitiveType::SPHERE)
            g.size = {o.radius, o.radius, o.radius, 0.0f};
        else
            g.size = {0.5f * o.size.x, 0.5f * o.size.y, 0.5f * o.size.z, 0.0f};
        const ObjectState* states[2] = {&cur.objects[i], &prev.objects[i]};
        for (uint32_t slot = 0; slot < 2; slot++)
        {
            const glm::mat3& R = states[slot]->rotation;
            const glm::vec3& T = states[slot]->position;
            for (int row = 0; row < 3; row++)
                g.xform[slot * 3 + uint32_t(row)] = {R[0][row], R[1][row], R[2][row], T[row]};
        }
        g.info.z = std::memcmp(g.xform, g.xform + 3, sizeof(gpu::vec4) * 3) == 0 ? 1u : 0u;
        objs[i] = g;
        const Material& m = o.material;
        mats[i].albedoRoughness = Vec4(m.albedo, m.roughness);
        mats[i].emissionMetalness = Vec4(m.emission, m.metalness);
    }

    auto* ls = static_cast<gpu::LabLight*>(device.MapBuffer(*lights));
    for (size_t i = 0; i < scene.lights.size(); i++)
    {
        const LightState* states[2] = {&cur.lights[i], &prev.lights[i]};
        gpu::LabLight g = {};
        g.info = {uint32_t(scene.lights[i].type), states[0]->enabled ? 1u : 0u, states[1]->enabled ? 1u : 0u, 0u};
        for (uint32_t slot = 0; slot < 2; slot++)
        {
            const LightState& s = *states[slot];
            if (s.type == LightType::SUN)
                g.posDir[slot] = Vec4(s.direction, s.cosAngularRadius);
            else
                g.posDir[slot] = Vec4(s.position, s.radius);
            g.intensity[slot] = Vec4(s.intensity, s.tanAngularRadius);
        }
        ls[i] = g;
    }
}

void SceneLab::Impl::StoreNoisy(Slot slot, const float* d, uint32_t w, uint32_t h, FrameData& out)
{
    switch (slot)
    {
    case SLOT_GBUFFER0:
        out.viewZ = Extract(d, w, h, 0, 1);
        out.motion2d = Extract(d, w, h, 1, 2);
        out.objectIndex = Extract(d, w, h, 3, 1);
        break;
    case SLOT_NORMAL_ROUGHNESS:
        out.normalRoughness = Extract(d, w, h, 0, 4);
        break;
    case SLOT_MV3D:
        out.motion3d = Extract(d, w, h, 0, 3);
        break;
    case SLOT_ALBEDO:
        out.albedo = Extract(d, w, h, 0, 3);
        break;
    case SLOT_SPEC_ALBEDO:
        out.specularAlbedo = Extract(d, w, h, 0, 3);
        break;
    case SLOT_SHADOW:
        out.shadowData = Extract(d, w, h, 0, 2);
        out.shadowVisibility = Extract(d, w, h, 2, 1);
        break;
    case SLOT_HIT_MASK:
        out.shadowHitMaskWidth = DivideUp(w, 8);
        out.shadowHitMaskHeight = DivideUp(h, 4);
        out.shadowHitMask.resize(size_t(out.shadowHitMaskWidth) * out.shadowHitMaskHeight);
        std::memcpy(out.shadowHitMask.data(), d, out.shadowHitMask.size() * sizeof(uint32_t));
        break;
    case SLOT_TRANSLUCENCY:
        out.translucency = Extract(d, w, h, 0, 4);
        break;
    case SLOT_TRANSLUCENCY_DATA:
        out.translucencyShadowData = Extract(d, w, h, 0, 2);
        break;
    case SLOT_DIFFUSE:
        out.diffuse = Extract(d, w, h, 0, 4);
        break;
    case SLOT_SPECULAR:
        out.specular = Extract(d, w, h, 0, 4);
        break;
    case SLOT_GRADIENTS:
    {
        uint32_t gw = DivideUp(w, 3), gh = DivideUp(h, 3);
        out.gradientsRaw = Extract(d, gw, gh, 0, 4);
        out.gradients = Image(gw, gh, 2);
        for (size_t px = 0; px < out.gradients.pixelCount(); px++)
            for (uint32_t ch = 0; ch < 2; ch++)
            {
                float delta = d[px * 4 + ch * 2], maxLum = d[px * 4 + ch * 2 + 1];
                out.gradients.pixels[px * 2 + ch] = maxLum > 0.0f ? std::min(delta / maxLum, 1.0f) : 0.0f;
            }
        break;
    }
    default:
        break;
    }
}

// What Render and TraceSpecularRays both need of their parameters; empty if they are fine.
std::string SceneLab::Impl::CheckParams(const Scene& scene, const RenderParams& p) const
{
    if (!isValid)
        return "the scene lab is not valid: " + error;
    if (p.width < 1 || p.height < 1 || p.width > kMaxSize || p.height > kMaxSize)
        return "size " + std::to_string(p.width) + "x" + std::to_string(p.height) + " out of range (1.." +
               std::to_string(kMaxSize) + ")";
    if (p.bounces < 1 || p.bounces > 2)
        return "bounces must be 1 or 2";
    if (scene.objects.size() > kMaxObjects || scene.lights.size() > kMaxLights)
        return "the scene has more objects or lights than the path tracer supports";
    for (size_t i = 0; i < scene.objects.size(); i++)
        if (scene.objects[i].type == PrimitiveType::MESH && (!scene.objects[i].mesh || scene.objects[i].mesh->nodes.empty()))
            return "object " + std::to_string(i) + " is a mesh without loaded triangles";
    return std::string();
}

bool SceneLab::Impl::Render(const Scene& scene, const RenderParams& p, FrameData& out, std::string& err)
{
    using Clock = std::chrono::steady_clock;
    auto fail = [&](const std::string& message) {
        err = message;
        return false;
    };

    // Parameters.
    std::string problem = CheckParams(scene, p);
    if (!problem.empty())
        return fail(problem);
    if (p.signals & ~uint32_t(SIGNAL_ALL))
        return fail("unknown signal bits in RenderParams::signals");
    if (p.truthSpp > 0 && p.truthChunkSpp == 0)
        return fail("truthChunkSpp must be at least 1");
    if ((p.signals & SIGNAL_SHADOW) && p.lightIndex >= scene.lights.size())
        return fail("lightIndex " + std::to_string(p.lightIndex) + " out of range: the scene has " +
                    std::to_string(scene.lights.size()) + " light(s)");

    const uint32_t w = p.width, h = p.height;
    const uint32_t seed = p.seed == kSceneSeed ? scene.seed : p.seed;
    const SceneState cur = EvaluateScene(scene, p.frameIndex);
    const SceneState prev = EvaluateScene(scene, p.frameIndex > 0 ? p.frameIndex - 1 : 0);

    out = FrameData();
    out.width = w;
    out.height = h;
    out.frameIndex = p.frameIndex;
    out.seed = seed;
    out.signals = p.signals;
    out.truthSpp = p.truthSpp;
    out.camera = ComputeFrameCamera(scene, p.frameIndex, w, h);
    out.lightIndex = p.lightIndex;
    for (const LightState& ls : cur.lights)
        out.lights.push_back(MakeLightInfo(ls));
    if (p.lightIndex < out.lights.size())
        out.light = out.lights[p.lightIndex];

    // Which parts are wanted, and which the cache already has.
    bool wanted[PART_NUM] = {};
    wanted[PART_GBUFFER] = true;
    wanted[PART_SHADOW] = (p.signals & SIGNAL_SHADOW) != 0;
    wanted[PART_TRANSLUCENCY] = (p.signals & SIGNAL_TRANSLUCENCY) != 0;
    wanted[PART_DIFFUSE] = (p.signals & SIGNAL_DIFFUSE) != 0;
    wanted[PART_SPECULAR] = (p.signals & SIGNAL_SPECULAR) != 0;
    wanted[PART_GRADIENTS] = (p.signals & SIGNAL_GRADIENTS) != 0;
    wanted[PART_SHADOW_TRUTH] = wanted[PART_SHADOW] && p.truthSpp > 0;
    wanted[PART_TRANSLUCENCY_TRUTH] = wanted[PART_TRANSLUCENCY] && p.truthSpp > 0;
    wanted[PART_DIFFUSE_TRUTH] = wanted[PART_DIFFUSE] && p.truthSpp > 0;
    wanted[PART_SPECULAR_TRUTH] = wanted[PART_SPECULAR] && p.truthSpp > 0;

    const bool cacheOn = p.useCache && cache.IsEnabled() && !scene.canonicalJson.empty();
    std::string paths[PART_NUM];
    bool have[PART_NUM] = {};
    for (uint32_t part = 0; part < PART_NUM; part++)
    {
        if (!wanted[part] || !cacheOn)
            continue;
        std::string key = std::string(kCacheVersion) + "|" + shaderHash + "|" + scene.canonicalJson + "|" +
                          std::to_string(w) + "x" + std::to_string(h) + "|frame=" + std::to_string(p.frameIndex) +
                          "|seed=" + std::to_string(seed) + "|" + kPartNames[part];
        if (part == PART_SHADOW || part == PART_SHADOW_TRUTH)
            key += "|light=" + std::to_string(p.lightIndex);
        if (part == PART_DIFFUSE || part == PART_SPECULAR || part == PART_GRADIENTS || part == PART_DIFFUSE_TRUTH ||
            part == PART_SPECULAR_TRUTH)
        {
            const nrd::HitDistanceParameters& hd = p.hitDistanceParameters;
            key += "|bounces=" + std::to_string(p.bounces) + "|direct=" + std::to_string(p.directLighting ? 1 : 0) +
                   "|hitDist=" + std::to_string(hd.A) + "," + std::to_string(hd.B) + "," + std::to_string(hd.C) + "," +
                   std::to_string(hd.D);
        }
        if (part >= PART_SHADOW_TRUTH)
            key += "|spp=" + std::to_string(p.truthSpp);
        std::string prefix = (scene.name.empty() ? std::string("scene") : scene.name) + "-" + std::to_string(w) +
                             "x" + std::to_string(h) + "-f" + std::to_string(p.frameIndex) + "-" + kPartNames[part];
        paths[part] = cache.GetPath(prefix, key);

        std::vector<CachedImage> images;
        if (!cache.Load(paths[part], images))
            continue;
        std::vector<NamedImage> expected = PartImages(Part(part));
        bool ok = images.size() == expected.size() + (part == PART_SHADOW ? 1 : 0);
        for (size_t i = 0; ok && i < expected.size(); i++)
        {
            ok = images[i].name == expected[i].name && images[i].image.width == w && images[i].image.height == h;
            if (part == PART_GRADIENTS)
                ok = images[i].name == expected[i].name && images[i].image.width == DivideUp(w, 3);
            if (ok)
                out.*(expected[i].member) = std::move(images[i].image);
        }
        if (ok && part == PART_SHADOW)
        {
            const Image& mask = images.back().image;
            ok = images.back().name == "shadowHitMask" && mask.width == DivideUp(w, 8) && mask.height == DivideUp(h, 4);
            if (ok)
            {
                out.shadowHitMask.resize(mask.pixels.size());
                std::memcpy(out.shadowHitMask.data(), mask.pixels.data(), mask.pixels.size() * sizeof(uint32_t));
                out.shadowHitMaskWidth = mask.width;
                out.shadowHitMaskHeight = mask.height;
            }
        }
        have[part] = ok;
    }

    // What the GPU has to do.
    const uint32_t partSignal[PART_NUM] = {0, SIGNAL_SHADOW, SIGNAL_TRANSLUCENCY, SIGNAL_DIFFUSE, SIGNAL_SPECULAR,
                                           SIGNAL_GRADIENTS, SIGNAL_SHADOW, SIGNAL_TRANSLUCENCY, SIGNAL_DIFFUSE,
                                           SIGNAL_SPECULAR};
    std::vector<Pass> noisyPasses;
    for (uint32_t part = PART_GBUFFER; part <= PART_GRADIENTS; part++)
        if (wanted[part] && !have[part])
            noisyPasses.push_back(NoisyPass(partSignal[part], p));
    std::vector<Pass> truthPasses;
    uint32_t truthSignals = 0;
    for (uint32_t part = PART_SHADOW_TRUTH; part < PART_NUM; part++)
        if (wanted[part] && !have[part])
        {
            truthPasses.push_back(TruthPass(partSignal[part], p));
            truthSignals |= partSignal[part];
        }
    out.noisyFromCache = noisyPasses.empty();
    out.truthFromCache = p.truthSpp > 0 && truthPasses.empty();
    if (noisyPasses.empty() && truthPasses.empty())
        return true;

    if (!UploadMeshes(scene))
        return fail(error);
    Upload(scene, cur, prev, out.camera, p, seed);
    if (!Check(device.ResetDescriptorPool(*descriptorPool), "ResetDescriptorPool"))
        return fail(error);

    // Noisy signals, G-buffer and gradients: one submission.
    if (!noisyPasses.empty())
    {
        auto t0 = Clock::now();
        std::vector<rhi::DescriptorSet*> sets;
        if (!PreparePasses(noisyPasses, w, h, sets) ||
            !Check(device.BeginCommandBuffer(*commandBuffer), "BeginCommandBuffer"))
            return fail(error);
        std::vector<Slot> slots = SlotsOf(noisyPasses);
        // Whatever was there (a previous copy, or nothing) -> compute writes; content discarded.
        for (Slot s : slots)
            textures[s].state = {rhi::ACCESS_UNKNOWN, rhi::Layout::UNDEFINED};
        Transition(slots, {rhi::ACCESS_SHADER_READ_WRITE, rhi::Layout::GENERAL});
        for (size_t i = 0; i < noisyPasses.size(); i++)
        {
            bool isGradients = noisyPasses[i].outputs[0].slot == SLOT_GRADIENTS;
            RecordDispatch(noisyPasses[i], *sets[i], isGradients ? DivideUp(w, 3) : w,
                           isGradients ? DivideUp(h, 3) : h, nullptr);
        }
        std::vector<uint64_t> offsets;
        if (!RecordReadback(slots, offsets) || !Check(device.EndCommandBuffer(*commandBuffer), "EndCommandBuffer") ||
            !Check(device.SubmitAndWait(*commandBuffer), "SubmitAndWait"))
            return fail(error);
        for (size_t i = 0; i < slots.size(); i++)
            StoreNoisy(slots[i], ReadbackFloats(offsets[i]), w, h, out);
        out.noisyMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }

    // Ground truth: chunks of truthChunkSpp samples, one submission each, every signal per chunk.
    if (!truthPasses.empty())
    {
        auto t0 = Clock::now();
        std::vector<rhi::DescriptorSet*> sets;
        if (!PreparePasses(truthPasses, w, h, sets))
            return fail(error);
        std::vector<Slot> slots = SlotsOf(truthPasses);
        for (Slot s : slots)
            textures[s].state = {rhi::ACCESS_UNKNOWN, rhi::Layout::UNDEFINED};
        std::vector<uint64_t> offsets;
        for (uint32_t first = 0; first < p.truthSpp; first += p.truthChunkSpp)
        {
            uint32_t count = std::min(p.truthChunkSpp, p.truthSpp - first);
            bool last = first + count >= p.truthSpp;
            if (!Check(device.BeginCommandBuffer(*commandBuffer), "BeginCommandBuffer"))
                return fail(error);
            // Previous chunk's writes (earlier submission) -> this chunk's read-modify-write.
            Transition(slots, {rhi::ACCESS_SHADER_READ_WRITE, rhi::Layout::GENERAL});
            gpu::LabTruthChunk chunk = {{first, count, 0u, 0u}};
            for (size_t i = 0; i < truthPasses.size(); i++)
                RecordDispatch(truthPasses[i], *sets[i], w, h, &chunk);
            if (last && !RecordReadback(slots, offsets))
                return fail(error);
            if (!Check(device.EndCommandBuffer(*commandBuffer), "EndCommandBuffer") ||
                !Check(device.SubmitAndWait(*commandBuffer), "SubmitAndWait"))
                return fail(error);
            if (desc.truthProgress)
                desc.truthProgress(first + count, p.truthSpp);
        }

        // Sums -> means. Sky pixels (left at 0 by the truth pass) get the sky values.
        auto acc = [&](Slot slot) {
            for (size_t i = 0; i < slots.size(); i++)
                if (slots[i] == slot)
                    return ReadbackFloats(offsets[i]);
            return static_cast<const float*>(nullptr);
        };
        const float n = float(p.truthSpp);
        const size_t pixelNum = size_t(w) * h;
        auto isSky = [&](size_t px) { return out.viewZ.pixels[px] >= kSkyViewZ; };
        if (truthSignals & SIGNAL_SHADOW)
        {
            const float* a = acc(SLOT_ACC_SHADOW_A);
            out.shadowTruth = Image(w, h, 1);
            for (size_t px = 0; px < pixelNum; px++)
                out.shadowTruth.pixels[px] = isSky(px) ? 1.0f : a[px * 4] / n;
        }
        if (truthSignals & SIGNAL_TRANSLUCENCY)
        {
            const float* a = acc(SLOT_ACC_TRANSLUCENCY_A);
            const float* b = acc(SLOT_ACC_TRANSLUCENCY_B);
            out.translucencyTruth = Image(w, h, 4);
            for (size_t px = 0; px < pixelNum; px++)
            {
                float* t = &out.translucencyTruth.pixels[px * 4];
                t[0] = isSky(px) ? 1.0f : a[px * 4 + 3] / n;
                for (int ch = 0; ch < 3; ch++)
                {
                    float lSum = a[px * 4 + ch];
                    t[1 + ch] = isSky(px) || lSum <= 0.0f ? 1.0f : std::min(b[px * 4 + ch] / lSum, 1.0f);
                }
            }
        }
        const uint32_t radianceSignals[2] = {SIGNAL_DIFFUSE, SIGNAL_SPECULAR};
        const Slot radianceSlots[2][2] = {{SLOT_ACC_DIFFUSE_A, SLOT_ACC_DIFFUSE_B},
                                          {SLOT_ACC_SPECULAR_A, SLOT_ACC_SPECULAR_B}};
        Image* radianceTruth[2] = {&out.diffuseTruth, &out.specularTruth};
        for (int k = 0; k < 2; k++)
        {
            if (!(truthSignals & radianceSignals[k]))
                continue;
            const float* a = acc(radianceSlots[k][0]);
            const float* b = acc(radianceSlots[k][1]);
            *radianceTruth[k] = Image(w, h, 4);
            for (size_t px = 0; px < pixelNum; px++)
            {
                float* t = &radianceTruth[k]->pixels[px * 4];
                for (int ch = 0; ch < 3; ch++)
                    t[ch] = isSky(px) ? 0.0f : a[px * 4 + ch] / n;
                t[3] = isSky(px) ? 1.0f : b[px * 4 + 1] / n; // Mean normalized hit distance.
            }
        }
        out.truthMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }

    // Store what was rendered.
    if (cacheOn)
    {
        for (uint32_t part = 0; part < PART_NUM; part++)
        {
            if (!wanted[part] || have[part])
                continue;
            std::vector<CachedImage> images;
            for (const NamedImage& ni : PartImages(Part(part)))
                images.push_back({ni.name, out.*(ni.member)});
            if (part == PART_SHADOW)
            {
                Image mask(out.shadowHitMaskWidth, out.shadowHitMaskHeight, 1);
                std::memcpy(mask.pixels.data(), out.shadowHitMask.data(), out.shadowHitMask.size() * sizeof(uint32_t));
                images.push_back({"shadowHitMask", std::move(mask)});
            }
            cache.Store(paths[part], images);
        }
    }
    return true;
}

// ------------------------------------------------------------------------------------------------

bool SceneLab::Impl::TraceSpecularRays(const Scene& scene, const RenderParams& p, const std::vector<uint32_t>& rays,
                                       Image& out, std::string& err)
{
    auto fail = [&](const std::string& message) {
        err = message;
        return false;
    };
    std::string problem = CheckParams(scene, p);
    if (!problem.empty())
        return fail(problem);
    if (rays.size() > size_t(p.width) * p.height)
        return fail("the ray list has more rays than pixels");

    const uint32_t w = p.width, h = p.height;
    const uint32_t seed = p.seed == kSceneSeed ? scene.seed : p.seed;
    const SceneState cur = EvaluateScene(scene, p.frameIndex);
    const SceneState prev = EvaluateScene(scene, p.frameIndex > 0 ? p.frameIndex - 1 : 0);
    const FrameCamera camera = ComputeFrameCamera(scene, p.frameIndex, w, h);
    if (!UploadMeshes(scene))
        return fail(error);
    Upload(scene, cur, prev, camera, p, seed);
    if (!Check(device.ResetDescriptorPool(*descriptorPool), "ResetDescriptorPool"))
        return fail(error);

    // The list and its indirect arguments, as the denoiser's classification wrote them.
    const uint64_t listBytes = std::max<uint64_t>(rays.size(), 1) * sizeof(uint32_t);
    if (listBytes > rayListSize || !rayArgs)
    {
        device.WaitIdle();
        device.DestroyBuffer(rayList);
        device.DestroyBuffer(rayArgs);
        rayList = rayArgs = nullptr;
        rayListSize = 0;
        rhi::BufferDesc bd;
        bd.size = listBytes;
        bd.usage = rhi::BUFFER_USAGE_STORAGE;
        bd.location = rhi::MemoryLocation::HOST_UPLOAD;
        bd.name = "LabRayList";
        if (!Check(device.CreateBuffer(bd, rayList), "CreateBuffer (ray list)"))
            return fail(error);
        rayListSize = listBytes;
        bd.size = 4 * sizeof(uint32_t);
        bd.usage = rhi::BUFFER_USAGE_STORAGE | rhi::BUFFER_USAGE_INDIRECT_ARGUMENTS;
        bd.name = "LabRayArgs";
        if (!Check(device.CreateBuffer(bd, rayArgs), "CreateBuffer (ray arguments)"))
            return fail(error);
    }
    if (!rays.empty())
        std::memcpy(device.MapBuffer(*rayList), rays.data(), rays.size() * sizeof(uint32_t));
    const uint32_t groupRays = LAB_GROUP_X * LAB_GROUP_Y;
    const uint32_t args[4] = {DivideUp(uint32_t(rays.size()), groupRays), 1u, 1u, uint32_t(rays.size())};
    std::memcpy(device.MapBuffer(*rayArgs), args, sizeof(args));

    Pass pass = {"LabRays_Specular" + VariantSuffix(p), {{LAB_BINDING_SPECULAR, SLOT_SPECULAR}}};
    pass.isRayList = true;
    std::vector<rhi::DescriptorSet*> sets;
    if (!PreparePasses({pass}, w, h, sets) || !Check(device.BeginCommandBuffer(*commandBuffer), "BeginCommandBuffer"))
        return fail(error);
    // Pixels no ray reaches read as "nothing traced": no radiance, no hit.
    textures[SLOT_SPECULAR].state = {rhi::ACCESS_UNKNOWN, rhi::Layout::UNDEFINED};
    Transition({SLOT_SPECULAR}, {rhi::ACCESS_COPY_DESTINATION, rhi::Layout::GENERAL});
    const float empty[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    device.CmdClearTexture(*commandBuffer, *textures[SLOT_SPECULAR].texture, rhi::Layout::GENERAL, empty);
    // Clear -> the ray pass's writes.
    Transition({SLOT_SPECULAR}, {rhi::ACCESS_SHADER_READ_WRITE, rhi::Layout::GENERAL});
    rhi::Pipeline& pipeline = *pipelines[pass.shader];
    device.CmdBindPipeline(*commandBuffer, pipeline);
    device.CmdBindDescriptorSet(*commandBuffer, pipeline, 0, *sets[0]);
    device.CmdDispatchIndirect(*commandBuffer, *rayArgs, 0);
    std::vector<uint64_t> offsets;
    if (!RecordReadback({SLOT_SPECULAR}, offsets) || !Check(device.EndCommandBuffer(*commandBuffer), "EndCommandBuffer") ||
        !Check(device.SubmitAndWait(*commandBuffer), "SubmitAndWait"))
        return fail(error);
    const float* data = ReadbackFloats(offsets[0]);
    out = Image(w, h, 4);
    std::memcpy(out.pixels.data(), data, size_t(w) * h * 4 * sizeof(float));
    return true;
}

SceneLab::SceneLab(nrd::rhi::Device& device, const SceneLabDesc& desc) : m_Impl(new Impl(device))
{
    m_Impl->desc = desc;
    m_Impl->cache.SetDirectory(desc.cacheDirectory);
    m_Impl->Create(); // On failure IsValid() is false and GetError() says why.
}

SceneLab::SceneLab(nrd::lab::VulkanContext& context, const SceneLabDesc& desc) : SceneLab(context.GetDevice(), desc)
{
}

SceneLab::~SceneLab() = default;

bool SceneLab::IsValid() const
{
    return m_Impl->isValid;
}

const std::string& SceneLab::GetError() const
{
    return m_Impl->error;
}

void SceneLab::SetCacheDirectory(const std::string& directory)
{
    m_Impl->cache.SetDirectory(directory);
}

bool SceneLab::Render(const Scene& scene, const RenderParams& params, FrameData& out, std::string& error)
{
    return m_Impl->Render(scene, params, out, error);
}

bool SceneLab::TraceSpecularRays(const Scene& scene, const RenderParams& params, const std::vector<uint32_t>& rayList,
                                 Image& out, std::string& error)
{
    return m_Impl->TraceSpecularRays(scene, params, rayList, out, error);
}

bool SceneLab::TraceMeshRays(const Scene& scene, uint32_t objectIndex, const std::vector<MeshRay>& rays,
                             std::vector<MeshHit>& hits, std::string& error)
{
    if (!m_Impl->TraceMeshRays(scene, objectIndex, rays, hits))
    {
        error = m_Impl->error;
        return false;
    }
    return true;
}

} // namespace nrdlab
