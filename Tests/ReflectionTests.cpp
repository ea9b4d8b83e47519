// REFLECTION through the Vulkan integration layer on lavapipe, validation on: the classification
// (ray list, ray counter, copies, tile list, indirect arguments) against a CPU evaluation of the
// per-pixel rules on the same inputs, the temporal-variance-guided decision with the variance the
// method wrote, the stage split of GetComputeDispatches, settings validation, and that tiles which
// need no denoiser are never written.
#include <catch2/catch.hpp>

#include "RHIVulkan.h"
#include "VulkanTestUtils.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>

using namespace nrd;
using nrd::test::Bindings;

namespace
{

constexpr Identifier REFLECTION_ID = 7;
constexpr float kSentinel = -7.0f; // Written into the output first; the method writes >= 0.
constexpr uint32_t kCopyH = 1u << 28, kCopyV = 1u << 29, kCopyD = 1u << 30;

DenoiserCreationDesc ReflectionCreationDesc(uint32_t w, uint32_t h)
{
    static const MethodDesc methodDesc = {REFLECTION_ID, Method::REFLECTION};
    DenoiserCreationDesc desc = {};
    desc.methods = &methodDesc;
    desc.methodsNum = 1;
    desc.renderWidth = uint16_t(w);
    desc.renderHeight = uint16_t(h);
    return desc;
}

// Inputs: surfaces facing the camera with per-pixel roughness drawn from a mix of mirrors, glossy
// (0.3 or random), rough (beyond the threshold) and NaN values, viewZ 10, 11 or 13 (10 and 13 are not one surface,
// 11 is one with both) and three normals (the second not one surface with the others); some sky
// pixels.
struct Inputs
{
    uint32_t width, height;
    std::vector<float> viewZ, normal, mv, radiance;

