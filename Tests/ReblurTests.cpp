// REBLUR: settings validation, dispatch sequence and memory of the descriptions (core only), and on
// lavapipe: reference accumulation equal to a CPU evaluation of the temporal accumulation with fp16
// history (also with a confidence input below 1), sky left unwritten, noise reduction on a plane,
// finite output on bad input.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace nrd;
using nrd::test::Bindings;

namespace
{

constexpr Identifier kId = 3;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kSentinel = -7.0f;

struct CoreDenoiser
{
    Denoiser* denoiser = nullptr;
    explicit CoreDenoiser(Method method, uint16_t w = 64, uint16_t h = 64)
    {
        MethodDesc m = {kId, method};
        DenoiserCreationDesc desc = {};
        desc.methods = &m;
        desc.methodsNum = 1;
        desc.renderWidth = w;
        desc.renderHeight = h;
        REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    }
    ~CoreDenoiser() { DestroyDenoiser(denoiser); }
};

std::vector<std::string> DispatchNames(Denoiser& denoiser)
{
    CommonSettings common = test::StillCameraSettings(0);
    REQUIRE(SetCommonSettings(denoiser, common) == Result::SUCCESS);
    const DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    REQUIRE(GetComputeDispatches(denoiser, nullptr, 0, dispatches, num) == Result::SUCCESS);
    std::vector<std::string> names;
    for (uint32_t i = 0; i < num; i++)
        names.push_back(dispatches[i].name);
    return names;
}

uint64_t PoolBytes(const DenoiserDesc& desc)
{
    uint64_t bytes = 0;
    for (int pass = 0; pass < 2; pass++)
    {
        const TextureDesc* pool = pass == 0 ? desc.permanentPool : desc.transientPool;
        uint32_t num = pass == 0 ? desc.permanentPoolSize : desc.transientPoolSize;
        for (uint32_t i = 0; i < num; i++)
        {
            uint64_t w = (desc.renderWidth + pool[i].downsampleX - 1) / pool[i].downsampleX;
            uint64_t h = (desc.renderHeight + pool[i].downsampleY - 1) / pool[i].downsampleY;
            bytes += w * h * GetFormatBytesPerPixel(pool[i].format);
        }
    }
    return bytes;
}

} // namespace

TEST_CASE("REBLUR methods have names and take ReblurSettings only", "[api][reblur]")
{
    const Method methods[] = {Method::REBLUR_DIFFUSE, Method::REBLUR_SPECULAR, Method::REBLUR_DIFFUSE_SPECULAR,
                              Method::REBLUR_DIFFUSE_OCCLUSION, Method::REBLUR_SPECULAR_OCCLUSION,
                              Method::REBLUR_DIFFUSE_SPECULAR_OCCLUSION};
    for (Method method : methods)
    {
        Method parsed = Method::MAX_NUM;
        CHECK(GetMethodFromString(GetMethodString(method), parsed));
        CHECK(parsed == method);
        CoreDenoiser d(method);
        CHECK(SetMethodSettings(*d.denoiser, kId, ReblurSettings{}) == Result::SUCCESS);
        CHECK(SetMethodSettings(*d.denoiser, kId, SigmaSettings{}) == Result::INVALID_ARGUMENT);
    }
}

