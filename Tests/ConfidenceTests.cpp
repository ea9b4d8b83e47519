// CONFIDENCE: settings validation, dispatch sequence and memory of the descriptions (core only),
// and on lavapipe: the a-trous filter, normalization, conversion and temporal filter equal to a CPU
// evaluation of the same steps (fp16 pool storage included), zero gradients give exactly 1, the
// temporal filter bounds the change per frame, sky is not written.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace nrd;
using nrd::test::Bindings;

namespace
{

constexpr Identifier kId = 5;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kSentinel = -7.0f;

struct LogCapture
{
    std::vector<std::string> messages;
    static void Callback(void* user, LogSeverity, const char* message)
    {
        static_cast<LogCapture*>(user)->messages.push_back(message);
    }
};

struct CoreDenoiser
{
    Denoiser* denoiser = nullptr;
    LogCapture log;
    explicit CoreDenoiser(uint16_t w = 64, uint16_t h = 64)
    {
        MethodDesc m = {kId, Method::CONFIDENCE};
        DenoiserCreationDesc desc = {};
        desc.methods = &m;
        desc.methodsNum = 1;
        desc.renderWidth = w;
        desc.renderHeight = h;
        desc.logCallback = LogCapture::Callback;
        desc.logUserArg = &log;
        REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    }
    ~CoreDenoiser() { DestroyDenoiser(denoiser); }
};

} // namespace

TEST_CASE("ConfidenceSettings outside their ranges are rejected with the field's name", "[api][confidence]")
{
    CoreDenoiser d;
    CHECK(SetMethodSettings(*d.denoiser, kId, ConfidenceSettings{}) == Result::SUCCESS);
    CHECK(SetMethodSettings(*d.denoiser, kId, ReblurSettings{}) == Result::INVALID_ARGUMENT);

    struct Bad
    {
        const char* field;
        void (*edit)(ConfidenceSettings&);
    };
    const Bad bad[] = {
        {"gradientThreshold", [](ConfidenceSettings& s) { s.gradientThreshold = 1.0f; }},
        {"gradientThreshold", [](ConfidenceSettings& s) { s.gradientThreshold = kNaN; }},
        {"gradientSensitivity", [](ConfidenceSettings& s) { s.gradientSensitivity = 0.5f; }},
        {"gradientSensitivity", [](ConfidenceSettings& s) { s.gradientSensitivity = 1001.0f; }},
        {"specularGradientSensitivity", [](ConfidenceSettings& s) { s.specularGradientSensitivity = 0.5f; }},
        {"specularGradientSensitivity", [](ConfidenceSettings& s) { s.specularGradientSensitivity = kNaN; }},
        {"fallHistoryWeight", [](ConfidenceSettings& s) { s.fallHistoryWeight = 1.0f; }},
        {"riseHistoryWeight", [](ConfidenceSettings& s) { s.riseHistoryWeight = -0.1f; }},
        {"atrousPassNum", [](ConfidenceSettings& s) { s.atrousPassNum = 0; }},
        {"atrousPassNum", [](ConfidenceSettings& s) { s.atrousPassNum = CONFIDENCE_MAX_ATROUS_PASS_NUM + 1; }},
        {"depthThreshold", [](ConfidenceSettings& s) { s.depthThreshold = 1.5f; }},
        {"normalPower", [](ConfidenceSettings& s) { s.normalPower = -1.0f; }},
        {"localGradientRadius", [](ConfidenceSettings& s) { s.localGradientRadius = CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS + 1; }},
    };
    for (const Bad& b : bad)
    {
        INFO(b.field);
        ConfidenceSettings s;
        b.edit(s);
        d.log.messages.clear();
        CHECK(SetMethodSettings(*d.denoiser, kId, s) == Result::INVALID_ARGUMENT);
        REQUIRE(d.log.messages.size() == 1);
        CHECK(d.log.messages[0].find(std::string("ConfidenceSettings::") + b.field) != std::string::npos);
    }
}