    Inputs(uint32_t w, uint32_t h, uint32_t seed) : width(w), height(h)
    {
        const size_t n = size_t(w) * h;
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
        viewZ.assign(n, 10.0f);
        normal.resize(n * 4);
        mv.assign(n * 4, 0.0f);
        radiance.resize(n * 4);
        for (size_t i = 0; i < n; i++)
        {
            const float normalPick = uniform(rng);
            normal[i * 4 + 0] = 0.5f;
            normal[i * 4 + 1] = normalPick < 0.8f ? 0.5f : normalPick < 0.9f ? 0.9f : 0.6f;
            normal[i * 4 + 2] = 0.0f;
            const float depthPick = uniform(rng);
            viewZ[i] = depthPick < 0.7f ? 10.0f : depthPick < 0.85f ? 11.0f : 13.0f;
            const float pick = uniform(rng);
            float roughness = uniform(rng);
            if (pick < 0.1f)
                roughness = 0.0f; // Mirror.
            else if (pick < 0.15f)
                roughness = std::numeric_limits<float>::quiet_NaN(); // Counts as 1.
            else if (pick < 0.5f)
                roughness = 0.3f; // Many neighbours of one roughness: one surface unless viewZ or normal differ.
            normal[i * 4 + 3] = roughness;
            if (uniform(rng) < 0.08f)
                viewZ[i] = std::numeric_limits<float>::infinity(); // Sky.
            for (int c = 0; c < 3; c++)
                radiance[i * 4 + c] = uniform(rng) * 2.0f;
            radiance[i * 4 + 3] = uniform(rng);
        }
        // A whole tile of sky and one of rough pixels only: neither needs the denoiser.
        for (uint32_t y = 8; y < 16 && y < h; y++)
            for (uint32_t x = 0; x < 8 && x < w; x++)
            {
                viewZ[size_t(y) * w + x] = std::numeric_limits<float>::infinity();
                if (x + 16 < w)
                    normal[(size_t(y) * w + x + 16) * 4 + 3] = 1.0f;
            }
    }
};

// The per-pixel rules of Shaders/Reflection/Reflection_Common.glsl and Reflection_Classify.comp.
struct Classification
{
    std::set<uint32_t> rays;  // Ray list entries.
    std::set<uint32_t> tiles; // x | y << 16.
    std::vector<uint8_t> needs, mirror;
};

bool IsBaseRay(uint32_t q, uint32_t frameIndex, uint32_t raysPerQuad)
{
    if (raysPerQuad >= 4)
        return true;
    if (raysPerQuad == 2)
        return ((q == 0 || q == 3) ? 0u : 1u) == (frameIndex & 1u);
    const uint32_t order[4] = {0, 3, 1, 2};
    return q == order[frameIndex & 3u];
}

Classification Classify(const Inputs& in, const ReflectionSettings& s, uint32_t frameIndex, const std::vector<float>* variance,
                        float denoisingRange)
{
    const uint32_t w = in.width, h = in.height;
    Classification c;
    c.needs.assign(size_t(w) * h, 0);
    c.mirror.assign(size_t(w) * h, 0);
    std::vector<uint8_t> wants(size_t(w) * h, 0);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
        {
            const size_t i = size_t(y) * w + x;
            const float z = in.viewZ[i];
            const bool valid = std::isfinite(z) && z > 0.0f && std::fabs(z) <= denoisingRange;
            float r = in.normal[i * 4 + 3];
            r = std::isfinite(r) ? std::min(std::max(r, 0.0f), 1.0f) : 1.0f;
            c.mirror[i] = valid && r < s.mirrorRoughness && r <= s.roughnessThreshold;
            c.needs[i] = valid && !(r < s.mirrorRoughness) && r <= s.roughnessThreshold;
            const uint32_t q = (x & 1u) | ((y & 1u) << 1u);
            const bool high = variance && s.enableTemporalVarianceGuidedTracing && !((*variance)[i] <= s.temporalVarianceThreshold);
            wants[i] = c.mirror[i] || (c.needs[i] && (IsBaseRay(q, frameIndex, s.raysPerQuad) || high));
        }
    // Per quad (members in quad order: even x even y, odd x, odd y, both odd; outside the image they
    // need nothing): which members share a surface, who traces, who copies from whom.
    auto surface = [&](size_t i, float n[3]) {
        float len2 = 0.0f;
        for (int k = 0; k < 3; k++)
        {
            n[k] = in.normal[i * 4 + k] * 2.0f - 1.0f;
            len2 += n[k] * n[k];
        }
        const float len = std::sqrt(len2);
        for (int k = 0; k < 3; k++)
            n[k] /= len;
    };
    auto roughness = [&](size_t i) {
        const float r = in.normal[i * 4 + 3];
        return std::isfinite(r) ? std::min(std::max(r, 0.0f), 1.0f) : 1.0f;
    };
    for (uint32_t qy = 0; qy < h; qy += 2)
        for (uint32_t qx = 0; qx < w; qx += 2)
        {
            bool inside[4], want[4], need[4], same[4][4], trace[4];
            size_t idx[4];
            for (uint32_t k = 0; k < 4; k++)
            {
                const uint32_t x = qx + (k & 1u), y = qy + (k >> 1);
                inside[k] = x < w && y < h;
                idx[k] = inside[k] ? size_t(y) * w + x : 0;
                want[k] = inside[k] && wants[idx[k]];
                need[k] = inside[k] && c.needs[idx[k]];
            }
            for (uint32_t a = 0; a < 4; a++)
                for (uint32_t b = 0; b < 4; b++)
                {
                    same[a][b] = a == b;
                    if (a == b || !need[a] || !need[b])
                        continue;
                    float na[3], nb[3];
                    surface(idx[a], na);
                    surface(idx[b], nb);
                    const float ra = roughness(idx[a]), rb = roughness(idx[b]);
                    const float za = in.viewZ[idx[a]], zb = in.viewZ[idx[b]];
                    same[a][b] = na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2] > 0.9f &&
                                 std::fabs(ra - rb) < 0.05f + 0.1f * std::min(ra, rb) &&
                                 std::fabs(za - zb) < 0.2f * std::min(za, zb);
                }
            // A member that needs the denoiser and has no ray of its surface (no wanted ray of a
            // same-surface member, no same-surface member before it that traces) traces its own.
            for (uint32_t k = 0; k < 4; k++)
            {
                bool hasRay = false;
                for (uint32_t j = 0; j < 4; j++)
                    hasRay = hasRay || (j != k && same[k][j] && (want[j] || (j < k && trace[j])));
                trace[k] = want[k] || (need[k] && !hasRay);
            }
            // Member n takes its copy from its horizontal (n ^ 1), else vertical (n ^ 2), else
            // diagonal (n ^ 3) member that traces on its surface.
            const uint32_t copyBits[4] = {0u, kCopyH, kCopyV, kCopyD};
            for (uint32_t k = 0; k < 4; k++)
            {
                if (!trace[k])
                    continue;
                uint32_t entry = (qx + (k & 1u)) | ((qy + (k >> 1)) << 14);
                for (uint32_t d = 1; d < 4; d++)
                {
                    const uint32_t n = k ^ d;
                    bool takes = need[n] && !trace[n] && same[n][k];
                    for (uint32_t e = 1; e < d; e++)
                        takes = takes && !(trace[n ^ e] && same[n][n ^ e]);
                    entry |= takes ? copyBits[d] : 0u;
                }
                c.rays.insert(entry);
            }
        }
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            if (c.needs[size_t(y) * w + x] || c.mirror[size_t(y) * w + x])
                c.tiles.insert((x / 8) | ((y / 8) << 16));
    return c;
}