TEST_CASE("ReblurSettings outside their ranges are rejected", "[api][reblur]")
{
    CoreDenoiser d(Method::REBLUR_DIFFUSE_SPECULAR);
    typedef void (*Edit)(ReblurSettings&);
    const Edit rejected[] = {
        [](ReblurSettings& s) { s.hitDistanceParameters.A = 0.0f; },
        [](ReblurSettings& s) { s.hitDistanceParameters.B = -1.0f; },
        [](ReblurSettings& s) { s.hitDistanceParameters.C = 0.5f; },
        [](ReblurSettings& s) { s.hitDistanceParameters.D = 1.0f; },
        [](ReblurSettings& s) { s.hitDistanceParameters.A = kNaN; },
        [](ReblurSettings& s) { s.maxAccumulatedFrameNum = REBLUR_MAX_HISTORY_FRAME_NUM + 1; },
        [](ReblurSettings& s) { s.maxFastAccumulatedFrameNum = s.maxAccumulatedFrameNum + 1; },
        [](ReblurSettings& s) { s.historyFixFrameNum = REBLUR_MAX_HISTORY_FIX_FRAME_NUM + 1; },
        [](ReblurSettings& s) { s.historyFixStride = 0.5f; },
        [](ReblurSettings& s) { s.blurRadius = REBLUR_MAX_BLUR_RADIUS * 1.01f; },
        [](ReblurSettings& s) { s.blurRadius = kNaN; },
        [](ReblurSettings& s) { s.minBlurRadius = s.blurRadius + 1.0f; },
        [](ReblurSettings& s) { s.diffusePrePassBlurRadius = -1.0f; },
        [](ReblurSettings& s) { s.specularPrePassBlurRadius = REBLUR_MAX_BLUR_RADIUS + 1.0f; },
        [](ReblurSettings& s) { s.occlusionPrePassBlurRadius = kNaN; },
        [](ReblurSettings& s) { s.postBlurRadiusScale = 2.5f; },
        [](ReblurSettings& s) { s.planeDistanceSensitivity = 0.0f; },
        [](ReblurSettings& s) { s.lobeAngleFraction = 0.0f; },
        [](ReblurSettings& s) { s.roughnessFraction = 1.5f; },
        [](ReblurSettings& s) { s.antilagSigmaScale = 0.25f; },
        [](ReblurSettings& s) { s.maxStabilizedFrameNum = REBLUR_MAX_HISTORY_FRAME_NUM + 1; },
        [](ReblurSettings& s) { s.colorCompression = -0.1f; },
        [](ReblurSettings& s) { s.antiFireflySigma = kNaN; },
        [](ReblurSettings& s) { s.checkerboardMode = CheckerboardMode(7); },
    };
    for (Edit edit : rejected)
    {
        ReblurSettings s;
        edit(s);
        CHECK(SetMethodSettings(*d.denoiser, kId, s) == Result::INVALID_ARGUMENT);
    }
    ReblurSettings limits;
    limits.maxAccumulatedFrameNum = REBLUR_MAX_HISTORY_FRAME_NUM;
    limits.maxFastAccumulatedFrameNum = REBLUR_MAX_HISTORY_FRAME_NUM;
    limits.historyFixFrameNum = 0;
    limits.blurRadius = REBLUR_MAX_BLUR_RADIUS;
    limits.minBlurRadius = REBLUR_MAX_BLUR_RADIUS;
    limits.diffusePrePassBlurRadius = REBLUR_MAX_BLUR_RADIUS;
    limits.specularPrePassBlurRadius = 0.0f;
    limits.occlusionPrePassBlurRadius = REBLUR_MAX_BLUR_RADIUS;
    limits.maxStabilizedFrameNum = 0;
    limits.checkerboardMode = CheckerboardMode::WHITE;
    CHECK(SetMethodSettings(*d.denoiser, kId, limits) == Result::SUCCESS);
}

TEST_CASE("REBLUR dispatches one classification and five passes per signal, six with the pre-pass", "[api][reblur]")
{
    {
        // Defaults: the specular pre-pass runs, the diffuse one does not.
        CoreDenoiser d(Method::REBLUR_DIFFUSE_SPECULAR);
        std::vector<std::string> names = DispatchNames(*d.denoiser);
        const std::vector<std::string> expected = {
            "REBLUR - Classify tiles",
            "REBLUR diffuse - Temporal accumulation", "REBLUR diffuse - History fix", "REBLUR diffuse - Blur",
            "REBLUR diffuse - Post-blur", "REBLUR diffuse - Temporal stabilization",
            "REBLUR specular - Pre-pass", "REBLUR specular - Temporal accumulation", "REBLUR specular - History fix",
            "REBLUR specular - Blur", "REBLUR specular - Post-blur", "REBLUR specular - Temporal stabilization"};
        CHECK(names == expected);
    }
    {
        // The occlusion variants take occlusionPrePassBlurRadius (default 0), not the specular one.
        CoreDenoiser d(Method::REBLUR_SPECULAR_OCCLUSION);
        CHECK(DispatchNames(*d.denoiser).size() == 6);
    }
    {
        CoreDenoiser d(Method::REBLUR_DIFFUSE_OCCLUSION);
        ReblurSettings s;
        s.occlusionPrePassBlurRadius = 8.0f;
        REQUIRE(SetMethodSettings(*d.denoiser, kId, s) == Result::SUCCESS);
        std::vector<std::string> names = DispatchNames(*d.denoiser);
        REQUIRE(names.size() == 7);
        CHECK(names[1] == "REBLUR diffuse - Pre-pass");
    }
}

