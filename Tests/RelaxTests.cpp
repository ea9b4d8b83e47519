// RELAX through the Vulkan integration layer on lavapipe, validation on: settings validation, the
// pool memory at 2560x1440, one a-trous iteration against a CPU evaluation, hard edges in normals
// and depth that no energy crosses, restart and confidence, and the denoising of a noisy plane.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

using namespace nrd;
using nrd::test::Bindings;

namespace
{

constexpr Identifier RELAX_ID = 7;
constexpr float kSentinel = -3.0f; // Written into the outputs first; the denoiser writes >= 0.

DenoiserCreationDesc RelaxCreationDesc(Method method, uint32_t w, uint32_t h)
{
    static MethodDesc methodDesc;
    methodDesc = {RELAX_ID, method};
    DenoiserCreationDesc desc = {};
    desc.methods = &methodDesc;
    desc.methodsNum = 1;
    desc.renderWidth = uint16_t(w);
    desc.renderHeight = uint16_t(h);
    return desc;
}

// One frame's application inputs; the camera is the identity (view = world) looking along +z.
struct Inputs
{
    uint32_t width = 0, height = 0;
    std::vector<float> viewZ, normal, mv, diffuse, specular, confidence;

    Inputs(uint32_t w, uint32_t h) : width(w), height(h)
    {
        size_t n = size_t(w) * h;
        viewZ.assign(n, 10.0f);
        normal.resize(n * 4);
        for (size_t i = 0; i < n; i++)
            SetNormal(i, 0.0f, 0.0f, -1.0f, 0.5f);
        mv.assign(n * 2, 0.0f);
        diffuse.assign(n * 4, 0.0f);
        specular.assign(n * 4, 0.0f);
        confidence.assign(n, 1.0f);
    }

    void SetNormal(size_t i, float x, float y, float z, float roughness)
    {
        // RGBA8 storage: the exact unorm8 values, so a CPU evaluation sees what the texture holds.
        normal[i * 4 + 0] = std::round((x * 0.5f + 0.5f) * 255.0f) / 255.0f;
        normal[i * 4 + 1] = std::round((y * 0.5f + 0.5f) * 255.0f) / 255.0f;
        normal[i * 4 + 2] = std::round((z * 0.5f + 0.5f) * 255.0f) / 255.0f;
        normal[i * 4 + 3] = std::round(roughness * 255.0f) / 255.0f;
    }

    bool IsSky(size_t i) const { return !(viewZ[i] > 0.0f) || viewZ[i] > 1e6f; }
};

struct RelaxRig
{
    lab::VulkanContext& context;
    Integration integration;
    uint32_t width = 0, height = 0;
    lab::LabTexture viewZ, normal, mv, diffuse, specular, diffConfidence, specConfidence, outDiffuse, outSpecular;

    explicit RelaxRig(lab::VulkanContext& c) : context(c) {}

    ~RelaxRig()
    {
        integration.Destroy();
        for (lab::LabTexture* t : {&viewZ, &normal, &mv, &diffuse, &specular, &diffConfidence, &specConfidence,
                                   &outDiffuse, &outSpecular})
            context.DestroyTexture(*t);
    }