TEST_CASE("CONFIDENCE dispatches one a-trous pass per setting, the local limit's pass and one temporal pass; "
          "1/3-resolution transients",
          "[api][confidence]")
{
    CoreDenoiser d(1920, 1080);
    for (uint32_t passes : {1u, 4u, 5u})
    {
        ConfidenceSettings s;
        s.atrousPassNum = passes;
        s.localGradientRadius = passes == 1 ? 0 : 3; // 0: no local pass.
        const uint32_t local = s.localGradientRadius > 0 ? 1 : 0;
        REQUIRE(SetMethodSettings(*d.denoiser, kId, s) == Result::SUCCESS);
        REQUIRE(SetCommonSettings(*d.denoiser, test::StillCameraSettings(1)) == Result::SUCCESS);
        const DispatchDesc* dispatches = nullptr;
        uint32_t num = 0;
        REQUIRE(GetComputeDispatches(*d.denoiser, nullptr, 0, dispatches, num) == Result::SUCCESS);
        REQUIRE(num == passes + local + 1);
        for (uint32_t i = 0; i < passes; i++)
        {
            CHECK(std::string(dispatches[i].name) == "CONFIDENCE - Filter gradients (step " + std::to_string(1 << i) + ")");
            CHECK(dispatches[i].gridWidth == (640u + 7u) / 8u); // 1920 / 3 strata in groups of 8.
        }
        if (local)
        {
            CHECK(std::string(dispatches[passes].name) == "CONFIDENCE - Local gradients");
            CHECK(dispatches[passes].gridWidth == (640u + 7u) / 8u);
        }
        CHECK(std::string(dispatches[passes + local].name) == "CONFIDENCE - Temporal");
    }
    // Memory: two RG16f histories at full resolution, three RGBA16f transients at 1/3 (a-trous
    // ping-pong, the local limit's box means).
    const DenoiserDesc& desc = GetDenoiserDesc(*d.denoiser);
    uint64_t permanent = 0, transient = 0;
    for (uint32_t i = 0; i < desc.permanentPoolSize; i++)
        permanent += uint64_t(GetFormatBytesPerPixel(desc.permanentPool[i].format)) *
                     ((1920u + desc.permanentPool[i].downsampleX - 1) / desc.permanentPool[i].downsampleX) *
                     ((1080u + desc.permanentPool[i].downsampleY - 1) / desc.permanentPool[i].downsampleY);
    for (uint32_t i = 0; i < desc.transientPoolSize; i++)
        transient += uint64_t(GetFormatBytesPerPixel(desc.transientPool[i].format)) *
                     ((1920u + desc.transientPool[i].downsampleX - 1) / desc.transientPool[i].downsampleX) *
                     ((1080u + desc.transientPool[i].downsampleY - 1) / desc.transientPool[i].downsampleY);
    CHECK(permanent == 2ull * 4 * 1920 * 1080);
    CHECK(transient == 3ull * 8 * 640 * 360);
}

namespace
{

// Still camera, a plane facing it at viewZ 4 (edge-stopping weights all 1), the first row sky.
struct ConfidenceRig
{
    static constexpr uint32_t kW = 23, kH = 17; // Cut strata at the right and bottom edges.
    static constexpr uint32_t kGW = (kW + 2) / 3, kGH = (kH + 2) / 3;
    lab::VulkanContext& context;
    Integration integration;
    lab::LabTexture viewZ, normal, mv, gradients, diff, spec;

    explicit ConfidenceRig(lab::VulkanContext& c) : context(c) {}
    ~ConfidenceRig()
    {
        integration.Destroy();
        for (lab::LabTexture* t : {&viewZ, &normal, &mv, &gradients, &diff, &spec})
            context.DestroyTexture(*t);
    }

