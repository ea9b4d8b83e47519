// SceneLab.cpp - runs the lab's path tracer (Shaders/Lab*.comp) through nrd::rhi and reads the
// results back: scene upload, one dispatch for the G-buffer + noisy signals, one for the temporal
// gradients, chunked dispatches for the ground truth, and the disk cache in front of all of them.
#include "SceneLab.h"

#include "FrameCache.h"
#include "LabShaders.h"
#include "RHI.h"
#include "VulkanContext.h"

#include <cstdint>
#include <cstring>

#include "Shaders/LabShared.glsl"

static_assert(nrdlab::kMaxObjects == LAB_MAX_OBJECTS && nrdlab::kMaxLights == LAB_MAX_LIGHTS,
              "Scene.h limits must match the shaders'");

#include <algorithm>
#include <chrono>
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

enum PassIndex : uint32_t
{
    PASS_PRIMARY,
    PASS_TRUTH,
    PASS_GRADIENTS,
    PASS_NUM
};

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

gpu::vec4 Vec4(const Float3& v, float w)
{
    return {v.x, v.y, v.z, w};
}

struct Texture
{
    rhi::Texture* texture = nullptr;
    rhi::TextureState state = {};
    uint32_t width = 0, height = 0;
};

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

    rhi::Pipeline* pipelines[PASS_NUM] = {};
    rhi::DescriptorPool* descriptorPool = nullptr;
    rhi::CommandBuffer* commandBuffer = nullptr;
    rhi::Buffer* constants = nullptr; // LabConstants (uniform, host-written)
    rhi::Buffer* objects = nullptr;   // LabObject[kMaxObjects]
    rhi::Buffer* materials = nullptr; // LabMaterial[kMaxObjects]
    rhi::Buffer* lights = nullptr;    // LabLight[kMaxLights]
    rhi::Buffer* readback = nullptr;
    uint64_t readbackSize = 0;
    Texture textures[LAB_BINDING_NUM]; // Indexed by binding; created on first use at the frame size.
    Texture dummyFloat;                // 1x1 stand-ins for outputs a dispatch does not write.
    Texture dummyUint;

    explicit Impl(rhi::Device& d) : device(d)
    {
    }

    ~Impl()
    {
        device.WaitIdle();
        for (Texture& t : textures)
            device.DestroyTexture(t.texture);
        device.DestroyTexture(dummyFloat.texture);
        device.DestroyTexture(dummyUint.texture);
        for (rhi::Pipeline* p : pipelines)
            device.DestroyPipeline(p);
        device.DestroyDescriptorPool(descriptorPool);
        device.DestroyCommandBuffer(commandBuffer);
        for (rhi::Buffer* b : {constants, objects, materials, lights, readback})
            device.DestroyBuffer(b);
    }

    bool Check(rhi::Result r, const char* what)
    {
        if (r == rhi::Result::SUCCESS)
            return true;
        error = std::string(what) + " failed: " + rhi::GetResultString(r);
        return false;
    }

    static bool IsUintBinding(uint32_t binding)
    {
        return binding == LAB_BINDING_HIT_MASK;
    }

    // Bindings of a pass's set 0, in order.
    static std::vector<uint32_t> PassOutputs(PassIndex pass)
    {
        switch (pass)
        {
        case PASS_PRIMARY:
            return {LAB_BINDING_GBUFFER0,    LAB_BINDING_NORMAL_ROUGHNESS,  LAB_BINDING_MV3D,
                    LAB_BINDING_ALBEDO,      LAB_BINDING_SPEC_ALBEDO,       LAB_BINDING_SHADOW,
                    LAB_BINDING_TRANSLUCENCY, LAB_BINDING_TRANSLUCENCY_DATA, LAB_BINDING_DIFFUSE,
                    LAB_BINDING_SPECULAR,    LAB_BINDING_HIT_MASK};
        case PASS_TRUTH:
            return {LAB_BINDING_ACC_SHADOW, LAB_BINDING_ACC_TRANSLUCENCY, LAB_BINDING_ACC_DIFFUSE,
                    LAB_BINDING_ACC_SPECULAR, LAB_BINDING_ACC_COUNT};
        default:
            return {LAB_BINDING_GRADIENTS};
        }
    }

    bool Create()
    {
        struct Blob
        {
            const uint32_t* words;
            uint32_t size;
            const char* name;
        };
        const Blob blobs[PASS_NUM] = {{g_LabPrimary, g_LabPrimary_size, "LabPrimary"},
                                      {g_LabTruth, g_LabTruth_size, "LabTruth"},
                                      {g_LabGradients, g_LabGradients_size, "LabGradients"}};
        uint64_t h = 0xcbf29ce484222325ull;
        for (uint32_t p = 0; p < PASS_NUM; p++)
        {
            h = Fnv1a64(blobs[p].words, blobs[p].size, h);
            std::vector<rhi::DescriptorBindingDesc> bindings;
            bindings.push_back({LAB_BINDING_CONSTANTS, rhi::DescriptorType::UNIFORM_BUFFER, 1, nullptr});
            bindings.push_back({LAB_BINDING_OBJECTS, rhi::DescriptorType::UNIFORM_BUFFER, 1, nullptr});
            bindings.push_back({LAB_BINDING_MATERIALS, rhi::DescriptorType::UNIFORM_BUFFER, 1, nullptr});
            bindings.push_back({LAB_BINDING_LIGHTS, rhi::DescriptorType::UNIFORM_BUFFER, 1, nullptr});
            for (uint32_t b : PassOutputs(PassIndex(p)))
                bindings.push_back({b, rhi::DescriptorType::STORAGE_TEXTURE, 1, nullptr});
            rhi::DescriptorSetDesc set = {bindings.data(), uint32_t(bindings.size())};
            rhi::ComputePipelineDesc pd;
            pd.spirv = blobs[p].words;
            pd.spirvSize = blobs[p].size;
            pd.sets = &set;
            pd.setsNum = 1;
            pd.pushConstantsSize = p == PASS_TRUTH ? uint32_t(sizeof(gpu::LabTruthChunk)) : 0;
            pd.name = blobs[p].name;
            if (!Check(device.CreateComputePipeline(pd, pipelines[p]), "CreateComputePipeline"))
                return false;
        }
        char hex[17];
        std::snprintf(hex, sizeof(hex), "%016llx", (unsigned long long)h);
        shaderHash = hex;

        rhi::DescriptorPoolDesc pool;
        pool.setsMaxNum = PASS_NUM;
        pool.descriptorsMaxNum[(size_t)rhi::DescriptorType::UNIFORM_BUFFER] = 4 * PASS_NUM;
        pool.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_TEXTURE] = LAB_BINDING_NUM;
        if (!Check(device.CreateDescriptorPool(pool, descriptorPool), "CreateDescriptorPool") ||
            !Check(device.CreateCommandBuffer(commandBuffer), "CreateCommandBuffer"))
            return false;

        auto makeBuffer = [&](uint64_t size, uint32_t usage, const char* name, rhi::Buffer*& out) {
            rhi::BufferDesc bd;
            bd.size = size;
            bd.usage = usage;
            bd.location = rhi::MemoryLocation::HOST_UPLOAD;
            bd.name = name;
            return Check(device.CreateBuffer(bd, out), "CreateBuffer");
        };
        return makeBuffer(sizeof(gpu::LabConstants), rhi::BUFFER_USAGE_UNIFORM, "LabConstants", constants) &&
               makeBuffer(sizeof(gpu::LabObject) * LAB_MAX_OBJECTS, rhi::BUFFER_USAGE_UNIFORM, "LabObjects", objects) &&
               makeBuffer(sizeof(gpu::LabMaterial) * LAB_MAX_OBJECTS, rhi::BUFFER_USAGE_UNIFORM, "LabMaterials",
                          materials) &&
               makeBuffer(sizeof(gpu::LabLight) * LAB_MAX_LIGHTS, rhi::BUFFER_USAGE_UNIFORM, "LabLights", lights) &&
               CreateTexture(dummyFloat, rhi::Format::RGBA32_SFLOAT, 1, 1, "LabDummy") &&
               CreateTexture(dummyUint, rhi::Format::R32_UINT, 1, 1, "LabDummyUint");
    }

    bool CreateTexture(Texture& t, rhi::Format format, uint32_t w, uint32_t h, const char* name)
    {
        device.DestroyTexture(t.texture);
        t = {};
        rhi::TextureDesc td;
        td.format = format;
        td.width = w;
        td.height = h;
        td.usage = rhi::TEXTURE_USAGE_STORAGE | rhi::TEXTURE_USAGE_COPY_SOURCE;
        td.name = name;
        if (!Check(device.CreateTexture(td, t.texture), "CreateTexture"))
            return false;
        t.width = w;
        t.height = h;
        return true;
    }

    void BindingSize(uint32_t binding, uint32_t w, uint32_t h, uint32_t& outW, uint32_t& outH) const
    {
        outW = w;
        outH = h;
        if (binding == LAB_BINDING_HIT_MASK)
        {
            outW = DivideUp(w, 8);
            outH = DivideUp(h, 4);
        }
        else if (binding == LAB_BINDING_GRADIENTS)
        {
            outW = DivideUp(w, 3);
            outH = DivideUp(h, 3);
        }
    }

    bool EnsureTexture(uint32_t binding, uint32_t w, uint32_t h)
    {
        uint32_t tw, th;
        BindingSize(binding, w, h, tw, th);
        Texture& t = textures[binding];
        if (t.texture && t.width == tw && t.height == th)
            return true;
        device.WaitIdle();
        return CreateTexture(t, IsUintBinding(binding) ? rhi::Format::R32_UINT : rhi::Format::RGBA32_SFLOAT, tw, th,
                             "LabOutput");
    }

    // Records barriers moving 'list' into 'after' (skipping textures already there and read-only).
    void Transition(const std::vector<Texture*>& list, rhi::TextureState after)
    {
        std::vector<rhi::TextureBarrier> barriers;
        for (Texture* t : list)
        {
            // Read-write to read-write still needs a barrier (write-after-write between dispatches).
            barriers.push_back({t->texture, t->state, after});
            t->state = after;
        }
        rhi::BarrierDesc bd;
        bd.textures = barriers.data();
        bd.texturesNum = uint32_t(barriers.size());
        device.CmdBarrier(*commandBuffer, bd);
    }

    void Upload(const Scene& scene, const SceneState& cur, const SceneState& prev, const FrameCamera& cam,
                const RenderParams& p, uint32_t seed, uint32_t signals)
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
        k.gCounts = {uint32_t(scene.objects.size()), uint32_t(scene.lights.size()), p.lightIndex, signals};
        k.gOptions = {p.bounces, p.frameIndex > 0 ? 1u : 0u, p.directLighting ? 1u : 0u, 0u};
        std::memcpy(device.MapBuffer(*constants), &k, sizeof(k));

        auto* objs = static_cast<gpu::LabObject*>(device.MapBuffer(*objects));
        auto* mats = static_cast<gpu::LabMaterial*>(device.MapBuffer(*materials));
        for (size_t i = 0; i < scene.objects.size(); i++)
        {
            const Object& o = scene.objects[i];
            gpu::LabObject g = {};
            g.info = {uint32_t(o.type), uint32_t(i), 0u, 0u};
            if (o.type == PrimitiveType::SPHERE)
                g.size = {o.radius, o.radius, o.radius, 0.0f};
            else
                g.size = {0.5f * o.size.x, 0.5f * o.size.y, 0.5f * o.size.z, 0.0f};
            const ObjectState* states[2] = {&cur.objects[i], &prev.objects[i]};
            for (uint32_t slot = 0; slot < 2; slot++)
            {
                const float* R = states[slot]->rotation;
                const Float3& T = states[slot]->position;
                const float t[3] = {T.x, T.y, T.z};
                for (uint32_t row = 0; row < 3; row++)
                    g.xform[slot * 3 + row] = {R[row * 3 + 0], R[row * 3 + 1], R[row * 3 + 2], t[row]};
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

    // Allocates and fills the set of 'pass'; outputs not in 'used' are bound to a dummy.
    bool BindPass(PassIndex pass, const std::vector<uint32_t>& used, rhi::DescriptorSet*& set)
    {
        if (!Check(device.AllocateDescriptorSet(*descriptorPool, *pipelines[pass], 0, set), "AllocateDescriptorSet"))
            return false;
        std::vector<rhi::DescriptorWrite> writes;
        auto buffer = [&](uint32_t binding, rhi::DescriptorType type, rhi::Buffer* b) {
            rhi::DescriptorWrite w;
            w.binding = binding;
            w.type = type;
            w.buffer = b;
            writes.push_back(w);
        };
        buffer(LAB_BINDING_CONSTANTS, rhi::DescriptorType::UNIFORM_BUFFER, constants);
        buffer(LAB_BINDING_OBJECTS, rhi::DescriptorType::UNIFORM_BUFFER, objects);
        buffer(LAB_BINDING_MATERIALS, rhi::DescriptorType::UNIFORM_BUFFER, materials);
        buffer(LAB_BINDING_LIGHTS, rhi::DescriptorType::UNIFORM_BUFFER, lights);
        for (uint32_t b : PassOutputs(pass))
        {
            bool isUsed = std::find(used.begin(), used.end(), b) != used.end();
            rhi::DescriptorWrite w;
            w.binding = b;
            w.type = rhi::DescriptorType::STORAGE_TEXTURE;
            w.texture = isUsed ? textures[b].texture : (IsUintBinding(b) ? dummyUint.texture : dummyFloat.texture);
            writes.push_back(w);
        }
        device.UpdateDescriptorSet(*set, writes.data(), uint32_t(writes.size()));
        return true;
    }

    // Records copies of 'bindings' into the readback buffer (grown first if needed; only between
    // submissions) and returns each one's byte offset.
    bool RecordReadback(const std::vector<uint32_t>& bindings, std::vector<uint64_t>& offsets)
    {
        std::vector<Texture*> list;
        uint64_t total = 0;
        offsets.clear();
        for (uint32_t b : bindings)
        {
            const Texture& t = textures[b];
            offsets.push_back(total);
            // Copy offsets must be multiples of the texel size: keep every region 16-byte aligned.
            total += (uint64_t(t.width) * t.height * (IsUintBinding(b) ? 4 : 16) + 15) & ~uint64_t(15);
            list.push_back(&textures[b]);
        }
        if (total == 0)
            return true;
        if (total > readbackSize)
        {
            device.DestroyBuffer(readback);
            readback = nullptr;
            rhi::BufferDesc bd;
            bd.size = total;
            bd.usage = rhi::BUFFER_USAGE_COPY_DESTINATION;
            bd.location = rhi::MemoryLocation::HOST_READBACK;
            bd.name = "LabReadback";
            if (!Check(device.CreateBuffer(bd, readback), "CreateBuffer (readback)"))
            {
                readbackSize = 0;
                return false;
            }
            readbackSize = total;
        }
        // Compute writes -> copy reads.
        Transition(list, {rhi::ACCESS_COPY_SOURCE, rhi::Layout::COPY_SOURCE});
        for (size_t i = 0; i < bindings.size(); i++)
            device.CmdCopyTextureToBuffer(*commandBuffer, *readback, offsets[i], *textures[bindings[i]].texture);
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

    bool Render(const Scene& scene, const RenderParams& p, FrameData& out, std::string& err);
};

bool SceneLab::Impl::Render(const Scene& scene, const RenderParams& p, FrameData& out, std::string& err)
{
    using Clock = std::chrono::steady_clock;
    auto fail = [&](const std::string& message) {
        err = message;
        return false;
    };

    // Parameters.
    if (!pipelines[PASS_PRIMARY])
        return fail("the scene lab is not valid: " + error);
    if (p.width < 1 || p.height < 1 || p.width > kMaxSize || p.height > kMaxSize)
        return fail("size " + std::to_string(p.width) + "x" + std::to_string(p.height) + " out of range (1.." +
                    std::to_string(kMaxSize) + ")");
    if (p.signals & ~uint32_t(SIGNAL_ALL))
        return fail("unknown signal bits in RenderParams::signals");
    if (p.bounces < 1 || p.bounces > 2)
        return fail("bounces must be 1 or 2");
    if (p.truthSpp > 0 && p.truthChunkSpp == 0)
        return fail("truthChunkSpp must be at least 1");
    if (scene.objects.size() > kMaxObjects || scene.lights.size() > kMaxLights)
        return fail("the scene has more objects or lights than the path tracer supports");
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
            key += "|bounces=" + std::to_string(p.bounces) + "|direct=" + std::to_string(p.directLighting ? 1 : 0);
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
    uint32_t primarySignals = 0;
    const uint32_t partSignal[PART_NUM] = {0, SIGNAL_SHADOW, SIGNAL_TRANSLUCENCY, SIGNAL_DIFFUSE, SIGNAL_SPECULAR,
                                           SIGNAL_GRADIENTS, SIGNAL_SHADOW, SIGNAL_TRANSLUCENCY, SIGNAL_DIFFUSE,
                                           SIGNAL_SPECULAR};
    for (uint32_t part = PART_SHADOW; part <= PART_SPECULAR; part++)
        if (wanted[part] && !have[part])
            primarySignals |= partSignal[part];
    const bool runPrimary = primarySignals != 0 || !have[PART_GBUFFER];
    const bool runGradients = wanted[PART_GRADIENTS] && !have[PART_GRADIENTS];
    uint32_t truthSignals = 0;
    for (uint32_t part = PART_SHADOW_TRUTH; part < PART_NUM; part++)
        if (wanted[part] && !have[part])
            truthSignals |= partSignal[part];
    out.noisyFromCache = !runPrimary && !runGradients;
    out.truthFromCache = p.truthSpp > 0 && truthSignals == 0;

    if (runPrimary || runGradients || truthSignals)
        Upload(scene, cur, prev, out.camera, p, seed, primarySignals | truthSignals);

    if (runPrimary || runGradients)
    {
        auto t0 = Clock::now();
        std::vector<uint32_t> primaryOut = {LAB_BINDING_GBUFFER0, LAB_BINDING_NORMAL_ROUGHNESS, LAB_BINDING_MV3D,
                                            LAB_BINDING_ALBEDO, LAB_BINDING_SPEC_ALBEDO};
        if (primarySignals & SIGNAL_SHADOW)
            primaryOut.insert(primaryOut.end(), {LAB_BINDING_SHADOW, LAB_BINDING_HIT_MASK});
        if (primarySignals & SIGNAL_TRANSLUCENCY)
            primaryOut.insert(primaryOut.end(), {LAB_BINDING_TRANSLUCENCY, LAB_BINDING_TRANSLUCENCY_DATA});
        if (primarySignals & SIGNAL_DIFFUSE)
            primaryOut.push_back(LAB_BINDING_DIFFUSE);
        if (primarySignals & SIGNAL_SPECULAR)
            primaryOut.push_back(LAB_BINDING_SPECULAR);
        if (!runPrimary)
            primaryOut.clear();
        std::vector<uint32_t> readList = primaryOut;
        if (runGradients)
            readList.push_back(LAB_BINDING_GRADIENTS);
        for (uint32_t b : readList)
            if (!EnsureTexture(b, w, h))
                return fail(error);

        if (!Check(device.ResetDescriptorPool(*descriptorPool), "ResetDescriptorPool") ||
            !Check(device.BeginCommandBuffer(*commandBuffer), "BeginCommandBuffer"))
            return fail(error);
        std::vector<Texture*> list = {&dummyFloat, &dummyUint};
        for (uint32_t b : readList)
            list.push_back(&textures[b]);
        // Previous copies / nothing -> compute writes (old content is discarded).
        for (Texture* t : list)
            t->state = {rhi::ACCESS_UNKNOWN, rhi::Layout::UNDEFINED};
        Transition(list, {rhi::ACCESS_SHADER_READ_WRITE, rhi::Layout::GENERAL});

        if (runPrimary)
        {
            rhi::DescriptorSet* set = nullptr;
            if (!BindPass(PASS_PRIMARY, primaryOut, set))
                return fail(error);
            device.CmdBindPipeline(*commandBuffer, *pipelines[PASS_PRIMARY]);
            device.CmdBindDescriptorSet(*commandBuffer, *pipelines[PASS_PRIMARY], 0, *set);
            device.CmdDispatch(*commandBuffer, DivideUp(w, LAB_GROUP_X), DivideUp(h, LAB_GROUP_Y), 1);
        }
        if (runGradients)
        {
            rhi::DescriptorSet* set = nullptr;
            if (!BindPass(PASS_GRADIENTS, {LAB_BINDING_GRADIENTS}, set))
                return fail(error);
            device.CmdBindPipeline(*commandBuffer, *pipelines[PASS_GRADIENTS]);
            device.CmdBindDescriptorSet(*commandBuffer, *pipelines[PASS_GRADIENTS], 0, *set);
            device.CmdDispatch(*commandBuffer, DivideUp(DivideUp(w, 3), LAB_GROUP_X),
                               DivideUp(DivideUp(h, 3), LAB_GROUP_Y), 1);
        }
        std::vector<uint64_t> offsets;
        if (!RecordReadback(readList, offsets) ||
            !Check(device.EndCommandBuffer(*commandBuffer), "EndCommandBuffer") ||
            !Check(device.SubmitAndWait(*commandBuffer), "SubmitAndWait"))
            return fail(error);

        for (size_t i = 0; i < readList.size(); i++)
        {
            const float* d = ReadbackFloats(offsets[i]);
            switch (readList[i])
            {
            case LAB_BINDING_GBUFFER0:
                out.viewZ = Extract(d, w, h, 0, 1);
                out.motion2d = Extract(d, w, h, 1, 2);
                out.objectIndex = Extract(d, w, h, 3, 1);
                break;
            case LAB_BINDING_NORMAL_ROUGHNESS:
                out.normalRoughness = Extract(d, w, h, 0, 4);
                break;
            case LAB_BINDING_MV3D:
                out.motion3d = Extract(d, w, h, 0, 3);
                break;
            case LAB_BINDING_ALBEDO:
                out.albedo = Extract(d, w, h, 0, 3);
                break;
            case LAB_BINDING_SPEC_ALBEDO:
                out.specularAlbedo = Extract(d, w, h, 0, 3);
                break;
            case LAB_BINDING_SHADOW:
                out.shadowData = Extract(d, w, h, 0, 2);
                out.shadowVisibility = Extract(d, w, h, 2, 1);
                break;
            case LAB_BINDING_HIT_MASK:
                out.shadowHitMaskWidth = DivideUp(w, 8);
                out.shadowHitMaskHeight = DivideUp(h, 4);
                out.shadowHitMask.resize(size_t(out.shadowHitMaskWidth) * out.shadowHitMaskHeight);
                std::memcpy(out.shadowHitMask.data(), d, out.shadowHitMask.size() * sizeof(uint32_t));
                break;
            case LAB_BINDING_TRANSLUCENCY:
                out.translucency = Extract(d, w, h, 0, 4);
                break;
            case LAB_BINDING_TRANSLUCENCY_DATA:
                out.translucencyShadowData = Extract(d, w, h, 0, 2);
                break;
            case LAB_BINDING_DIFFUSE:
                out.diffuse = Extract(d, w, h, 0, 4);
                break;
            case LAB_BINDING_SPECULAR:
                out.specular = Extract(d, w, h, 0, 4);
                break;
            case LAB_BINDING_GRADIENTS:
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
        out.noisyMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }

    if (truthSignals)
    {
        auto t0 = Clock::now();
        std::vector<uint32_t> accs = PassOutputs(PASS_TRUTH);
        for (uint32_t b : accs)
            if (!EnsureTexture(b, w, h))
                return fail(error);
        std::vector<Texture*> list;
        for (uint32_t b : accs)
        {
            list.push_back(&textures[b]);
            textures[b].state = {rhi::ACCESS_UNKNOWN, rhi::Layout::UNDEFINED};
        }

        if (!Check(device.ResetDescriptorPool(*descriptorPool), "ResetDescriptorPool"))
            return fail(error);
        rhi::DescriptorSet* set = nullptr;
        if (!BindPass(PASS_TRUTH, accs, set))
            return fail(error);

        for (uint32_t first = 0; first < p.truthSpp; first += p.truthChunkSpp)
        {
            uint32_t count = std::min(p.truthChunkSpp, p.truthSpp - first);
            bool last = first + count >= p.truthSpp;
            if (!Check(device.BeginCommandBuffer(*commandBuffer), "BeginCommandBuffer"))
                return fail(error);
            // Previous chunk's writes (earlier submission) -> this chunk's read-modify-write.
            Transition(list, {rhi::ACCESS_SHADER_READ_WRITE, rhi::Layout::GENERAL});
            device.CmdBindPipeline(*commandBuffer, *pipelines[PASS_TRUTH]);
            device.CmdBindDescriptorSet(*commandBuffer, *pipelines[PASS_TRUTH], 0, *set);
            gpu::LabTruthChunk chunk = {{first, count, 0u, 0u}};
            device.CmdPushConstants(*commandBuffer, *pipelines[PASS_TRUTH], &chunk, sizeof(chunk));
            device.CmdDispatch(*commandBuffer, DivideUp(w, LAB_GROUP_X), DivideUp(h, LAB_GROUP_Y), 1);
            std::vector<uint64_t> offsets;
            if (last && !RecordReadback(accs, offsets))
                return fail(error);
            if (!Check(device.EndCommandBuffer(*commandBuffer), "EndCommandBuffer") ||
                !Check(device.SubmitAndWait(*commandBuffer), "SubmitAndWait"))
                return fail(error);
            if (desc.truthProgress)
                desc.truthProgress(first + count, p.truthSpp);
            if (!last)
                continue;

            // Sums -> means. Sky pixels (the truth pass leaves them at 0) get the sky values.
            const float* accShadow = ReadbackFloats(offsets[0]);
            const float* accTrans = ReadbackFloats(offsets[1]);
            const float* accDiff = ReadbackFloats(offsets[2]);
            const float* accSpec = ReadbackFloats(offsets[3]);
            const float* accCount = ReadbackFloats(offsets[4]);
            const float n = float(p.truthSpp);
            if (truthSignals & SIGNAL_SHADOW)
                out.shadowTruth = Image(w, h, 1);
            if (truthSignals & SIGNAL_TRANSLUCENCY)
                out.translucencyTruth = Image(w, h, 4);
            if (truthSignals & SIGNAL_DIFFUSE)
                out.diffuseTruth = Image(w, h, 4);
            if (truthSignals & SIGNAL_SPECULAR)
                out.specularTruth = Image(w, h, 4);
            for (size_t px = 0; px < size_t(w) * h; px++)
            {
                bool sky = out.viewZ.pixels[px] >= kSkyViewZ;
                if (truthSignals & SIGNAL_SHADOW)
                    out.shadowTruth.pixels[px] = sky ? 1.0f : accShadow[px * 4] / n;
                if (truthSignals & SIGNAL_TRANSLUCENCY)
                {
                    float* t = &out.translucencyTruth.pixels[px * 4];
                    t[0] = sky ? 1.0f : accTrans[px * 4 + 3] / n;
                    for (int ch = 0; ch < 3; ch++)
                    {
                        float lSum = accTrans[px * 4 + ch];
                        t[1 + ch] = sky || lSum <= 0.0f ? 1.0f : std::min(accShadow[px * 4 + 1 + ch] / lSum, 1.0f);
                    }
                }
                const float* accs2[2] = {accDiff, accSpec};
                Image* dst[2] = {&out.diffuseTruth, &out.specularTruth};
                const uint32_t bits[2] = {SIGNAL_DIFFUSE, SIGNAL_SPECULAR};
                for (int k = 0; k < 2; k++)
                {
                    if (!(truthSignals & bits[k]))
                        continue;
                    float* t = &dst[k]->pixels[px * 4];
                    const float* a = &accs2[k][px * 4];
                    float hits = accCount[px * 4 + k];
                    for (int ch = 0; ch < 3; ch++)
                        t[ch] = sky ? 0.0f : a[ch] / n;
                    t[3] = sky || hits <= 0.0f ? kNoHitDistance : a[3] / hits;
                }
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

SceneLab::SceneLab(nrd::rhi::Device& device, const SceneLabDesc& desc) : m_Impl(new Impl(device))
{
    m_Impl->desc = desc;
    m_Impl->cache.SetDirectory(desc.cacheDirectory);
    if (!m_Impl->Create())
    {
        // Leave the object in a clean "invalid" state: no half-created pipelines used later.
        for (rhi::Pipeline*& p : m_Impl->pipelines)
        {
            device.DestroyPipeline(p);
            p = nullptr;
        }
    }
}

SceneLab::SceneLab(nrd::lab::VulkanContext& context, const SceneLabDesc& desc) : SceneLab(context.GetDevice(), desc)
{
}

SceneLab::~SceneLab() = default;

bool SceneLab::IsValid() const
{
    return m_Impl->pipelines[PASS_PRIMARY] != nullptr;
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

} // namespace nrdlab