    void Create(Method method, uint32_t w, uint32_t h, const RelaxSettings& settings)
    {
        width = w;
        height = h;
        DenoiserCreationDesc desc = RelaxCreationDesc(method, w, h);
        IntegrationCreationDesc integrationDesc = context.GetIntegrationCreationDesc();
        integrationDesc.name = "RELAX test";
        REQUIRE(integration.Create(integrationDesc, desc) == VK_SUCCESS);
        REQUIRE(integration.SetMethodSettings(RELAX_ID, settings) == Result::SUCCESS);
        using F = rhi::Format;
        REQUIRE(context.CreateTexture(F::R32_SFLOAT, w, h, "IN_VIEWZ", viewZ) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(F::RGBA8_UNORM, w, h, "IN_NORMAL_ROUGHNESS", normal) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(F::RG16_SFLOAT, w, h, "IN_MV", mv) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(F::RGBA16_SFLOAT, w, h, "IN_DIFF_RADIANCE_HITDIST", diffuse) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(F::RGBA16_SFLOAT, w, h, "IN_SPEC_RADIANCE_HITDIST", specular) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(F::R8_UNORM, w, h, "IN_DIFF_CONFIDENCE", diffConfidence) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(F::R8_UNORM, w, h, "IN_SPEC_CONFIDENCE", specConfidence) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(F::RGBA32_SFLOAT, w, h, "OUT_DIFF_RADIANCE_HITDIST", outDiffuse) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(F::RGBA32_SFLOAT, w, h, "OUT_SPEC_RADIANCE_HITDIST", outSpecular) == VK_SUCCESS);
        std::vector<float> sentinel(size_t(w) * h * 4, kSentinel);
        REQUIRE(context.UploadTexture(outDiffuse, sentinel.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(outSpecular, sentinel.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
    }

    // Denoises one frame; 'outDiff' / 'outSpec' receive the outputs (RGBA).
    void Frame(const CommonSettings& settings, const Inputs& in, std::vector<float>& outDiff, std::vector<float>& outSpec)
    {
        REQUIRE(context.UploadTexture(viewZ, in.viewZ.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(normal, in.normal.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(mv, in.mv.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(diffuse, in.diffuse.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(specular, in.specular.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(diffConfidence, in.confidence.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(specConfidence, in.confidence.data()) == VK_SUCCESS);
        REQUIRE(integration.SetCommonSettings(settings) == Result::SUCCESS);
        Bindings bindings = {{ResourceType::IN_VIEWZ, &viewZ},
                             {ResourceType::IN_NORMAL_ROUGHNESS, &normal},
                             {ResourceType::IN_MV, &mv},
                             {ResourceType::IN_DIFF_RADIANCE_HITDIST, &diffuse},
                             {ResourceType::IN_SPEC_RADIANCE_HITDIST, &specular},
                             {ResourceType::IN_DIFF_CONFIDENCE, &diffConfidence},
                             {ResourceType::IN_SPEC_CONFIDENCE, &specConfidence},
                             {ResourceType::OUT_DIFF_RADIANCE_HITDIST, &outDiffuse},
                             {ResourceType::OUT_SPEC_RADIANCE_HITDIST, &outSpecular}};
        REQUIRE(test::DenoiseAndWait(context, integration, bindings) == VK_SUCCESS);
        REQUIRE(context.ReadbackTexture(outDiffuse, outDiff) == VK_SUCCESS);
        REQUIRE(context.ReadbackTexture(outSpecular, outSpec) == VK_SUCCESS);
    }
};

// The dispatch list of a bare core denoiser for one frame (pool indices are the Integration's).
std::vector<DispatchDesc> Dispatches(Method method, uint32_t w, uint32_t h, const RelaxSettings& settings,
                                     std::vector<std::vector<ResourceDesc>>& resources)
{
    DenoiserCreationDesc desc = RelaxCreationDesc(method, w, h);
    Denoiser* denoiser = nullptr;
    REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    REQUIRE(SetMethodSettings(*denoiser, RELAX_ID, settings) == Result::SUCCESS);
    REQUIRE(SetCommonSettings(*denoiser, test::StillCameraSettings(0)) == Result::SUCCESS);
    const DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    REQUIRE(GetComputeDispatches(*denoiser, nullptr, 0, dispatches, num) == Result::SUCCESS);
    std::vector<DispatchDesc> result(dispatches, dispatches + num);
    resources.clear();
    for (const DispatchDesc& d : result)
        resources.emplace_back(d.resources, d.resources + d.resourcesNum);
    DestroyDenoiser(denoiser);
    return result;
}

// CPU evaluation of one a-trous iteration (Relax_Atrous.comp) for the identity camera of
// StillCameraSettings (frustum {1, 0, 1, 0}: X = viewZ * (ndc.x, ndc.y, 1)).
struct AtrousParams
{
    int step = 1;
    bool isSpecular = false, isLast = false, roughnessStop = true;
    float phiLuminance = 2.0f, lobeAngleFraction = 0.5f, lobeAngleSlack = 0.0f, roughnessFraction = 0.15f;
    float depthThreshold = 0.01f;
};

struct Surface
{
    float X[3] = {}, N[3] = {}, z = 0.0f, roughness = 1.0f;
};

Surface LoadSurface(const Inputs& in, int x, int y)
{
    Surface s;
    if (x < 0 || y < 0 || x >= int(in.width) || y >= int(in.height))
        return s;
    size_t i = size_t(y) * in.width + x;
    if (in.IsSky(i))
        return s;
    s.z = in.viewZ[i];
    float ndcX = (float(x) + 0.5f) / float(in.width) * 2.0f - 1.0f;
    float ndcY = (float(y) + 0.5f) / float(in.height) * 2.0f - 1.0f;
    s.X[0] = s.z * ndcX;
    s.X[1] = s.z * ndcY;
    s.X[2] = s.z;
    float n[3], len = 0.0f;
    for (int c = 0; c < 3; c++)
    {
        n[c] = in.normal[i * 4 + c] * 2.0f - 1.0f;
        len += n[c] * n[c];
    }
    len = std::sqrt(len);
    for (int c = 0; c < 3; c++)
        s.N[c] = n[c] / len;
    s.roughness = in.normal[i * 4 + 3];
    return s;
}

float Luminance(const float* c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }
float Saturate(float x) { return std::min(std::max(x, 0.0f), 1.0f); }

// 'src' RGBA (radiance, variance); 'hit' RGBA whose .w is the hit distance (last iteration).
std::vector<float> AtrousReference(const Inputs& in, const std::vector<float>& src, const std::vector<float>& hit,
                                   const AtrousParams& p)
{
    const int w = int(in.width), h = int(in.height);
    std::vector<float> out(src.size(), kSentinel);
    const float kernel[3] = {3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
        {
            Surface c = LoadSurface(in, x, y);
            if (c.z == 0.0f)
                continue;
            const float* center = &src[(size_t(y) * w + x) * 4];
            double variance = 0.0, varianceWeight = 0.0;
            for (int j = -1; j <= 1; j++)
                for (int i = -1; i <= 1; i++)
                {
                    int qx = x + i * p.step, qy = y + j * p.step;
                    if (LoadSurface(in, qx, qy).z == 0.0f)
                        continue;
                    double k = (i == 0 ? 0.5 : 0.25) * (j == 0 ? 0.5 : 0.25);
                    variance += k * src[(size_t(qy) * w + qx) * 4 + 3];
                    varianceWeight += k;
                }
            variance /= varianceWeight;
            float r = p.isSpecular ? c.roughness : 1.0f;
            float maxAngle = p.lobeAngleFraction * std::atan(3.0f * r * r) + p.lobeAngleSlack;
            float lumaScale = 1.0f / (p.phiLuminance * float(std::sqrt(std::max(variance, 0.0))) + 1e-6f);
            float lumaCenter = Luminance(center);
            double sum[3] = {}, varianceSum = 0.0, weightSum = 0.0, hitSum = 0.0;
            for (int j = -2; j <= 2; j++)
                for (int i = -2; i <= 2; i++)
                {
                    int qx = x + i * p.step, qy = y + j * p.step;
                    Surface t = LoadSurface(in, qx, qy);
                    if (t.z == 0.0f)
                        continue;
                    const float* tap = &src[(size_t(qy) * w + qx) * 4];
                    double weight = 1.0;
                    if (i != 0 || j != 0)
                    {
                        float cosAngle = std::min(std::max(c.N[0] * t.N[0] + c.N[1] * t.N[1] + c.N[2] * t.N[2], -1.0f), 1.0f);
                        weight = Saturate(1.0f - std::acos(cosAngle) / maxAngle);
                        float distance = std::fabs(c.N[0] * (t.X[0] - c.X[0]) + c.N[1] * (t.X[1] - c.X[1]) +
                                                   c.N[2] * (t.X[2] - c.X[2]));
                        weight *= Saturate(1.0f - distance / (p.depthThreshold * c.z));
                        if (p.isSpecular && p.roughnessStop)
                            weight *= Saturate(1.0f - std::fabs(c.roughness - t.roughness) /
                                                          (p.roughnessFraction * c.roughness + 0.01f));
                        weight *= std::exp(-std::fabs(Luminance(tap) - lumaCenter) * lumaScale);
                    }
                    weight *= kernel[std::abs(i)] * kernel[std::abs(j)];
                    if (weight <= 0.0)
                        continue;
                    for (int ch = 0; ch < 3; ch++)
                        sum[ch] += weight * tap[ch];
                    varianceSum += weight * weight * tap[3];
                    weightSum += weight;
                    hitSum += weight * hit[(size_t(qy) * w + qx) * 4 + 3];
                }
            float* o = &out[(size_t(y) * w + x) * 4];
            for (int ch = 0; ch < 3; ch++)
                o[ch] = float(sum[ch] / weightSum);
            o[3] = float(p.isLast ? hitSum / weightSum : varianceSum / (weightSum * weightSum));
        }
    return out;
}

// Random surfaces: two depth layers, tilted normals, sky holes, random roughness and signals.
Inputs RandomInputs(uint32_t w, uint32_t h, uint32_t seed)
{
    Inputs in(w, h);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
        {
            size_t i = size_t(y) * w + x;
            in.viewZ[i] = (x + y / 3) % 17 < 9 ? 10.0f + 0.01f * float(x) : 14.0f;
            if (u(rng) < 0.04f)
                in.viewZ[i] = 1e7f;
            float tx = (u(rng) - 0.5f) * 0.4f, ty = (u(rng) - 0.5f) * 0.4f;
            float len = std::sqrt(tx * tx + ty * ty + 1.0f);
            in.SetNormal(i, tx / len, ty / len, -1.0f / len, 0.05f + 0.9f * u(rng));
            for (int c = 0; c < 3; c++)
            {
                in.diffuse[i * 4 + c] = u(rng) < 0.1f ? 8.0f * u(rng) : u(rng);
                in.specular[i * 4 + c] = u(rng) * u(rng) * 2.0f;
            }
            in.diffuse[i * 4 + 3] = u(rng);
            in.specular[i * 4 + 3] = u(rng);
        }
    return in;
}

size_t CompareNonSky(const Inputs& in, const std::vector<float>& actual, const std::vector<float>& expected,
                     uint32_t channels, float relTolerance, float absTolerance, double& maxDiff)
{
    size_t mismatches = 0;
    maxDiff = 0.0;
    for (size_t i = 0; i < size_t(in.width) * in.height; i++)
    {
        if (in.IsSky(i))
            continue;
        for (uint32_t c = 0; c < channels; c++)
        {
            float a = actual[i * 4 + c], e = expected[i * 4 + c];
            double d = std::fabs(double(a) - double(e));
            maxDiff = std::max(maxDiff, d / (std::fabs(e) + absTolerance));
            if (!(d <= absTolerance + relTolerance * std::fabs(e)) && mismatches++ < 5)
                std::printf("  pixel %zu channel %u: got %.7g, expected %.7g\n", i, c, a, e);
        }
    }
    return mismatches;
}

} // namespace

TEST_CASE("RELAX settings are validated and the wrong settings type is refused", "[api]")
{
    DenoiserCreationDesc desc = RelaxCreationDesc(Method::RELAX_DIFFUSE_SPECULAR, 16, 16);
    Denoiser* denoiser = nullptr;
    REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    CHECK(SetMethodSettings(*denoiser, RELAX_ID, RelaxSettings{}) == Result::SUCCESS);
    auto rejects = [&](void (*edit)(RelaxSettings&)) {
        RelaxSettings s;
        edit(s);
        return SetMethodSettings(*denoiser, RELAX_ID, s) == Result::INVALID_ARGUMENT;
    };
    CHECK(rejects([](RelaxSettings& s) { s.atrousIterationNum = 1; }));
    CHECK(rejects([](RelaxSettings& s) { s.atrousIterationNum = 9; }));
    CHECK(rejects([](RelaxSettings& s) { s.diffuseMaxAccumulatedFrameNum = RELAX_MAX_HISTORY_FRAME_NUM + 1; }));
    CHECK(rejects([](RelaxSettings& s) { s.specularMaxFastAccumulatedFrameNum = 31; }));
    CHECK(rejects([](RelaxSettings& s) { s.historyFixFrameNum = 4; }));
    CHECK(rejects([](RelaxSettings& s) { s.depthThreshold = 0.0f; }));
    CHECK(rejects([](RelaxSettings& s) { s.diffusePhiLuminance = std::nanf(""); }));
    CHECK(rejects([](RelaxSettings& s) { s.specularLobeAngleSlack = INFINITY; }));
    CHECK(rejects([](RelaxSettings& s) { s.checkerboardMode = CheckerboardMode(3); }));
    RelaxSettings limits;
    limits.atrousIterationNum = 8;
    limits.diffuseMaxAccumulatedFrameNum = limits.diffuseMaxFastAccumulatedFrameNum = 0;
    limits.historyFixFrameNum = 0;
    limits.antilagSigmaScale = 0.0f;
    CHECK(SetMethodSettings(*denoiser, RELAX_ID, limits) == Result::SUCCESS);
    CHECK(SetMethodSettings(*denoiser, RELAX_ID, SigmaSettings{}) == Result::INVALID_ARGUMENT);
    DestroyDenoiser(denoiser);
}

TEST_CASE("RELAX_DIFFUSE_SPECULAR pool memory at 2560x1440 is what its formats add up to, under 60% of NRD's", "[api]")
{
    // Per pixel: permanent 2 x (RGBA16F + RGBA16F + RG8) + R16F = 38 bytes; transient (shared by the
    // two signals) RGBA16F + RG8 = 10 bytes, plus the 1/64-size tile map.
    DenoiserCreationDesc desc = RelaxCreationDesc(Method::RELAX_DIFFUSE_SPECULAR, 2560, 1440);
    Denoiser* denoiser = nullptr;
    REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    const DenoiserDesc& d = GetDenoiserDesc(*denoiser);
    auto bytes = [](const TextureDesc* pool, uint32_t num) {
        uint64_t total = 0;
        for (uint32_t i = 0; i < num; i++)
            total += uint64_t(GetFormatBytesPerPixel(pool[i].format)) * ((2560 + pool[i].downsampleX - 1) / pool[i].downsampleX) *
                     ((1440 + pool[i].downsampleY - 1) / pool[i].downsampleY);
        return total;
    };
    uint64_t permanent = bytes(d.permanentPool, d.permanentPoolSize), transient = bytes(d.transientPool, d.transientPoolSize);
    const double kNrdMegabytes = 300.06; // NRD's published RELAX diffuse + specular memory at 1440p (document 004).
    double total = double(permanent + transient) / 1e6;
    std::printf("RELAX_DIFFUSE_SPECULAR at 2560x1440: permanent %.2f MB, transient %.2f MB, total %.2f MB (%.1f%% of NRD's)\n",
                double(permanent) / 1e6, double(transient) / 1e6, total, 100.0 * total / kNrdMegabytes);
    CHECK(permanent == 38ull * 2560 * 1440);
    CHECK(transient == 10ull * 2560 * 1440 + 320 * 180);
    CHECK(total <= 0.6 * kNrdMegabytes);
    DestroyDenoiser(denoiser);
}

TEST_CASE("RELAX dispatches one a-trous pass per iteration, alternating so that the last writes the output", "[api]")
{
    for (Method method : {Method::RELAX_DIFFUSE, Method::RELAX_SPECULAR, Method::RELAX_DIFFUSE_SPECULAR})
        for (uint32_t n = 2; n <= 8; n++)
        {
            INFO(GetMethodString(method) << ", " << n << " iterations");
            RelaxSettings settings;
            settings.atrousIterationNum = n;
            std::vector<std::vector<ResourceDesc>> resources;
            std::vector<DispatchDesc> dispatches = Dispatches(method, 16, 16, settings, resources);
            const uint32_t chains = method == Method::RELAX_DIFFUSE_SPECULAR ? 2 : 1;
            // Classification, then per chain: temporal, history fix, variance, n a-trous.
            CHECK(dispatches.size() == 1 + chains * (3 + n));
            ResourceType previousOutput = ResourceType::MAX_NUM;
            uint32_t atrous = 0;
            for (size_t i = 0; i < dispatches.size(); i++)
            {
                std::string name = dispatches[i].name;
                const std::vector<ResourceDesc>& r = resources[i];
                if (name.find("variance") != std::string::npos)
                    previousOutput = r.back().type;
                if (name.find("a-trous") == std::string::npos)
                    continue;
                // Each iteration reads what the previous one (or the variance estimation) wrote.
                CHECK(r[3].type == previousOutput);
                CHECK(r[3].type != r[5].type);
                previousOutput = r[5].type;
                atrous++;
                if (atrous % n == 0)
                    CHECK(std::string(GetResourceTypeString(r[5].type)).rfind("OUT_", 0) == 0);
            }
            CHECK(atrous == chains * n);
        }
}

// CPU evaluation of the variance estimation with the spatial estimate off (Relax_SpatialVariance.comp):
// (radiance, max(E[l^2] - E[l]^2, 0) / history length) from the permanent histories (the RG8 length
// texture read back: .x the length in the low 6 bits, .y the lighting change record in the top 3
// bits, where the lighting moves from 2 on and the variance is a quarter), the variance rounded to
// fp16 as the pass stores it.
std::vector<float> VarianceReference(const Inputs& in, const std::vector<float>& slow, const std::vector<float>& fast,
                                     const std::vector<float>& lengthRecord, bool truncate)
{
    std::vector<float> out(slow.size(), kSentinel);
    for (size_t i = 0; i < size_t(in.width) * in.height; i++)
    {
        if (in.IsSky(i))
            continue;
        float m1 = Luminance(&slow[i * 4]), m2 = fast[i * 4 + 3] * fast[i * 4 + 3];
        const uint32_t x = uint32_t(std::floor(lengthRecord[i * 2] * 255.0f + 0.5f));
        const uint32_t record = uint32_t(std::floor(lengthRecord[i * 2 + 1] * 255.0f + 0.5f)) >> 5u;
        float n = std::max(float(x & 63u), 1.0f);
        for (int c = 0; c < 3; c++)
            out[i * 4 + c] = slow[i * 4 + c];
        out[i * 4 + 3] = test::RoundToHalf(std::max(m2 - m1 * m1, 0.0f) / n * (record >= 2u ? 0.25f : 1.0f), truncate);
    }
    return out;
}

TEST_CASE("RELAX variance estimation and a-trous iterations equal a CPU evaluation", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const uint32_t w = 45, h = 29;
    Inputs in = RandomInputs(w, h, 3);
    for (Method method : {Method::RELAX_DIFFUSE, Method::RELAX_SPECULAR})
    {
        const bool isSpecular = method == Method::RELAX_SPECULAR;
        INFO((isSpecular ? "specular" : "diffuse"));
        RelaxSettings settings;
        settings.atrousIterationNum = 2;
        settings.spatialVarianceEstimationHistoryThreshold = 0;
        std::vector<std::vector<ResourceDesc>> resources;
        std::vector<DispatchDesc> dispatches = Dispatches(method, w, h, settings, resources);
        // Two iterations: the variance estimation writes the output texture, iteration 0 (shared
        // memory) reads it and writes the transient texture, iteration 1 reads that and the slow
        // history and writes the output.
        int variance = -1, first = -1, last = -1;
        for (size_t i = 0; i < dispatches.size(); i++)
        {
            std::string name = dispatches[i].name;
            if (name.find("variance") != std::string::npos)
                variance = int(i);
            if (name.find("a-trous") != std::string::npos)
                (first < 0 ? first : last) = int(i);
        }
        REQUIRE(variance >= 0);
        REQUIRE(first > variance);
        REQUIRE(last > first);
        const ResourceType output = isSpecular ? ResourceType::OUT_SPEC_RADIANCE_HITDIST : ResourceType::OUT_DIFF_RADIANCE_HITDIST;
        const std::vector<ResourceDesc>& v = resources[size_t(variance)];
        REQUIRE(v[6].type == output);
        REQUIRE(resources[size_t(first)][3].type == output);
        REQUIRE(resources[size_t(first)][5].type == ResourceType::TRANSIENT_POOL);
        REQUIRE(resources[size_t(last)][3].type == ResourceType::TRANSIENT_POOL);
        REQUIRE(resources[size_t(last)][4].type == ResourceType::PERMANENT_POOL);
        REQUIRE(resources[size_t(last)][5].type == output);
        for (int k : {3, 4, 5})
            REQUIRE(v[size_t(k)].type == ResourceType::PERMANENT_POOL);

        RelaxRig rig(*context);
        rig.Create(method, w, h, settings);
        std::vector<float> outDiff, outSpec;
        for (uint32_t frame = 0; frame < 2; frame++)
            rig.Frame(test::StillCameraSettings(frame), in, outDiff, outSpec);
        const std::vector<float>& out = isSpecular ? outSpec : outDiff;
        auto permanent = [&](size_t k) {
            return test::ReadbackPoolTexture(*context, rig.integration, ResourceType::PERMANENT_POOL, v[k].indexInPool);
        };
        std::vector<float> slow = permanent(3), fast = permanent(4), length = permanent(5);
        // RG8: history length and confidence debt (.x), lighting change record and residual (.y).
        REQUIRE(length.size() == 2u * w * h);
        std::vector<float> b = test::ReadbackPoolTexture(*context, rig.integration, ResourceType::TRANSIENT_POOL,
                                                         resources[size_t(first)][5].indexInPool);

        AtrousParams p;
        p.isSpecular = isSpecular;
        p.phiLuminance = isSpecular ? settings.specularPhiLuminance : settings.diffusePhiLuminance;
        p.lobeAngleFraction = isSpecular ? settings.specularLobeAngleFraction : settings.diffuseLobeAngleFraction;
        p.lobeAngleSlack = isSpecular ? settings.specularLobeAngleSlack * 3.14159265f / 180.0f : 0.0f;
        p.roughnessFraction = settings.roughnessFraction;
        p.depthThreshold = settings.depthThreshold;
        // The implementation chooses how a 16-bit float store rounds (lavapipe: toward zero): the
        // closer of the two evaluations is compared.
        double maxDiff = 0.0, maxDiffOther = 0.0;
        std::vector<float> a = VarianceReference(in, slow, fast, length, true);
        std::vector<float> expectedB = AtrousReference(in, a, slow, p);
        size_t mismatches = CompareNonSky(in, b, expectedB, 4, 2e-3f, 1e-4f, maxDiff);
        std::vector<float> aNearest = VarianceReference(in, slow, fast, length, false);
        size_t mismatchesNearest = CompareNonSky(in, b, AtrousReference(in, aNearest, slow, p), 4, 2e-3f, 1e-4f, maxDiffOther);
        if (mismatchesNearest < mismatches)
        {
            std::swap(mismatches, mismatchesNearest);
            std::swap(maxDiff, maxDiffOther);
            a.swap(aNearest);
        }
        CHECK(mismatches == 0);
        std::printf("RELAX %s variance + a-trous step 1 (shared memory) vs CPU: max relative difference %.2e\n",
                    isSpecular ? "specular" : "diffuse", maxDiff);
        p.step = 2;
        p.isLast = true;
        std::vector<float> expectedOut = AtrousReference(in, b, slow, p);
        CHECK(CompareNonSky(in, out, expectedOut, 4, 2e-3f, 1e-4f, maxDiff) == 0);
        std::printf("RELAX %s a-trous step 2 (last) vs CPU: max relative difference %.2e\n",
                    isSpecular ? "specular" : "diffuse", maxDiff);
        // The same tolerance rejects a neighbouring filter (the step doubled).
        p.step = 4;
        std::vector<float> wrong = AtrousReference(in, b, slow, p);
        CHECK(CompareNonSky(in, out, wrong, 3, 2e-3f, 1e-4f, maxDiff) > 50);
        // Sky pixels are not written.
        for (size_t i = 0; i < size_t(w) * h; i++)
            if (in.IsSky(i))
                CHECK(out[i * 4] == kSentinel);

        // Three iterations: the third (step 4) reads the transient texture (the second's result)
        // and writes the output.
        RelaxSettings settings3 = settings;
        settings3.atrousIterationNum = 3;
        std::vector<std::vector<ResourceDesc>> resources3;
        std::vector<DispatchDesc> dispatches3 = Dispatches(method, w, h, settings3, resources3);
        int third = -1;
        for (size_t i = 0; i < dispatches3.size(); i++)
            if (std::string(dispatches3[i].name).find("a-trous") != std::string::npos)
                third = int(i);
        REQUIRE(third >= 0);
        REQUIRE(resources3[size_t(third)][3].type == ResourceType::TRANSIENT_POOL);
        REQUIRE(resources3[size_t(third)][5].type == output);
        RelaxRig rig3(*context);
        rig3.Create(method, w, h, settings3);
        for (uint32_t frame = 0; frame < 2; frame++)
            rig3.Frame(test::StillCameraSettings(frame), in, outDiff, outSpec);
        std::vector<float> second = test::ReadbackPoolTexture(*context, rig3.integration, ResourceType::TRANSIENT_POOL,
                                                              resources3[size_t(third)][3].indexInPool);
        std::vector<float> slow3 = test::ReadbackPoolTexture(*context, rig3.integration, ResourceType::PERMANENT_POOL,
                                                             resources3[size_t(third)][4].indexInPool);
        p.step = 4;
        p.isLast = true;
        CHECK(CompareNonSky(in, isSpecular ? outSpec : outDiff, AtrousReference(in, second, slow3, p), 4, 2e-3f, 1e-4f,
                            maxDiff) == 0);
        std::printf("RELAX %s a-trous step 4 (last) vs CPU: max relative difference %.2e\n",
                    isSpecular ? "specular" : "diffuse", maxDiff);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("RELAX keeps hard edges in normals and in depth: no energy crosses them", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const uint32_t w = 48, h = 24;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.5f, 2.0f);
    for (bool depthEdge : {false, true})
        for (bool darkLeft : {true, false})
            for (Method method : {Method::RELAX_DIFFUSE, Method::RELAX_SPECULAR})
            {
                INFO((depthEdge ? "depth edge" : "normal edge") << (darkLeft ? ", dark left" : ", dark right")
                                                                << (method == Method::RELAX_SPECULAR ? ", specular" : ", diffuse"));
                RelaxSettings settings;
                settings.historyFixFrameNum = 0; // Its cos^8 normal weight is soft by design.
                settings.atrousIterationNum = 5;
                RelaxRig rig(*context);
                rig.Create(method, w, h, settings);
                for (uint32_t frame = 0; frame < 3; frame++)
                {
                    Inputs in(w, h);
                    for (uint32_t y = 0; y < h; y++)
                        for (uint32_t x = 0; x < w; x++)
                        {
                            size_t i = size_t(y) * w + x;
                            bool right = x >= w / 2 + 3;
                            if (right && depthEdge)
                                in.viewZ[i] = 13.0f;
                            if (right && !depthEdge)
                                in.SetNormal(i, 0.0f, 0.8660254f, -0.5f, 0.5f); // 60 degrees about x.
                            bool dark = right != darkLeft;
                            for (int c = 0; c < 4; c++)
                            {
                                float v = dark ? 0.0f : u(rng);
                                in.diffuse[i * 4 + c] = v;
                                in.specular[i * 4 + c] = v;
                            }
                        }
                    std::vector<float> outDiff, outSpec;
                    rig.Frame(test::StillCameraSettings(frame), in, outDiff, outSpec);
                    const std::vector<float>& out = method == Method::RELAX_SPECULAR ? outSpec : outDiff;
                    size_t leaks = 0, lit = 0;
                    for (uint32_t y = 0; y < h; y++)
                        for (uint32_t x = 0; x < w; x++)
                        {
                            size_t i = size_t(y) * w + x;
                            bool dark = (x >= w / 2 + 3) != darkLeft;
                            for (int c = 0; c < 4; c++)
                            {
                                leaks += dark && out[i * 4 + c] != 0.0f;
                                lit += !dark && c < 3 && out[i * 4 + c] > 0.25f && std::isfinite(out[i * 4 + c]);
                            }
                        }
                    CHECK(leaks == 0);
                    size_t litPixels = size_t(w / 2 + (darkLeft ? -3 : 3)) * h;
                    CHECK(lit == 3 * litPixels);
                }
            }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("RELAX diffuse keeps the history short where a line of light moves over a still surface, long elsewhere",
          "[vulkan]")
{
    // A still plane at 0.45 crossed by a line of light one pixel high (1.3) that moves down one row
    // every two frames (venetian_blinds' stripes, without motion vectors): the change test finds the
    // rows it crosses (this frame's and the previous frame's samples above their fast histories) and
    // the lighting change record keeps their histories at 2 + 1 frames; rows the line never reaches
    // accumulate every frame. The permanent length texture (RG8) is read back: .x the length (low 6
    // bits), .y the record (top 3 bits, moving from 2 on).
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const uint32_t w = 40, h = 32, frames = 16, firstRow = 4;
    RelaxSettings settings;
    std::vector<std::vector<ResourceDesc>> resources;
    std::vector<DispatchDesc> dispatches = Dispatches(Method::RELAX_DIFFUSE, w, h, settings, resources);
    int variance = -1;
    for (size_t i = 0; i < dispatches.size() && variance < 0; i++)
        if (std::string(dispatches[i].name).find("variance") != std::string::npos)
            variance = int(i);
    REQUIRE(variance >= 0);
    const ResourceDesc lengthDesc = resources[size_t(variance)][5];
    REQUIRE(lengthDesc.type == ResourceType::PERMANENT_POOL);

    RelaxRig rig(*context);
    rig.Create(Method::RELAX_DIFFUSE, w, h, settings);
    Inputs in(w, h);
    std::vector<float> outDiff, outSpec;
    uint32_t row = firstRow;
    for (uint32_t frame = 0; frame < frames; frame++)
    {
        row = firstRow + frame / 2;
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
            {
                size_t i = size_t(y) * w + x;
                float v = y == row ? 1.3f : 0.45f;
                for (int c = 0; c < 3; c++)
                    in.diffuse[i * 4 + c] = v;
                in.diffuse[i * 4 + 3] = 0.5f;
            }
        rig.Frame(test::StillCameraSettings(frame), in, outDiff, outSpec);
    }
    std::vector<float> length =
        test::ReadbackPoolTexture(*context, rig.integration, ResourceType::PERMANENT_POOL, lengthDesc.indexInPool);
    REQUIRE(length.size() == 2u * w * h);
    auto at = [&](uint32_t x, uint32_t y, int c) { return uint32_t(std::floor(length[(size_t(y) * w + x) * 2 + c] * 255.0f + 0.5f)); };
    size_t shortOnLine = 0, longAway = 0;
    for (uint32_t x = 4; x < w - 4; x++)
    {
        // The line's row this frame (it arrived the frame before): moving, 2 + 1 frames.
        uint32_t n = at(x, row, 0) & 63u, record = at(x, row, 1) >> 5u;
        shortOnLine += record >= 2u && n <= 3u;
        // Rows 8 and more below the line's last row: never lit, every frame accumulated.
        longAway += (at(x, row + 8, 0) & 63u) == frames && (at(x, row + 8, 1) >> 5u) == 0u;
    }
    CHECK(shortOnLine == w - 8);
    CHECK(longAway == w - 8);
    // The output shows the line: its row above the rows around it.
    for (uint32_t x = 4; x < w - 4; x++)
    {
        INFO("x " << x);
        CHECK(outDiff[(size_t(row) * w + x) * 4] > outDiff[(size_t(row + 4) * w + x) * 4] + 0.2f);
    }
    CHECK(context->ValidationMessageCount() == 0);
}