    void Create(const ConfidenceSettings& settings)
    {
        MethodDesc methodDesc = {kId, Method::CONFIDENCE};
        DenoiserCreationDesc desc = {};
        desc.methods = &methodDesc;
        desc.methodsNum = 1;
        desc.renderWidth = kW;
        desc.renderHeight = kH;
        IntegrationCreationDesc integrationDesc = context.GetIntegrationCreationDesc();
        integrationDesc.name = "CONFIDENCE test";
        REQUIRE(integration.Create(integrationDesc, desc) == VK_SUCCESS);
        REQUIRE(integration.SetMethodSettings(kId, settings) == Result::SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::R32_SFLOAT, kW, kH, "IN_VIEWZ", viewZ) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA8_UNORM, kW, kH, "IN_NORMAL_ROUGHNESS", normal) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RG16_SFLOAT, kW, kH, "IN_MV", mv) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA32_SFLOAT, kGW, kGH, "IN_GRADIENTS", gradients) == VK_SUCCESS);
        std::vector<float> sentinel(size_t(kW) * kH, kSentinel);
        for (lab::LabTexture* t : {&diff, &spec})
        {
            REQUIRE(context.CreateTexture(rhi::Format::R32_SFLOAT, kW, kH, "OUT_*_CONFIDENCE", *t) == VK_SUCCESS);
            REQUIRE(context.UploadTexture(*t, sentinel.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
        }
        std::vector<float> z(kW * kH, 4.0f), n(kW * kH * 4), m(kW * kH * 2, 0.0f);
        for (uint32_t i = 0; i < kW * kH; i++)
        {
            n[i * 4 + 0] = 0.5f;
            n[i * 4 + 1] = 0.5f;
            n[i * 4 + 2] = 0.0f;
            n[i * 4 + 3] = 1.0f;
            if (i < kW)
                z[i] = 1e7f; // Sky.
        }
        REQUIRE(context.UploadTexture(viewZ, z.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(normal, n.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(mv, m.data()) == VK_SUCCESS);
    }

    // Returns diffuse and specular confidence, kW * kH each.
    void Frame(uint32_t frameIndex, const std::vector<float>& g, std::vector<float>& outDiff, std::vector<float>& outSpec)
    {
        REQUIRE(context.UploadTexture(gradients, g.data()) == VK_SUCCESS);
        REQUIRE(integration.SetCommonSettings(test::StillCameraSettings(frameIndex)) == Result::SUCCESS);
        Bindings bindings = {{ResourceType::IN_VIEWZ, &viewZ},           {ResourceType::IN_NORMAL_ROUGHNESS, &normal},
                             {ResourceType::IN_MV, &mv},                 {ResourceType::IN_GRADIENTS, &gradients},
                             {ResourceType::OUT_DIFF_CONFIDENCE, &diff}, {ResourceType::OUT_SPEC_CONFIDENCE, &spec}};
        REQUIRE(test::DenoiseAndWait(context, integration, bindings) == VK_SUCCESS);
        REQUIRE(context.ReadbackTexture(diff, outDiff) == VK_SUCCESS);
        REQUIRE(context.ReadbackTexture(spec, outSpec) == VK_SUCCESS);
    }
};

// CPU evaluation of the method with uniform geometry (all edge-stopping weights 1).
struct CpuConfidence
{
    ConfidenceSettings s;
    std::vector<float> history; // kW * kH * 2, RG16f.
    bool hasHistory = false;

    std::vector<float> Filter(std::vector<float> g) const
    {
        const int gw = ConfidenceRig::kGW, gh = ConfidenceRig::kGH;
        const float k[3] = {0.25f, 0.5f, 0.25f};
        for (uint32_t pass = 0; pass < s.atrousPassNum; pass++)
        {
            const int step = 1 << pass;
            std::vector<float> out(g.size(), 0.0f);
            for (int y = 0; y < gh; y++)
                for (int x = 0; x < gw; x++)
                {
                    float sum[4] = {}, w = 0.0f;
                    for (int j = -1; j <= 1; j++)
                        for (int i = -1; i <= 1; i++)
                        {
                            int qx = x + i * step, qy = y + j * step;
                            if (qx < 0 || qy < 0 || qx >= gw || qy >= gh)
                                continue;
                            float wt = k[i + 1] * k[j + 1];
                            for (int c = 0; c < 4; c++)
                            {
                                float v = g[(size_t(qy) * gw + qx) * 4 + c];
                                sum[c] += wt * (std::isfinite(v) ? std::max(v, 0.0f) : 0.0f);
                            }
                            w += wt;
                        }
                    for (int c = 0; c < 4; c++)
                        out[(size_t(y) * gw + x) * 4 + c] = sum[c] / w;
                }
            g = test::Quantize(rhi::Format::RGBA16_SFLOAT, out);
        }
        return g;
    }

    // The local limit's box means over (2 r + 1)^2 strata, edge texels repeated, stored as RGBA16f.
    std::vector<float> Box(const std::vector<float>& g) const
    {
        const int gw = ConfidenceRig::kGW, gh = ConfidenceRig::kGH, r = int(s.localGradientRadius);
        const float n = float((2 * r + 1) * (2 * r + 1));
        std::vector<float> out(g.size(), 0.0f);
        for (int y = 0; y < gh; y++)
            for (int x = 0; x < gw; x++)
                for (int j = -r; j <= r; j++)
                    for (int i = -r; i <= r; i++)
                    {
                        int qx = std::min(std::max(x + i, 0), gw - 1), qy = std::min(std::max(y + j, 0), gh - 1);
                        for (int c = 0; c < 4; c++)
                        {
                            float v = g[(size_t(qy) * gw + qx) * 4 + c];
                            out[(size_t(y) * gw + x) * 4 + c] += (std::isfinite(v) ? std::min(std::max(v, 0.0f), 65504.0f) : 0.0f) / n;
                        }
                    }
        return test::Quantize(rhi::Format::RGBA16_SFLOAT, out);
    }

    float Convert(float d, float l, int signal) const
    {
        float g = d / std::max(l, 1e-6f);
        float sensitivity = signal == 0 ? s.gradientSensitivity : s.specularGradientSensitivity;
        return std::min(std::max(1.0f - std::max(g - s.gradientThreshold, 0.0f) * sensitivity, 0.0f), 1.0f);
    }

    // Raw (before the temporal filter) and filtered confidence, kW * kH * 2; sky pixels left as NaN.
    void Frame(const std::vector<float>& gradients, bool reset, std::vector<float>& raw, std::vector<float>& result)
    {
        const int w = ConfidenceRig::kW, h = ConfidenceRig::kH, gw = ConfidenceRig::kGW, gh = ConfidenceRig::kGH;
        std::vector<float> f = Filter(gradients);
        std::vector<float> box = Box(gradients);
        raw.assign(size_t(w) * h * 2, kNaN);
        result = raw;
        std::vector<float> next(size_t(w) * h * 2, 1.0f);
        for (int y = 1; y < h; y++)
            for (int x = 0; x < w; x++)
            {
                float fx = (x + 0.5f) / 3.0f - 0.5f, fy = (y + 0.5f) / 3.0f - 0.5f;
                int ox = int(std::floor(fx)), oy = int(std::floor(fy));
                float tx = fx - ox, ty = fy - oy;
                // Bilinear fetch of a 1/3-resolution RGBA image at this pixel, clamped at the edges.
                auto upsample = [&](const std::vector<float>& src, float out[4]) {
                    for (int j = 0; j < 2; j++)
                        for (int i = 0; i < 2; i++)
                        {
                            int qx = std::min(std::max(ox + i, 0), gw - 1), qy = std::min(std::max(oy + j, 0), gh - 1);
                            float wt = (i ? tx : 1.0f - tx) * (j ? ty : 1.0f - ty);
                            for (int c = 0; c < 4; c++)
                                out[c] += wt * src[(size_t(qy) * gw + qx) * 4 + c];
                        }
                };
                float g[4] = {};
                upsample(f, g);
                if (s.localGradientRadius > 0)
                {
                    // The box means of the unfiltered strata, interpolated as the filtered gradients.
                    float local[4] = {};
                    upsample(box, local);
                    for (int c = 0; c < 4; c += 2)
                        if (local[c] * std::max(g[c + 1], 1e-6f) < g[c] * std::max(local[c + 1], 1e-6f))
                        {
                            g[c] = local[c];
                            g[c + 1] = local[c + 1];
                        }
                }
                for (int c = 0; c < 2; c++)
                {
                    size_t i = (size_t(y) * w + x) * 2 + c;
                    float conf = Convert(g[c * 2], g[c * 2 + 1], c);
                    raw[i] = conf;
                    if (!reset && hasHistory)
                    {
                        float prev = history[i];
                        conf = conf + (prev - conf) * (conf < prev ? s.fallHistoryWeight : s.riseHistoryWeight);
                    }
                    conf = conf >= 0.99f ? 1.0f : conf;
                    result[i] = conf;
                    next[i] = conf;
                }
            }
        history.resize(next.size());
        for (size_t i = 0; i < next.size(); i++)
            history[i] = test::Quantize(rhi::Format::R16_SFLOAT, {next[i]})[0];
        hasHistory = true;
    }
};

} // namespace

TEST_CASE("CONFIDENCE equals a CPU evaluation; zero gradients give exactly 1; the temporal filter bounds the change",
          "[vulkan][confidence]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ConfidenceSettings settings;
        settings.gradientThreshold = 0.02f;
        settings.gradientSensitivity = 4.0f;
        settings.fallHistoryWeight = 0.25f; // A temporal filter that falls and rises over several frames.
        settings.riseHistoryWeight = 0.5f;
        ConfidenceRig rig(*context);
        rig.Create(settings);
        CpuConfidence cpu;
        cpu.s = settings;
        const size_t gn = size_t(ConfidenceRig::kGW) * ConfidenceRig::kGH;
        const size_t n = size_t(ConfidenceRig::kW) * ConfidenceRig::kH;

        // Frames: no change (exactly 1), a change in one corner (falls), unchanged (rises),
        // random gradients with bad values, and a restart.
        std::vector<std::vector<float>> inputs;
        std::vector<float> still(gn * 4, 0.0f);
        for (size_t i = 0; i < gn; i++)
            still[i * 4 + 1] = still[i * 4 + 3] = 0.5f + 0.1f * float(i % 7); // Luminance, no difference.
        inputs.push_back(still);
        inputs.push_back(still);
        std::vector<float> corner = still;
        for (uint32_t y = 0; y < 3; y++)
            for (uint32_t x = 0; x < 3; x++)
            {
                float* p = &corner[(size_t(y) * ConfidenceRig::kGW + x) * 4];
                p[0] = p[1];        // Diffuse: switched off (difference = luminance).
                p[2] = 0.1f * p[3]; // Specular: a 10% change.
            }
        inputs.push_back(corner);
        inputs.push_back(still);
        inputs.push_back(still);
        std::vector<float> noisy = test::RandomFloats(gn * 4, 77, 0.0f, 2.0f);
        noisy[5] = kNaN;
        noisy[10] = -3.0f;
        inputs.push_back(noisy);

        std::vector<float> previous(n * 2, 1.0f);
        for (uint32_t frame = 0; frame < inputs.size() + 1; frame++)
        {
            INFO("frame " << frame);
            const bool restart = frame == inputs.size();
            const std::vector<float>& g = restart ? noisy : inputs[frame];
            std::vector<float> diff, spec, raw, expected;
            rig.Frame(restart ? 0 : frame, g, diff, spec);
            cpu.Frame(g, frame == 0 || restart, raw, expected);
            std::vector<float> actual(n * 2), expectedSurface;
            size_t mismatches = 0, unwrittenSky = 0;
            for (size_t i = 0; i < n; i++)
            {
                for (int c = 0; c < 2; c++)
                {
                    float a = (c ? spec : diff)[i];
                    actual[i * 2 + c] = a;
                    if (i < ConfidenceRig::kW)
                    {
                        unwrittenSky += a == kSentinel;
                        continue;
                    }
                    float e = expected[i * 2 + c];
                    mismatches += std::fabs(a - e) > 2e-3f;
                    if (frame > 0 && !restart)
                    {
                        // One frame moves confidence by at most (1 - weight) of the way to the new value.
                        float p = previous[i * 2 + c], r = raw[i * 2 + c];
                        float weight = r < p ? settings.fallHistoryWeight : settings.riseHistoryWeight;
                        CHECK((std::fabs(a - p) <= (1.0f - weight) * std::fabs(r - p) + 2e-3f || a == 1.0f));
                    }
                    CHECK(a >= 0.0f);
                    CHECK(a <= 1.0f);
                }
            }
            CHECK(mismatches == 0);
            CHECK(unwrittenSky == 2 * ConfidenceRig::kW);
            if (frame <= 1)
            {
                // No lighting change: every surface pixel exactly 1.
                for (size_t i = ConfidenceRig::kW; i < n; i++)
                {
                    CHECK(diff[i] == 1.0f);
                    CHECK(spec[i] == 1.0f);
                }
            }
            if (frame == 2)
            {
                // The switched-off corner (strata 0..2) is invalidated at once below 0.5; the far
                // corner, within the a-trous footprint but 4 strata away, keeps exactly 1 (local limit).
                CHECK(diff[size_t(4) * ConfidenceRig::kW + 2] < 0.5f);
                CHECK(diff[size_t(ConfidenceRig::kH - 1) * ConfidenceRig::kW + ConfidenceRig::kW - 1] == 1.0f);
                CHECK(spec[size_t(ConfidenceRig::kH - 1) * ConfidenceRig::kW + ConfidenceRig::kW - 1] == 1.0f);
            }
            previous = actual;
        }
    }
    CHECK(context->ValidationMessageCount() == 0);
}