TEST_CASE("REBLUR_DIFFUSE_SPECULAR at 2560x1440 needs at most 60% of NRD's published 262.56 MB", "[api][reblur]")
{
    CoreDenoiser d(Method::REBLUR_DIFFUSE_SPECULAR, 2560, 1440);
    uint64_t bytes = PoolBytes(GetDenoiserDesc(*d.denoiser));
    double mb = double(bytes) / 1e6;
    std::printf("REBLUR_DIFFUSE_SPECULAR at 2560x1440: %.2f MB (%.1f%% of 262.56 MB)\n", mb, 100.0 * mb / 262.56);
    CHECK(mb <= 0.6 * 262.56);
}

namespace
{

// A 16x16 plane facing the camera at viewZ 4, the top row sky, and the REBLUR_DIFFUSE textures.
struct ReblurRig
{
    static constexpr uint32_t kW = 16, kH = 16;
    lab::VulkanContext& context;
    Integration integration;
    lab::LabTexture viewZ, normal, mv, input, output, confidence;

    explicit ReblurRig(lab::VulkanContext& c) : context(c) {}
    ~ReblurRig()
    {
        integration.Destroy();
        for (lab::LabTexture* t : {&viewZ, &normal, &mv, &input, &output, &confidence})
            context.DestroyTexture(*t);
    }