struct ReflectionRig
{
    lab::VulkanContext& context;
    Integration integration;
    uint32_t width = 0, height = 0;
    lab::LabTexture viewZ, normal, mv, radiance, output;
    uint32_t rayList = 0, tileList = 0, counters = 0;

    explicit ReflectionRig(lab::VulkanContext& c) : context(c) {}
    ~ReflectionRig()
    {
        integration.Destroy();
        for (lab::LabTexture* t : {&viewZ, &normal, &mv, &radiance, &output})
            context.DestroyTexture(*t);
    }

    void Create(uint32_t w, uint32_t h, const ReflectionSettings& settings)
    {
        width = w;
        height = h;
        IntegrationCreationDesc integrationDesc = context.GetIntegrationCreationDesc();
        integrationDesc.name = "REFLECTION test";
        REQUIRE(integration.Create(integrationDesc, ReflectionCreationDesc(w, h)) == VK_SUCCESS);
        REQUIRE(integration.SetMethodSettings(REFLECTION_ID, settings) == Result::SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::R32_SFLOAT, w, h, "IN_VIEWZ", viewZ) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA32_SFLOAT, w, h, "IN_NORMAL_ROUGHNESS", normal) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA16_SFLOAT, w, h, "IN_MV", mv) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA16_SFLOAT, w, h, "IN_SPEC_RADIANCE_HITDIST", radiance) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA32_SFLOAT, w, h, "OUT_SPEC_RADIANCE_HITDIST", output) == VK_SUCCESS);
        std::vector<float> sentinel(size_t(w) * h * 4, kSentinel);
        REQUIRE(context.UploadTexture(output, sentinel.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
        const DenoiserDesc& desc = integration.GetDenoiserDesc();
        uint32_t found = 0;
        for (uint32_t i = 0; i < desc.buffersNum; i++)
        {
            REQUIRE(desc.buffers[i].identifier == REFLECTION_ID);
            if (desc.buffers[i].content == BufferContent::RAY_LIST)
                rayList = i, found |= 1;
            else if (desc.buffers[i].content == BufferContent::RAY_COUNTERS)
                counters = i, found |= 2;
            else
                tileList = i, found |= 4;
        }
        REQUIRE(found == 7);
        REQUIRE(desc.buffers[rayList].size == uint64_t(w) * h * 4);
        REQUIRE(desc.buffers[counters].isIndirectArguments);
    }

    Bindings AllBindings()
    {
        return {{ResourceType::IN_VIEWZ, &viewZ},
                {ResourceType::IN_NORMAL_ROUGHNESS, &normal},
                {ResourceType::IN_MV, &mv},
                {ResourceType::IN_SPEC_RADIANCE_HITDIST, &radiance},
                {ResourceType::OUT_SPEC_RADIANCE_HITDIST, &output}};
    }

    void Stage(DispatchStage stage)
    {
        UserPool pool = {};
        Bindings bindings = AllBindings();
        for (const auto& b : bindings)
            pool[b.first] = b.second->AsUserTexture();
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        REQUIRE(context.BeginCommands(cmd) == VK_SUCCESS);
        REQUIRE(integration.Denoise(cmd, nullptr, 0, pool, stage) == VK_SUCCESS);
        REQUIRE(context.SubmitAndWait(cmd) == VK_SUCCESS);
        for (const auto& b : bindings)
            b.second->FromUserTexture(pool[b.first]);
    }

    void Classify(uint32_t frameIndex, const Inputs& in)
    {
        REQUIRE(context.UploadTexture(viewZ, in.viewZ.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(normal, in.normal.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(mv, in.mv.data()) == VK_SUCCESS);
        REQUIRE(integration.SetCommonSettings(test::StillCameraSettings(frameIndex)) == Result::SUCCESS);
        Stage(DispatchStage::CLASSIFICATION);
    }

    std::vector<uint32_t> Buffer(uint32_t index, uint64_t bytes)
    {
        std::vector<uint32_t> words;
        const uint32_t written = rhi::ACCESS_SHADER_READ_WRITE | rhi::ACCESS_INDIRECT_ARGUMENTS;
        REQUIRE(context.ReadbackBuffer(*integration.GetPoolBuffer(index), written, bytes, words) == VK_SUCCESS);
        return words;
    }

    // The temporal variance: the method's only R16F permanent texture.
    uint16_t VarianceIndex()
    {
        const DenoiserDesc& desc = integration.GetDenoiserDesc();
        for (uint32_t i = 0; i < desc.permanentPoolSize; i++)
            if (desc.permanentPool[i].format == Format::R16_SFLOAT)
                return uint16_t(i);
        FAIL("no temporal variance texture");
        return 0;
    }

    std::vector<float> Permanent(uint16_t index)
    {
        return test::ReadbackPoolTexture(context, integration, ResourceType::PERMANENT_POOL, index);
    }

    // Compares this frame's ray list, counters, tile list and indirect arguments with 'expected'.
    void CheckClassification(const Classification& expected)
    {
        const std::vector<uint32_t> words = Buffer(counters, 16 * 4);
        const uint32_t rays = words[3], tiles = words[7];
        CHECK(rays == expected.rays.size());
        CHECK(words[0] == (rays + 63) / 64);
        CHECK(words[1] == 1u);
        CHECK(words[2] == 1u);
        CHECK(tiles == expected.tiles.size());
        CHECK(words[4] == tiles);
        CHECK(words[5] == 1u);
        CHECK(words[6] == 1u);
        CHECK(words[8] == 0u); // Live counters reset for the next frame.
        CHECK(words[9] == 0u);
        std::vector<uint32_t> list = rays ? Buffer(rayList, uint64_t(rays) * 4) : std::vector<uint32_t>();
        std::set<uint32_t> got(list.begin(), list.end());
        CHECK(got.size() == list.size()); // No pixel listed twice.
        CHECK(got == expected.rays);
        std::vector<uint32_t> tileWords = tiles ? Buffer(tileList, uint64_t(tiles) * 4) : std::vector<uint32_t>();
        CHECK(std::set<uint32_t>(tileWords.begin(), tileWords.end()) == expected.tiles);
    }

    // The application's ray pass, on the CPU: each listed ray writes 'in.radiance' of its pixel to
    // the pixel and to the neighbours its entry names. Returns the input and how often each pixel
    // was written.
    std::vector<float> TraceOnCpu(const Inputs& in, std::vector<uint8_t>& writes)
    {
        const uint32_t rays = Buffer(counters, 16)[3];
        std::vector<uint32_t> list = rays ? Buffer(rayList, uint64_t(rays) * 4) : std::vector<uint32_t>();
        std::vector<float> traced(size_t(width) * height * 4, 0.0f);
        writes.assign(size_t(width) * height, 0);
        for (uint32_t entry : list)
        {
            const uint32_t x = entry & 0x3FFFu, y = (entry >> 14) & 0x3FFFu;
            const size_t src = size_t(y) * width + x;
            auto write = [&](uint32_t tx, uint32_t ty) {
                if (tx >= width || ty >= height)
                    return;
                const size_t dst = size_t(ty) * width + tx;
                std::memcpy(&traced[dst * 4], &in.radiance[src * 4], 4 * sizeof(float));
                writes[dst]++;
            };
            write(x, y);
            if (entry & kCopyH)
                write(x ^ 1u, y);
            if (entry & kCopyV)
                write(x, y ^ 1u);
            if (entry & kCopyD)
                write(x ^ 1u, y ^ 1u);
        }
        return traced;
    }
};

} // namespace

TEST_CASE("REFLECTION classification lists exactly the rays, tiles and arguments the rules give", "[reflection]")
{
    auto context = test::CreateValidatedContext();
    const uint32_t w = 37, h = 29; // Partial tiles and quads at the right and bottom edges.
    for (uint32_t raysPerQuad : {1u, 2u, 4u})
    {
        INFO("raysPerQuad " << raysPerQuad);
        ReflectionSettings s;
        s.roughnessThreshold = 0.6f;
        s.raysPerQuad = raysPerQuad;
        s.temporalVarianceThreshold = 0.01f;
        ReflectionRig rig(*context);
        rig.Create(w, h, s);
        const Inputs in(w, h, 11 + raysPerQuad);
        const float range = CommonSettings().denoisingRange;
        // Frames 0..5: frame 0 has no history (rate only), later frames add the pixels whose
        // temporal variance, as the previous frame's denoising wrote it, is high.
        for (uint32_t frame = 0; frame < 6; frame++)
        {
            INFO("frame " << frame);
            std::vector<float> variance;
            if (frame > 0)
                variance = rig.Permanent(rig.VarianceIndex());
            rig.Classify(frame, in);
            const Classification expected = Classify(in, s, frame, frame > 0 ? &variance : nullptr, range);
            rig.CheckClassification(expected);
            // Frame 0 left variance 1 (no history) everywhere it denoised: frame 1 traces them all.
            if (frame == 1 && raysPerQuad < 4)
                CHECK(expected.rays.size() > Classify(in, s, frame, nullptr, range).rays.size());

            // Copies land exactly on the pixels that need the denoiser and trace nothing: every
            // pixel the method processes is written once, no other pixel.
            std::vector<uint8_t> writes;
            std::vector<float> traced = rig.TraceOnCpu(in, writes);
            size_t wrong = 0;
            for (size_t i = 0; i < writes.size(); i++)
                wrong += writes[i] != ((expected.needs[i] || expected.mirror[i]) ? 1 : 0);
            CHECK(wrong == 0);
            REQUIRE(context->UploadTexture(rig.radiance, traced.data()) == VK_SUCCESS);
            rig.Stage(DispatchStage::DENOISING);
        }
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("REFLECTION writes only the tiles that need it, mirrors as traced, finite values", "[reflection]")
{
    auto context = test::CreateValidatedContext();
    const uint32_t w = 40, h = 24;
    ReflectionSettings s;
    s.roughnessThreshold = 0.6f;
    ReflectionRig rig(*context);
    rig.Create(w, h, s);
    const Inputs in(w, h, 5);
    for (uint32_t frame = 0; frame < 4; frame++)
    {
        rig.Classify(frame, in);
        std::vector<uint8_t> writes;
        std::vector<float> traced = rig.TraceOnCpu(in, writes);
        REQUIRE(context->UploadTexture(rig.radiance, traced.data()) == VK_SUCCESS);
        rig.Stage(DispatchStage::DENOISING);
    }
    std::vector<float> out;
    REQUIRE(context->ReadbackTexture(rig.output, out) == VK_SUCCESS);
    const Classification c = Classify(in, s, 3, nullptr, CommonSettings().denoisingRange);
    size_t wrongUntouched = 0, wrongMirror = 0, notFinite = 0, unwritten = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
        {
            const size_t i = size_t(y) * w + x;
            const bool processed = c.needs[i] || c.mirror[i];
            if (!processed)
            {
                // Not the method's pixel: left as it was (this covers whole tiles without any).
                for (int ch = 0; ch < 4; ch++)
                    wrongUntouched += out[i * 4 + ch] != kSentinel;
                continue;
            }
            for (int ch = 0; ch < 4; ch++)
            {
                notFinite += !std::isfinite(out[i * 4 + ch]);
                unwritten += out[i * 4 + ch] == kSentinel;
            }
            if (c.mirror[i])
            {
                // As traced (fp16 input texture).
                std::vector<float> q = test::Quantize(rhi::Format::RGBA16_SFLOAT, {in.radiance.begin() + i * 4, in.radiance.begin() + i * 4 + 4});
                for (int ch = 0; ch < 4; ch++)
                    wrongMirror += std::fabs(out[i * 4 + ch] - q[ch]) > 1e-6f;
            }
        }
    CHECK(c.tiles.size() < size_t((w + 7) / 8) * ((h + 7) / 8)); // The inputs hold tiles without any.
    CHECK(wrongUntouched == 0);
    CHECK(wrongMirror == 0);
    CHECK(notFinite == 0);
    CHECK(unwritten == 0);
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("REFLECTION dispatches split into a classification and a denoising stage", "[reflection]")
{
    const MethodDesc methods[] = {{1, Method::REFLECTION}, {2, Method::REFERENCE}};
    DenoiserCreationDesc desc = {};
    desc.methods = methods;
    desc.methodsNum = 2;
    desc.renderWidth = 64;
    desc.renderHeight = 48;
    Denoiser* denoiser = nullptr;
    REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    REQUIRE(SetCommonSettings(*denoiser, test::StillCameraSettings(1)) == Result::SUCCESS);
    const DenoiserDesc& dd = GetDenoiserDesc(*denoiser);
    uint32_t counters = 0xFFFF;
    for (uint32_t i = 0; i < dd.buffersNum; i++)
        if (dd.buffers[i].content == BufferContent::RAY_COUNTERS)
            counters = i;
    REQUIRE(counters != 0xFFFF);

    const DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    REQUIRE(GetComputeDispatches(*denoiser, nullptr, 0, DispatchStage::CLASSIFICATION, dispatches, num) == Result::SUCCESS);
    REQUIRE(num == 2); // REFERENCE has no classification part.
    CHECK(std::string(dispatches[0].name) == "REFLECTION - Classify");
    CHECK(dispatches[0].gridWidth == 8);
    CHECK(dispatches[0].gridHeight == 6);
    CHECK(std::string(dispatches[1].name) == "REFLECTION - Prepare arguments");
    CHECK_FALSE(dispatches[0].isIndirect);

    REQUIRE(GetComputeDispatches(*denoiser, nullptr, 0, DispatchStage::DENOISING, dispatches, num) == Result::SUCCESS);
    REQUIRE(num == 5);
    const char* names[] = {"REFLECTION - Reproject", "REFLECTION - Spatial", "REFLECTION - Temporal", "REFLECTION - Blur"};
    for (uint32_t i = 0; i < 4; i++)
    {
        CHECK(std::string(dispatches[i].name) == names[i]);
        CHECK(dispatches[i].isIndirect);
        CHECK(dispatches[i].indirectArgumentsBuffer == counters);
        CHECK(dispatches[i].indirectArgumentsOffset == 16u);
        CHECK(dispatches[i].gridWidth == 48); // Every tile: the upper bound.
    }
    CHECK(std::string(dispatches[4].name).find("REFERENCE") == 0);

    REQUIRE(GetComputeDispatches(*denoiser, nullptr, 0, DispatchStage::ALL, dispatches, num) == Result::SUCCESS);
    CHECK(num == 7);
    CHECK(GetComputeDispatches(*denoiser, nullptr, 0, DispatchStage::MAX_NUM, dispatches, num) == Result::INVALID_ARGUMENT);
    DestroyDenoiser(denoiser);
}

TEST_CASE("REFLECTION settings are validated", "[reflection]")
{
    const MethodDesc method = {1, Method::REFLECTION};
    DenoiserCreationDesc desc = {};
    desc.methods = &method;
    desc.methodsNum = 1;
    desc.renderWidth = 16;
    desc.renderHeight = 16;
    Denoiser* denoiser = nullptr;
    REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    CHECK(SetMethodSettings(*denoiser, 1, ReflectionSettings{}) == Result::SUCCESS);
    auto rejected = [&](void (*edit)(ReflectionSettings&)) {
        ReflectionSettings s;
        edit(s);
        return SetMethodSettings(*denoiser, 1, s) == Result::INVALID_ARGUMENT;
    };
    CHECK(rejected([](ReflectionSettings& s) { s.raysPerQuad = 3; }));
    CHECK(rejected([](ReflectionSettings& s) { s.raysPerQuad = 0; }));
    CHECK(rejected([](ReflectionSettings& s) { s.roughnessThreshold = std::numeric_limits<float>::quiet_NaN(); }));
    CHECK(rejected([](ReflectionSettings& s) { s.temporalVarianceThreshold = 0.0f; }));
    CHECK(rejected([](ReflectionSettings& s) { s.maxHistoryFrameNum = REFLECTION_MAX_HISTORY_FRAME_NUM + 1; }));
    CHECK(rejected([](ReflectionSettings& s) { s.historyClipSigma = 0.1f; }));
    CHECK(rejected([](ReflectionSettings& s) { s.depthSigma = 0.0f; }));
    CHECK(rejected([](ReflectionSettings& s) { s.hitDistanceParameters.A = 0.0f; }));
    CHECK(SetMethodSettings(*denoiser, 1, ReferenceSettings{}) == Result::INVALID_ARGUMENT);
    DestroyDenoiser(denoiser);
}