    void Create(const ReblurSettings& settings)
    {
        MethodDesc methodDesc = {kId, Method::REBLUR_DIFFUSE};
        DenoiserCreationDesc desc = {};
        desc.methods = &methodDesc;
        desc.methodsNum = 1;
        desc.renderWidth = kW;
        desc.renderHeight = kH;
        IntegrationCreationDesc integrationDesc = context.GetIntegrationCreationDesc();
        integrationDesc.name = "REBLUR test";
        REQUIRE(integration.Create(integrationDesc, desc) == VK_SUCCESS);
        REQUIRE(integration.SetMethodSettings(kId, settings) == Result::SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::R32_SFLOAT, kW, kH, "IN_VIEWZ", viewZ) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA8_UNORM, kW, kH, "IN_NORMAL_ROUGHNESS", normal) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RG16_SFLOAT, kW, kH, "IN_MV", mv) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::R32_SFLOAT, kW, kH, "IN_DIFF_CONFIDENCE", confidence) == VK_SUCCESS);
        std::vector<float> one(size_t(kW) * kH, 1.0f);
        REQUIRE(context.UploadTexture(confidence, one.data()) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA32_SFLOAT, kW, kH, "IN_DIFF_RADIANCE_HITDIST", input) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA32_SFLOAT, kW, kH, "OUT_DIFF_RADIANCE_HITDIST", output) ==
                VK_SUCCESS);
        std::vector<float> sentinel(size_t(kW) * kH * 4, kSentinel);
        REQUIRE(context.UploadTexture(output, sentinel.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
        std::vector<float> z(kW * kH, 4.0f), n(kW * kH * 4), m(kW * kH * 2, 0.0f);
        for (uint32_t i = 0; i < kW * kH; i++)
        {
            n[i * 4 + 0] = 0.5f;
            n[i * 4 + 1] = 0.5f;
            n[i * 4 + 2] = 0.0f; // (0, 0, -1): towards the camera.
            n[i * 4 + 3] = 1.0f;
            if (i < kW)
                z[i] = 1e7f; // Sky (beyond the default denoisingRange).
        }
        REQUIRE(context.UploadTexture(viewZ, z.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(normal, n.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(mv, m.data()) == VK_SUCCESS);
    }

    std::vector<float> Frame(uint32_t frameIndex, const std::vector<float>& radianceHitDist)
    {
        REQUIRE(context.UploadTexture(input, radianceHitDist.data()) == VK_SUCCESS);
        REQUIRE(integration.SetCommonSettings(test::StillCameraSettings(frameIndex)) == Result::SUCCESS);
        Bindings bindings = {{ResourceType::IN_VIEWZ, &viewZ},
                             {ResourceType::IN_NORMAL_ROUGHNESS, &normal},
                             {ResourceType::IN_MV, &mv},
                             {ResourceType::IN_DIFF_RADIANCE_HITDIST, &input},
                             {ResourceType::IN_DIFF_CONFIDENCE, &confidence},
                             {ResourceType::OUT_DIFF_RADIANCE_HITDIST, &output}};
        REQUIRE(test::DenoiseAndWait(context, integration, bindings) == VK_SUCCESS);
        std::vector<float> result;
        REQUIRE(context.ReadbackTexture(output, result) == VK_SUCCESS);
        return result;
    }
};

} // namespace

TEST_CASE("REBLUR reference accumulation equals a CPU running mean with fp16 history; sky is not written",
          "[vulkan][reblur]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ReblurRig rig(*context);
        ReblurSettings settings;
        settings.forceReferenceAccumulation = true;
        rig.Create(settings);
        const uint32_t n = ReblurRig::kW * ReblurRig::kH;
        std::vector<float> expected(n * 4, 0.0f);
        std::vector<float> actual;
        for (uint32_t frame = 0; frame < 6; frame++)
        {
            std::vector<float> in = test::RandomFloats(n * 4, 1700 + frame, 0.0f, 4.0f);
            for (uint32_t i = 0; i < n; i++)
                in[i * 4 + 3] *= 0.25f; // Normalized hit distance in [0, 1].
            actual = rig.Frame(frame, in);
            // CPU: slow = mix(slow, current, 1 / (frame + 1)), stored in fp16 once per frame.
            float a = 1.0f / float(frame + 1);
            for (size_t i = 0; i < expected.size(); i++)
                expected[i] = expected[i] * (1.0f - a) + in[i] * a;
            expected = test::Quantize(rhi::Format::RGBA16_SFLOAT, expected);
        }
        std::vector<float> sky(actual.begin(), actual.begin() + ReblurRig::kW * 4);
        std::vector<float> surface(actual.begin() + ReblurRig::kW * 4, actual.end());
        std::vector<float> expectedSurface(expected.begin() + ReblurRig::kW * 4, expected.end());
        CHECK(test::CountMismatches(surface, expectedSurface, 2e-3f, 2e-3f) == 0);
        CHECK(test::CountMismatches(sky, std::vector<float>(sky.size(), kSentinel), 0.0f, 0.0f) == 0);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("REBLUR multiplies its history length by the confidence without rounding it down", "[vulkan][reblur]")
{
    // Reference accumulation with confidence 0.9 everywhere: the history length L read back is
    // multiplied by 0.9 (but kept where 6 frames or shorter, and at 6 frames or more:
    // REBLUR_DIFFUSE_CONFIDENCE_MIN_HISTORY) and the new
    // sample weighs 1 / (0.9 L + 1), so L grows towards
    // 1 / (1 - 0.9) = 10 frames (fp16 storage). Rounded down, 0.9 L + 1 would stay at 1 frame;
    // rounded to the nearest frame, at 6.4.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ReblurRig rig(*context);
        ReblurSettings settings;
        settings.forceReferenceAccumulation = true;
        settings.isConfidenceInput = true;
        rig.Create(settings);
        const uint32_t n = ReblurRig::kW * ReblurRig::kH;
        std::vector<float> c(n, 0.9f);
        REQUIRE(rig.context.UploadTexture(rig.confidence, c.data()) == VK_SUCCESS);
        std::vector<float> expected(n * 4, 0.0f);
        std::vector<float> actual;
        float storedLength = 0.0f;
        for (uint32_t frame = 0; frame < 12; frame++)
        {
            std::vector<float> in = test::RandomFloats(n * 4, 2100 + frame, 0.0f, 4.0f);
            for (uint32_t i = 0; i < n; i++)
                in[i * 4 + 3] *= 0.25f;
            actual = rig.Frame(frame, in);
            // Shaders/Reblur/Reblur_Common.glsl: diffuse keeps at least 6 frames of a cut history.
            float length = std::max(storedLength * 0.9f, std::min(storedLength, 6.0f)) + 1.0f;
            storedLength = test::Quantize(rhi::Format::R16_SFLOAT, {length})[0];
            float a = 1.0f / length;
            for (size_t i = 0; i < expected.size(); i++)
                expected[i] = expected[i] * (1.0f - a) + in[i] * a;
            expected = test::Quantize(rhi::Format::RGBA16_SFLOAT, expected);
        }
        INFO("history length after 12 frames " << storedLength);
        CHECK(storedLength > 7.0f);
        // Tolerance: fp16 stores that round towards zero (lavapipe) add up to a few ulps over an
        // exponential mean of this length; a history of 6.4 frames instead is off by 0.1 and more.
        std::vector<float> surface(actual.begin() + ReblurRig::kW * 4, actual.end());
        std::vector<float> expectedSurface(expected.begin() + ReblurRig::kW * 4, expected.end());
        CHECK(test::CountMismatches(surface, expectedSurface, 1e-2f, 1e-2f) == 0);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("REBLUR_DIFFUSE removes most of the noise of a flat signal and stays finite on bad input",
          "[vulkan][reblur]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ReblurRig rig(*context);
        rig.Create(ReblurSettings{});
        const uint32_t n = ReblurRig::kW * ReblurRig::kH;
        const uint32_t first = ReblurRig::kW; // Below the sky row.
        double inputError = 0.0, outputError = 0.0;
        std::vector<float> out;
        for (uint32_t frame = 0; frame < 10; frame++)
        {
            // Radiance 1 in expectation (0 or 2), hit distance 0.5 in expectation.
            std::vector<float> in = test::RandomFloats(n * 4, 1800 + frame, 0.0f, 1.0f);
            for (uint32_t i = 0; i < n; i++)
            {
                float v = in[i * 4] < 0.5f ? 0.0f : 2.0f;
                in[i * 4 + 0] = in[i * 4 + 1] = in[i * 4 + 2] = v;
            }
            out = rig.Frame(frame, in);
            if (frame == 9)
            {
                for (uint32_t i = first; i < n; i++)
                {
                    inputError += (in[i * 4] - 1.0) * (in[i * 4] - 1.0);
                    outputError += (out[i * 4] - 1.0) * (out[i * 4] - 1.0);
                }
            }
        }
        std::printf("REBLUR_DIFFUSE flat signal: input MSE %.4f, output MSE %.4f\n", inputError / (n - first),
                    outputError / (n - first));
        CHECK(outputError < 0.05 * inputError);

        // NaN, Inf, 1e30, negative and denormal radiance, hit distance NaN / huge: finite output.
        std::vector<float> bad = test::RandomFloats(n * 4, 1900, 0.0f, 1.0f);
        const float values[] = {kNaN, std::numeric_limits<float>::infinity(), 1e30f, -5.0f, 1e-40f};
        for (uint32_t i = 0; i < n; i++)
        {
            bad[i * 4 + (i % 3)] = values[i % 5];
            bad[i * 4 + 3] = i % 2 ? kNaN : 1e30f;
        }
        out = rig.Frame(10, bad);
        bool finite = true;
        for (uint32_t i = first * 4; i < n * 4; i++)
            finite = finite && std::isfinite(out[i]);
        CHECK(finite);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("REBLUR diffuse keeps the history short where a line of light moves over a still surface, long elsewhere",
          "[vulkan][reblur]")
{
    // The plane at 0.45 crossed by a line of light one pixel high (1.3) that moves down one row every
    // two frames (venetian_blinds' stripes, without motion vectors): the change
    // test finds the rows the line crosses (this frame's and the previous frame's residuals covary over
    // the 5x5 taps) and the lighting change record keeps their histories at 1 + 1 frames; rows the
    // line never reaches accumulate every frame. The permanent debt texture (R8) holds the record in
    // its top 3 bits (moving from 2 on); the fast history's .y the length.
    ResourceDesc debtDesc = {}, fastDesc = {};
    {
        CoreDenoiser d(Method::REBLUR_DIFFUSE, ReblurRig::kW, ReblurRig::kH);
        REQUIRE(SetCommonSettings(*d.denoiser, test::StillCameraSettings(0)) == Result::SUCCESS);
        const DispatchDesc* dispatches = nullptr;
        uint32_t num = 0;
        REQUIRE(GetComputeDispatches(*d.denoiser, nullptr, 0, dispatches, num) == Result::SUCCESS);
        bool found = false;
        for (uint32_t i = 0; i < num && !found; i++)
            if (std::string(dispatches[i].name) == "REBLUR diffuse - History fix")
            {
                REQUIRE(dispatches[i].resourcesNum == 9);
                fastDesc = dispatches[i].resources[6];  // gOut_Fast
                debtDesc = dispatches[i].resources[8];  // gOut_Debt
                found = true;
            }
        REQUIRE(found);
        REQUIRE(debtDesc.type == ResourceType::PERMANENT_POOL);
        REQUIRE(fastDesc.type == ResourceType::PERMANENT_POOL);
    }
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    // Without a confidence input and with one that is 1 everywhere (the test runs after the
    // confidence's cut, on the same record).
    for (bool withConfidence : {false, true})
    {
        INFO((withConfidence ? "with" : "without") << " a confidence input");
        ReblurRig rig(*context);
        ReblurSettings settings;
        settings.isConfidenceInput = withConfidence;
        rig.Create(settings);
        const uint32_t w = ReblurRig::kW, h = ReblurRig::kH, frames = 14, firstRow = 1, farRow = h - 2; // (the rig's confidence is 1)
        std::vector<float> in(size_t(w) * h * 4), out;
        uint32_t row = firstRow;
        for (uint32_t frame = 0; frame < frames; frame++)
        {
            row = firstRow + frame / 2;
            for (uint32_t i = 0; i < w * h; i++)
            {
                float v = i / w == row ? 1.3f : 0.45f;
                in[i * 4 + 0] = in[i * 4 + 1] = in[i * 4 + 2] = v;
                in[i * 4 + 3] = 0.5f;
            }
            out = rig.Frame(frame, in);
        }
        std::vector<float> debt = test::ReadbackPoolTexture(*context, rig.integration, ResourceType::PERMANENT_POOL, debtDesc.indexInPool);
        std::vector<float> fast = test::ReadbackPoolTexture(*context, rig.integration, ResourceType::PERMANENT_POOL, fastDesc.indexInPool);
        REQUIRE(debt.size() == size_t(w) * h);
        REQUIRE(fast.size() == 2u * w * h);
        auto record = [&](uint32_t x, uint32_t y) { return uint32_t(std::floor(debt[size_t(y) * w + x] * 255.0f + 0.5f)) >> 5u; };
        auto length = [&](uint32_t x, uint32_t y) { return fast[(size_t(y) * w + x) * 2 + 1]; };
        size_t shortOnLine = 0, longAway = 0;
        for (uint32_t x = 2; x < w - 2; x++)
        {
            // The line's row this frame (it arrived the frame before): moving, 1 + 1 frames.
            shortOnLine += record(x, row) >= 2u && length(x, row) <= 2.0f;
            // A row 7 below the line's last one: never lit, every frame accumulated.
            longAway += record(x, farRow) == 0u && length(x, farRow) == float(frames);
        }
        INFO("row " << row << ": record " << record(w / 2, row) << ", length " << length(w / 2, row) << "; row " << farRow
                    << ": record " << record(w / 2, farRow) << ", length " << length(w / 2, farRow));
        CHECK(shortOnLine == w - 4);
        CHECK(longAway == w - 4);
        // The output shows the line: its row above the rows around it.
        for (uint32_t x = 2; x < w - 2; x++)
        {
            INFO("x " << x);
            CHECK(out[(size_t(row) * w + x) * 4] > out[(size_t(row + 3) * w + x) * 4] + 0.3f);
        }
    }
    CHECK(context->ValidationMessageCount() == 0);
}
