// SIGMA (SIGMA_SHADOW, SIGMA_SHADOW_TRANSLUCENCY) through the Vulkan integration layer on lavapipe,
// validation on. The scene is synthetic with a known ground truth: a plane facing the camera at a
// constant depth, crossed by a straight shadow edge whose visibility ramps linearly over the
// penumbra (width 2 * radius). Each frame the noisy input is one Bernoulli(truth) visibility sample
// per pixel with consistent penumbra data (SIGMA_FrontEnd_PackShadow: radius / viewZ where occluded,
// NRD_FP16_MAX where lit).
#include <catch2/catch.hpp>

#include "ImageIO.h"
#include "Metrics.h"
#include "VulkanTestUtils.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

using namespace nrd;
using nrd::test::Bindings;

namespace
{

constexpr Identifier SIGMA_ID = 3;
constexpr float kPlaneViewZ = 10.0f;
constexpr float kFp16Max = 65504.0f;
constexpr float kOutputSentinel = 2.0f; // Written into the output before denoising; SIGMA writes [0, 1].

// Quality factors relMSE(noisy) / relMSE(denoised). Each test prints what it measures; the
// thresholds are about half of what lavapipe measured (in brackets).
constexpr double kStaticFactor = 30.0;       // [64x] 256x256, radius 10 px, after 8 still frames.
constexpr double kFirstFrameFactor = 15.0;   // [30x] Frame 0: spatial filtering alone.
constexpr double kTranslucencyFactor = 25.0; // [53x shadow, 69x translucency] 128x128, 6 frames.
constexpr double kSlidingEdgeFactor = 8.0;   // [17x] The light moves 1.5 px per frame.
constexpr double kMovingCameraFactor = 28.0; // [57x] The camera moves 1.5 px per frame.
constexpr double kGroundPlaneFactor = 22.0;  // [45x] Grazing ground plane, varying depth.
constexpr double kSpatialOnlyFactor = 11.0;  // [23x] maxStabilizedFrameNum = 0 (then restarted).

struct Scene
{
    uint32_t width = 128;
    uint32_t height = 128;
    float penumbraRadius = 8.0f;                // Pixels at the plane's depth.
    float edgeAngle = 0.35f;                    // Radians from the vertical.
    float edgeOffset = 0.0f;                    // Pixels from the image center along the edge normal.
    float cameraShift = 0.0f;                   // Camera translation along +x in pixels at the plane's depth.
    bool hasSky = false;                        // The top quarter is sky (viewZ = +Inf).
    float translucency[3] = {0.2f, 0.5f, 0.8f}; // Transmittance of the occluder.

    bool IsSky(uint32_t, uint32_t y) const { return hasSky && y < height / 4; }

    float Truth(uint32_t x, uint32_t y) const
    {
        float nx = std::cos(edgeAngle), ny = std::sin(edgeAngle);
        float d = (float(x) + cameraShift + 0.5f - 0.5f * float(width)) * nx +
                  (float(y) + 0.5f - 0.5f * float(height)) * ny - edgeOffset;
        return std::min(std::max((d + penumbraRadius) / (2.0f * penumbraRadius), 0.0f), 1.0f);
    }

    // Penumbra radius / viewZ for the still camera of VulkanTestUtils (|P11| = 1): pixels =
    // value * 0.5 * height.
    float PenumbraOverViewZ() const { return penumbraRadius / (0.5f * float(height)); }

    // World units of the camera position for a shift in pixels (|P00| = 1: one pixel is
    // 2 * viewZ / width).
    float CameraX(float shiftPixels) const { return shiftPixels * 2.0f * kPlaneViewZ / float(width); }
};

// Frame 'frame' of a camera translating along +x by 'speed' pixels a frame: sets the scene's shift
// (for MakeFrame) and returns the settings with this and the previous frame's camera.
CommonSettings TranslatingCamera(Scene& scene, uint32_t frame, float speed)
{
    float shift = speed * float(frame), shiftPrev = speed * float(frame ? frame - 1 : 0);
    scene.cameraShift = shift;
    CommonSettings settings = test::StillCameraSettings(frame);
    settings.worldToViewMatrix[12] = -scene.CameraX(shift);
    settings.worldToViewMatrixPrev[12] = -scene.CameraX(shiftPrev);
    return settings;
}

// Inputs of one frame and the ground truth (RGBA, .x shadow, .yzw translucency).
struct FrameData
{
    std::vector<float> viewZ, normal, mv, shadowData, shadowTranslucency;
    std::vector<float> truth; // 4 channels.
    std::vector<float> noisy; // 4 channels, what the denoiser gets.
};

FrameData MakeFrame(const Scene& scene, uint32_t seed)
{
    size_t n = size_t(scene.width) * scene.height;
    FrameData f;
    f.viewZ.resize(n);
    f.normal.resize(n * 4);
    f.mv.assign(n * 2, 0.0f);
    f.shadowData.resize(n * 2);
    f.shadowTranslucency.resize(n * 4);
    f.truth.resize(n * 4);
    f.noisy.resize(n * 4);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (uint32_t y = 0; y < scene.height; y++)
    {
        for (uint32_t x = 0; x < scene.width; x++)
        {
            size_t i = size_t(y) * scene.width + x;
            float truth = scene.Truth(x, y);
            bool lit = uniform(rng) < truth;
            bool sky = scene.IsSky(x, y);
            f.viewZ[i] = sky ? INFINITY : kPlaneViewZ;
            // World = view (identity camera) looking along +z: the plane faces -z.
            f.normal[i * 4 + 0] = 0.5f;
            f.normal[i * 4 + 1] = 0.5f;
            f.normal[i * 4 + 2] = 0.0f;
            f.normal[i * 4 + 3] = 1.0f;
            f.shadowData[i * 2 + 0] = sky || lit ? 1.0f : 0.0f;
            f.shadowData[i * 2 + 1] = sky || lit ? kFp16Max : scene.PenumbraOverViewZ();
            f.shadowTranslucency[i * 4 + 0] = f.shadowData[i * 2 + 0];
            for (int c = 0; c < 3; c++)
            {
                f.shadowTranslucency[i * 4 + 1 + c] = sky || lit ? 1.0f : scene.translucency[c];
                f.truth[i * 4 + 1 + c] = truth + (1.0f - truth) * scene.translucency[c];
            }
            f.truth[i * 4 + 0] = truth;
            for (int c = 0; c < 4; c++)
                f.noisy[i * 4 + c] = f.shadowTranslucency[i * 4 + c];
        }
    }
    return f;
}

// Channels [first, first + count) of the non-sky pixels, as a 1-row image (metrics input).
nrdlab::Image Channels(const Scene& scene, const std::vector<float>& rgba, uint32_t first, uint32_t count)
{
    std::vector<float> values;
    for (uint32_t y = 0; y < scene.height; y++)
        for (uint32_t x = 0; x < scene.width; x++)
            if (!scene.IsSky(x, y))
                for (uint32_t c = first; c < first + count; c++)
                    values.push_back(rgba[(size_t(y) * scene.width + x) * 4 + c]);
    nrdlab::Image image(uint32_t(values.size() / count), 1, count);
    image.pixels = values;
    return image;
}

double RelMse(const Scene& scene, const std::vector<float>& test, const std::vector<float>& truth, uint32_t first = 0,
              uint32_t count = 1)
{
    return nrdlab::RelMSE(Channels(scene, test, first, count), Channels(scene, truth, first, count));
}

// One SIGMA denoiser with its application textures.
struct SigmaRig
{
    lab::VulkanContext& context;
    Integration integration;
    Method method;
    Scene scene;
    lab::LabTexture viewZ, normal, mv, shadowData, shadowTranslucency, output;

    SigmaRig(lab::VulkanContext& c, Method m, const Scene& s) : context(c), method(m), scene(s) {}

    ~SigmaRig()
    {
        integration.Destroy();
        for (lab::LabTexture* t : {&viewZ, &normal, &mv, &shadowData, &shadowTranslucency, &output})
            context.DestroyTexture(*t);
    }

    void Create(const SigmaSettings& settings = {})
    {
        MethodDesc methodDesc = {SIGMA_ID, method};
        DenoiserCreationDesc desc = {};
        desc.methods = &methodDesc;
        desc.methodsNum = 1;
        desc.renderWidth = uint16_t(scene.width);
        desc.renderHeight = uint16_t(scene.height);
        IntegrationCreationDesc integrationDesc = context.GetIntegrationCreationDesc();
        integrationDesc.name = "SIGMA test";
        REQUIRE(integration.Create(integrationDesc, desc) == VK_SUCCESS);
        REQUIRE(integration.SetMethodSettings(SIGMA_ID, settings) == Result::SUCCESS);
        uint32_t w = scene.width, h = scene.height;
        REQUIRE(context.CreateTexture(rhi::Format::R32_SFLOAT, w, h, "IN_VIEWZ", viewZ) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA8_UNORM, w, h, "IN_NORMAL_ROUGHNESS", normal) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RG16_SFLOAT, w, h, "IN_MV", mv) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RG16_SFLOAT, w, h, "IN_SHADOWDATA", shadowData) == VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA16_SFLOAT, w, h, "IN_SHADOW_TRANSLUCENCY", shadowTranslucency) ==
                VK_SUCCESS);
        REQUIRE(context.CreateTexture(rhi::Format::RGBA16_SFLOAT, w, h, "OUT_SHADOW_TRANSLUCENCY", output) ==
                VK_SUCCESS);
        std::vector<float> sentinel(size_t(w) * h * 4, kOutputSentinel);
        REQUIRE(context.UploadTexture(output, sentinel.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
    }

    // Denoises one frame; returns the output (RGBA).
    std::vector<float> Frame(uint32_t frameIndex, const FrameData& f)
    {
        return Frame(test::StillCameraSettings(frameIndex), f);
    }

    std::vector<float> Frame(const CommonSettings& settings, const FrameData& f)
    {
        REQUIRE(context.UploadTexture(viewZ, f.viewZ.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(normal, f.normal.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(mv, f.mv.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(shadowData, f.shadowData.data()) == VK_SUCCESS);
        REQUIRE(context.UploadTexture(shadowTranslucency, f.shadowTranslucency.data()) == VK_SUCCESS);
        REQUIRE(integration.SetCommonSettings(settings) == Result::SUCCESS);
        Bindings bindings = {{ResourceType::IN_VIEWZ, &viewZ},
                             {ResourceType::IN_NORMAL_ROUGHNESS, &normal},
                             {ResourceType::IN_MV, &mv},
                             {ResourceType::IN_SHADOWDATA, &shadowData},
                             {ResourceType::OUT_SHADOW_TRANSLUCENCY, &output}};
        if (method == Method::SIGMA_SHADOW_TRANSLUCENCY)
            bindings.push_back({ResourceType::IN_SHADOW_TRANSLUCENCY, &shadowTranslucency});
        REQUIRE(test::DenoiseAndWait(context, integration, bindings) == VK_SUCCESS);
        std::vector<float> result;
        REQUIRE(context.ReadbackTexture(output, result) == VK_SUCCESS);
        return result;
    }
};

// With NRD_TEST_IMAGES=<folder> set, writes "noisy | denoised | truth" of channel 'channel' as a PNG.
void WriteStrip(const Scene& scene, const char* name, const std::vector<float>& noisy,
                const std::vector<float>& denoised, const std::vector<float>& truth, uint32_t channel = 0)
{
    const char* folder = std::getenv("NRD_TEST_IMAGES");
    if (!folder)
        return;
    std::vector<nrdlab::Image> images;
    for (const std::vector<float>* rgba : {&noisy, &denoised, &truth})
    {
        nrdlab::Image image(scene.width, scene.height, 1);
        for (size_t i = 0; i < image.pixels.size(); i++)
            image.pixels[i] = (*rgba)[i * 4 + channel];
        images.push_back(image);
    }
    nrdlab::PngOptions options;
    options.toneMap = false;
    nrdlab::WriteSideBySide(std::string(folder) + "/" + name + ".png", images, nullptr, 4, options);
}

bool AllFinite(const std::vector<float>& values)
{
    return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
}

} // namespace

TEST_CASE("SIGMA_SHADOW lowers the error of a noisy soft sun shadow many times", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        Scene scene;
        scene.width = 256;
        scene.height = 256;
        scene.penumbraRadius = 10.0f;
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();

        double noisySum = 0.0, outputSum = 0.0, firstFactor = 0.0;
        const uint32_t frames = 8;
        for (uint32_t frame = 0; frame < frames; frame++)
        {
            FrameData f = MakeFrame(scene, 1000 + frame);
            std::vector<float> output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
            double noisy = RelMse(scene, f.noisy, f.truth);
            double denoised = RelMse(scene, output, f.truth);
            std::printf("SIGMA_SHADOW frame %u: relMSE noisy %.5f, denoised %.5f (%.1fx)\n", frame, noisy, denoised,
                        noisy / denoised);
            if (frame == 0)
                firstFactor = noisy / denoised;
            WriteStrip(scene, ("sigma_shadow_" + std::to_string(frame)).c_str(), f.noisy, output, f.truth);
            if (frame >= frames - 2)
            {
                noisySum += noisy;
                outputSum += denoised;
            }
        }
        double factor = noisySum / outputSum;
        std::printf("SIGMA_SHADOW quality factor: %.1fx after %u still frames, %.1fx on the first frame\n", factor,
                    frames, firstFactor);
        CHECK(firstFactor > kFirstFrameFactor);
        CHECK(factor > kStaticFactor);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA_SHADOW_TRANSLUCENCY denoises the translucency with the shadow", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        Scene scene;
        scene.width = 128;
        scene.height = 128;
        scene.penumbraRadius = 8.0f;
        SigmaRig rig(*context, Method::SIGMA_SHADOW_TRANSLUCENCY, scene);
        rig.Create();

        double noisy[2] = {}, denoised[2] = {};
        const uint32_t frames = 6;
        for (uint32_t frame = 0; frame < frames; frame++)
        {
            FrameData f = MakeFrame(scene, 2000 + frame);
            std::vector<float> output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
            if (frame < frames - 2)
                continue;
            noisy[0] += RelMse(scene, f.noisy, f.truth, 0, 1);
            denoised[0] += RelMse(scene, output, f.truth, 0, 1);
            noisy[1] += RelMse(scene, f.noisy, f.truth, 1, 3);
            denoised[1] += RelMse(scene, output, f.truth, 1, 3);
        }
        std::printf("SIGMA_SHADOW_TRANSLUCENCY quality factor: shadow %.1fx, translucency %.1fx\n",
                    noisy[0] / denoised[0], noisy[1] / denoised[1]);
        CHECK(noisy[0] / denoised[0] > kTranslucencyFactor);
        CHECK(noisy[1] / denoised[1] > kTranslucencyFactor);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA leaves sky pixels untouched", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    for (Method method : {Method::SIGMA_SHADOW, Method::SIGMA_SHADOW_TRANSLUCENCY})
    {
        INFO(GetMethodString(method));
        Scene scene;
        scene.width = 101; // Partial tiles on both axes.
        scene.height = 75;
        scene.hasSky = true;
        SigmaRig rig(*context, method, scene);
        rig.Create();
        std::vector<float> output;
        for (uint32_t frame = 0; frame < 3; frame++)
            output = rig.Frame(frame, MakeFrame(scene, 3000 + frame));
        REQUIRE(AllFinite(output));
        size_t touched = 0, untouched = 0;
        for (uint32_t y = 0; y < scene.height; y++)
            for (uint32_t x = 0; x < scene.width; x++)
            {
                const float* p = &output[(size_t(y) * scene.width + x) * 4];
                bool isSentinel = p[0] == kOutputSentinel && p[1] == kOutputSentinel && p[2] == kOutputSentinel &&
                                  p[3] == kOutputSentinel;
                if (scene.IsSky(x, y))
                    touched += !isSentinel;
                else
                    untouched += isSentinel;
            }
        CHECK(touched == 0);   // Sky: not written.
        CHECK(untouched == 0); // Everything else: written.
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA does not leave a ghost behind a moving shadow edge", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        Scene scene;
        scene.width = 128;
        scene.height = 128;
        scene.penumbraRadius = 6.0f;
        scene.edgeOffset = -20.0f;
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();

        // Still for 6 frames, then the edge jumps by 40 pixels (the light moved) and stays.
        const uint32_t jumpFrame = 6, frames = 12;
        std::vector<double> errors;
        for (uint32_t frame = 0; frame < frames; frame++)
        {
            if (frame == jumpFrame)
                rig.scene.edgeOffset = 20.0f;
            FrameData f = MakeFrame(rig.scene, 4000 + frame);
            std::vector<float> output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
            errors.push_back(RelMse(rig.scene, output, f.truth));
            WriteStrip(rig.scene, ("sigma_moving_" + std::to_string(frame)).c_str(), f.noisy, output, f.truth);
            std::printf("SIGMA moving edge frame %u: relMSE %.5f (noisy %.5f)\n", frame, errors.back(),
                        RelMse(rig.scene, f.noisy, f.truth));
        }
        double steady = 0.5 * (errors[jumpFrame - 1] + errors[jumpFrame - 2]);
        int lag = nrdlab::LagFrames(errors, jumpFrame, steady);
        std::printf("SIGMA moving edge: back within 2x of the steady error (%.5f) after %d frames\n", steady, lag);
        CHECK(lag >= 0);
        CHECK(lag <= 3);
        double settled = 0.5 * (errors[frames - 1] + errors[frames - 2]);
        CHECK(settled < 2.0 * steady);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA output stays finite with NaN and Inf inputs", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    for (Method method : {Method::SIGMA_SHADOW, Method::SIGMA_SHADOW_TRANSLUCENCY})
    {
        INFO(GetMethodString(method));
        Scene scene;
        scene.width = 64;
        scene.height = 64;
        SigmaRig rig(*context, method, scene);
        rig.Create();
        for (uint32_t frame = 0; frame < 3; frame++)
        {
            FrameData f = MakeFrame(scene, 5000 + frame);
            std::mt19937 rng(frame);
            for (int k = 0; k < 64; k++)
            {
                size_t i = rng() % f.viewZ.size();
                float bad = (k & 1) ? NAN : INFINITY;
                switch (k % 5)
                {
                case 0:
                    f.shadowData[i * 2 + 0] = bad;
                    break;
                case 1:
                    f.shadowData[i * 2 + 1] = (k & 2) ? -bad : bad;
                    break;
                case 2:
                    f.shadowTranslucency[i * 4 + 1 + k % 3] = bad;
                    break;
                case 3:
                    f.mv[i * 2 + k % 2] = bad;
                    break;
                default:
                    f.viewZ[i] = (k & 2) ? 0.0f : bad;
                    break;
                }
            }
            std::vector<float> output = rig.Frame(frame, f);
            size_t nonFinite =
                size_t(std::count_if(output.begin(), output.end(), [](float v) { return !std::isfinite(v); }));
            CHECK(nonFinite == 0);
        }
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA keeps denoising a shadow edge that slides every frame", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        Scene scene;
        scene.width = 128;
        scene.height = 128;
        scene.penumbraRadius = 8.0f;
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();
        double noisy = 0.0, denoised = 0.0;
        const uint32_t frames = 10;
        for (uint32_t frame = 0; frame < frames; frame++)
        {
            rig.scene.edgeOffset = -15.0f + 1.5f * float(frame); // The light moves: 1.5 pixels per frame.
            FrameData f = MakeFrame(rig.scene, 6000 + frame);
            std::vector<float> output = rig.Frame(frame, f);
            WriteStrip(rig.scene, ("sigma_sliding_" + std::to_string(frame)).c_str(), f.noisy, output, f.truth);
            if (frame < frames - 3)
                continue;
            noisy += RelMse(rig.scene, f.noisy, f.truth);
            denoised += RelMse(rig.scene, output, f.truth);
        }
        std::printf("SIGMA sliding edge quality factor: %.1fx\n", noisy / denoised);
        CHECK(noisy / denoised > kSlidingEdgeFactor);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA follows camera motion with matrices, 2D and 3D motion vectors", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const char* modes[] = {"matrices only", "2D motion vectors", "3D motion vectors"};
    for (int mode = 0; mode < 3; mode++)
    {
        INFO(modes[mode]);
        Scene scene;
        scene.width = 128;
        scene.height = 128;
        scene.penumbraRadius = 8.0f;
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();
        double noisy = 0.0, denoised = 0.0;
        const uint32_t frames = 8;
        const float speed = 1.5f; // Pixels per frame, not a whole number: bilinear history.
        for (uint32_t frame = 0; frame < frames; frame++)
        {
            CommonSettings settings = TranslatingCamera(rig.scene, frame, speed);
            FrameData f = MakeFrame(rig.scene, 7000 + frame);
            if (mode == 0)
            {
                settings.motionVectorScale[0] = settings.motionVectorScale[1] = settings.motionVectorScale[2] = 0.0f;
            }
            else if (mode == 1)
            {
                // uvPrev = uv + mv: the point now at x was at x + speed pixels (frame 0: still).
                for (size_t i = 0; i < f.mv.size(); i += 2)
                    f.mv[i] = (frame ? speed : 0.0f) / float(scene.width);
            }
            else
            {
                settings.isMotionVectorInWorldSpace = true; // Static scene: zero object motion.
                settings.motionVectorScale[2] = 1.0f;
            }
            std::vector<float> output = rig.Frame(settings, f);
            REQUIRE(AllFinite(output));
            if (frame < frames - 2)
                continue;
            noisy += RelMse(rig.scene, f.noisy, f.truth);
            denoised += RelMse(rig.scene, output, f.truth);
        }
        std::printf("SIGMA moving camera (%s) quality factor: %.1fx\n", modes[mode], noisy / denoised);
        CHECK(noisy / denoised > kMovingCameraFactor);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA copies uniform input exactly (tiles without penumbra are skipped)", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    for (Method method : {Method::SIGMA_SHADOW, Method::SIGMA_SHADOW_TRANSLUCENCY})
    {
        INFO(GetMethodString(method));
        // A hard vertical shadow edge on a tile boundary (x = 48): every tile is uniform (umbra or
        // lit), so every pass copies.
        Scene scene;
        scene.width = 80;
        scene.height = 40;
        scene.penumbraRadius = 0.01f;
        scene.edgeAngle = 0.0f;
        scene.edgeOffset = 8.0f;
        SigmaRig rig(*context, method, scene);
        rig.Create();
        for (uint32_t frame = 0; frame < 3; frame++)
        {
            FrameData f = MakeFrame(scene, 8000 + frame);
            std::vector<float> output = rig.Frame(frame, f);
            std::vector<float> expected = test::Quantize(rhi::Format::RGBA16_SFLOAT, f.noisy);
            if (method == Method::SIGMA_SHADOW)
                for (size_t i = 0; i < expected.size(); i += 4)
                    expected[i + 1] = expected[i + 2] = expected[i + 3] = expected[i];
            CHECK(test::CountMismatches(output, expected, 0.0f, 0.0f) == 0);
        }
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA without temporal stabilization still denoises spatially", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        Scene scene;
        scene.width = 128;
        scene.height = 96;
        scene.penumbraRadius = 8.0f;
        scene.hasSky = true;
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        SigmaSettings settings = {};
        settings.maxStabilizedFrameNum = 0;
        rig.Create(settings);
        double noisy = 0.0, denoised = 0.0;
        for (uint32_t frame = 0; frame < 4; frame++)
        {
            if (frame == 2)
            {
                settings.maxStabilizedFrameNum = 5; // Turning it back on restarts the history.
                REQUIRE(rig.integration.SetMethodSettings(SIGMA_ID, settings) == Result::SUCCESS);
            }
            FrameData f = MakeFrame(scene, 9000 + frame);
            std::vector<float> output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
            size_t skyWritten = 0;
            for (uint32_t y = 0; y < scene.height; y++)
                for (uint32_t x = 0; x < scene.width; x++)
                    skyWritten += scene.IsSky(x, y) && output[(size_t(y) * scene.width + x) * 4] != kOutputSentinel;
            CHECK(skyWritten == 0);
            noisy += RelMse(scene, f.noisy, f.truth);
            denoised += RelMse(scene, output, f.truth);
        }
        std::printf("SIGMA spatial only + restart quality factor: %.1fx\n", noisy / denoised);
        CHECK(noisy / denoised > kSpatialOnlyFactor);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA dispatch sequence and pools (golden)", "[api][sigma]")
{
    for (Method method : {Method::SIGMA_SHADOW, Method::SIGMA_SHADOW_TRANSLUCENCY})
    {
        std::string prefix = GetMethodString(method);
        INFO(prefix);
        MethodDesc methodDesc = {SIGMA_ID, method};
        DenoiserCreationDesc desc = {};
        desc.methods = &methodDesc;
        desc.methodsNum = 1;
        desc.renderWidth = 1920;
        desc.renderHeight = 1080;
        Denoiser* denoiser = nullptr;
        REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);

        const DenoiserDesc& d = GetDenoiserDesc(*denoiser);
        CHECK(d.pipelinesNum == 5);
        const Format signal = method == Method::SIGMA_SHADOW ? Format::R16_SFLOAT : Format::RGBA16_SFLOAT;
        REQUIRE(d.permanentPoolSize == 4); // History and viewZ + history length, ping-pong.
        CHECK(d.permanentPool[0].format == signal);
        CHECK(d.permanentPool[1].format == Format::R32_UINT);
        CHECK(d.permanentPool[2].format == signal);
        CHECK(d.permanentPool[3].format == Format::R32_UINT);
        REQUIRE(d.transientPoolSize == 5); // Tiles, tile modes, penumbra, blurred, post-blurred.
        CHECK(d.transientPool[0].format == Format::RG16_SFLOAT);
        CHECK(d.transientPool[0].downsampleX == 16);
        CHECK(d.transientPool[0].downsampleY == 16);
        CHECK(d.transientPool[1].format == Format::R8_UNORM);
        CHECK(d.transientPool[1].downsampleX == 16);

        auto frame = [&](uint32_t frameIndex)
        {
            CommonSettings settings = test::StillCameraSettings(frameIndex);
            REQUIRE(SetCommonSettings(*denoiser, settings) == Result::SUCCESS);
            const DispatchDesc* dispatches = nullptr;
            uint32_t num = 0;
            REQUIRE(GetComputeDispatches(*denoiser, nullptr, 0, dispatches, num) == Result::SUCCESS);
            std::vector<const DispatchDesc*> list;
            for (uint32_t i = 0; i < num; i++)
                list.push_back(dispatches + i);
            return list;
        };
        for (uint32_t f = 0; f < 2; f++)
        {
            auto list = frame(f);
            REQUIRE(list.size() == 5);
            CHECK(list[0]->name == prefix + " - Classify tiles");
            CHECK(list[1]->name == prefix + " - Smooth tiles");
            CHECK(list[2]->name == prefix + " - Blur");
            CHECK(list[3]->name == prefix + " - Post-blur");
            CHECK(list[4]->name == prefix + " - Temporal stabilization");
            CHECK(list[0]->gridWidth == 120); // One 16x16 group per tile.
            CHECK(list[0]->gridHeight == 68);
            CHECK(list[1]->gridWidth == 15); // One thread per tile, 8x8 groups.
            CHECK(list[1]->gridHeight == 9);
            // History ping-pong: frame parity f writes permanent textures 2f, 2f + 1 (bindings 9, 10)
            // and reads the other pair (bindings 6, 7).
            const DispatchDesc& temporal = *list[4];
            REQUIRE(temporal.resourcesNum == 11);
            CHECK(temporal.resources[6].type == ResourceType::PERMANENT_POOL);
            CHECK(temporal.resources[6].indexInPool == 2 * (1 - f));
            CHECK(temporal.resources[7].indexInPool == 2 * (1 - f) + 1);
            CHECK(temporal.resources[9].indexInPool == 2 * f);
            CHECK(temporal.resources[10].indexInPool == 2 * f + 1);
            CHECK(temporal.resources[8].type == ResourceType::OUT_SHADOW_TRANSLUCENCY);
        }

        SigmaSettings settings = {};
        settings.maxStabilizedFrameNum = 0;
        REQUIRE(SetMethodSettings(*denoiser, SIGMA_ID, settings) == Result::SUCCESS);
        auto list = frame(2);
        REQUIRE(list.size() == 4); // No history: the post-blur writes the output.
        CHECK(list[3]->resources[5].type == ResourceType::OUT_SHADOW_TRANSLUCENCY);
        DestroyDenoiser(denoiser);
    }
}

TEST_CASE("SigmaSettings out of range are rejected with a message", "[api][sigma]")
{
    MethodDesc methodDesc = {SIGMA_ID, Method::SIGMA_SHADOW};
    DenoiserCreationDesc desc = {};
    desc.methods = &methodDesc;
    desc.methodsNum = 1;
    desc.renderWidth = 64;
    desc.renderHeight = 64;
    std::string lastMessage;
    desc.logCallback = [](void* user, LogSeverity, const char* message) { *static_cast<std::string*>(user) = message; };
    desc.logUserArg = &lastMessage;
    Denoiser* denoiser = nullptr;
    REQUIRE(CreateDenoiser(desc, denoiser) == Result::SUCCESS);
    auto reject = [&](const SigmaSettings& s, const char* field)
    {
        lastMessage.clear();
        CHECK(SetMethodSettings(*denoiser, SIGMA_ID, s) == Result::INVALID_ARGUMENT);
        CHECK(lastMessage.find(field) != std::string::npos);
    };
    SigmaSettings s = {};
    s.blurRadiusScale = SIGMA_MAX_BLUR_RADIUS_SCALE * 2.0f;
    reject(s, "blurRadiusScale");
    s = {};
    s.planeDistanceSensitivity = -0.1f;
    reject(s, "planeDistanceSensitivity");
    s = {};
    s.planeDistanceSensitivity = NAN;
    reject(s, "planeDistanceSensitivity");
    s = {};
    s.lightDirection[2] = INFINITY;
    reject(s, "lightDirection");
    s = {};
    s.maxStabilizedFrameNum = 1000;
    reject(s, "maxStabilizedFrameNum");
    s = {};
    s.tanOfLightAngularRadius = -0.01f;
    reject(s, "tanOfLightAngularRadius");
    s = {};
    s.tanOfLightAngularRadius = NAN;
    reject(s, "tanOfLightAngularRadius");
    s = {};
    s.lightRadius = -1.0f;
    reject(s, "lightRadius");
    s = {};
    s.lightPosition[1] = INFINITY;
    reject(s, "lightPosition");
    s = {};
    s.lightDirection[0] = 1.0f;
    s.blurRadiusScale = 0.0f; // Edges of the ranges are valid.
    s.planeDistanceSensitivity = 1.0f;
    s.maxStabilizedFrameNum = SIGMA_MAX_HISTORY_FRAME_NUM;
    s.tanOfLightAngularRadius = 1.0f;
    s.lightRadius = 1e6f;
    s.lightPosition[2] = -1e30f;
    CHECK(SetMethodSettings(*denoiser, SIGMA_ID, s) == Result::SUCCESS);
    DestroyDenoiser(denoiser);
}

TEST_CASE("SIGMA denoises a penumbra on a ground plane seen at a grazing angle", "[vulkan][sigma]")
{
    // The still camera looks along +z with view y pointing down the image; the ground is the plane
    // y = 1 (normal towards the camera and the sun: -y), so viewZ = 1 / ndc.y below the horizon and
    // the upper half is sky. The sun is overhead: the penumbra is a band of world radius 0.15
    // around x = 0.3, its pixel size shrinking with distance.
    const uint32_t w = 192, h = 128;
    const float radius = 0.15f, edge = 0.3f;
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        Scene scene;
        scene.width = w;
        scene.height = h;
        scene.hasSky = false; // Sky comes from viewZ below; metrics use the ground only.
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        SigmaSettings settings = {};
        settings.lightDirection[1] = -1.0f;
        rig.Create(settings);

        auto ground = [&](uint32_t y) { return (float(y) + 0.5f) / float(h) * 2.0f - 1.0f > 0.02f; };
        double noisySum = 0.0, denoisedSum = 0.0;
        const uint32_t frames = 8;
        for (uint32_t frame = 0; frame < frames; frame++)
        {
            FrameData f = MakeFrame(scene, 10000 + frame);
            std::mt19937 rng(11000 + frame);
            std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < w; x++)
                {
                    size_t i = size_t(y) * w + x;
                    float ndcX = (float(x) + 0.5f) / float(w) * 2.0f - 1.0f;
                    float ndcY = (float(y) + 0.5f) / float(h) * 2.0f - 1.0f;
                    bool isGround = ground(y);
                    float viewZ = isGround ? 1.0f / ndcY : INFINITY;
                    float worldX = ndcX * viewZ;
                    float truth =
                        isGround ? std::min(std::max((worldX - edge + radius) / (2.0f * radius), 0.0f), 1.0f) : 1.0f;
                    bool lit = uniform(rng) < truth;
                    f.viewZ[i] = viewZ;
                    f.normal[i * 4 + 0] = 0.5f;
                    f.normal[i * 4 + 1] = 0.0f; // -y
                    f.normal[i * 4 + 2] = 0.5f;
                    f.shadowData[i * 2 + 0] = lit ? 1.0f : 0.0f;
                    f.shadowData[i * 2 + 1] = lit ? kFp16Max : radius / viewZ;
                    for (int c = 0; c < 4; c++)
                    {
                        f.truth[i * 4 + c] = truth;
                        f.noisy[i * 4 + c] = f.shadowData[i * 2 + 0];
                    }
                }
            std::vector<float> output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
            WriteStrip(scene, ("sigma_ground_" + std::to_string(frame)).c_str(), f.noisy, output, f.truth);
            // Ground pixels only (sky keeps the sentinel).
            std::vector<float> o, t, n;
            size_t skyWritten = 0;
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < w; x++)
                    if (ground(y))
                    {
                        size_t i = (size_t(y) * w + x) * 4;
                        o.push_back(output[i]);
                        t.push_back(f.truth[i]);
                        n.push_back(f.noisy[i]);
                    }
                    else
                        skyWritten += output[(size_t(y) * w + x) * 4] != kOutputSentinel;
            CHECK(skyWritten == 0);
            nrdlab::Image oi(uint32_t(o.size()), 1, 1), ti(uint32_t(t.size()), 1, 1), ni(uint32_t(n.size()), 1, 1);
            oi.pixels = o;
            ti.pixels = t;
            ni.pixels = n;
            if (frame >= frames - 2)
            {
                noisySum += nrdlab::RelMSE(ni, ti);
                denoisedSum += nrdlab::RelMSE(oi, ti);
            }
        }
        std::printf("SIGMA ground plane quality factor: %.1fx\n", noisySum / denoisedSum);
        CHECK(noisySum / denoisedSum > kGroundPlaneFactor);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA leaves no light behind in the umbra of a hard shadow that moves", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        Scene scene;
        scene.width = 96;
        scene.height = 64;
        scene.penumbraRadius = 0.3f; // Sub-pixel: a hard shadow.
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();
        for (uint32_t frame = 0; frame < 10; frame++)
        {
            rig.scene.edgeOffset = -20.0f + 4.0f * float(frame); // The occluder moves 4 px per frame.
            FrameData f = MakeFrame(rig.scene, 12000 + frame);
            std::vector<float> output = rig.Frame(frame, f);
            size_t lightInUmbra = 0;
            for (size_t i = 0; i < output.size(); i += 4)
                lightInUmbra += f.truth[i] == 0.0f && output[i] > 0.02f;
            INFO("frame " << frame);
            CHECK(lightInUmbra == 0);
            CHECK(RelMse(rig.scene, output, f.truth) <= RelMse(rig.scene, f.noisy, f.truth));
        }
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA takes up a lamp's history again when it is switched back on", "[vulkan][sigma]")
{
    // Still camera, 96x64: a lamp's soft shadow edge (penumbra radius 8 pixels) for 12 frames, then the
    // lamp off for 3 frames (every sample 0: every tile uniform, copied), then on again. On the frames
    // off the output is the input (0); on the first frame back the penumbra's error stays close to what
    // it was before the switch (HOLD_MIN_HISTORY: 0.0049 against 0.0052), where the history restarted
    // from the frames off, as one that saw the lamp off only, leaves about 1.4 times as much (0.0072).
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const uint32_t offFrom = 12, onAgain = 15;
    Scene scene;
    scene.width = 96;
    scene.height = 64;
    scene.penumbraRadius = 8.0f;
    auto run = [&](bool (*lampOn)(uint32_t), std::vector<double>& errors, uint32_t& nonZeroOff) {
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();
        for (uint32_t frame = 0; frame <= onAgain; frame++)
        {
            FrameData f = MakeFrame(scene, 13000 + frame);
            bool isOn = lampOn(frame);
            if (!isOn)
            {
                for (size_t i = 0; i < f.viewZ.size(); i++)
                {
                    f.shadowData[i * 2 + 0] = 0.0f;
                    f.shadowData[i * 2 + 1] = scene.PenumbraOverViewZ();
                    for (int c = 0; c < 4; c++)
                        f.shadowTranslucency[i * 4 + c] = f.noisy[i * 4 + c] = f.truth[i * 4 + c] = 0.0f;
                }
            }
            std::vector<float> output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
            errors.push_back(isOn ? RelMse(scene, output, f.truth) : 0.0);
            for (size_t i = 0; i < output.size() && !isOn; i += 4)
                nonZeroOff += output[i] != 0.0f ? 1u : 0u;
        }
    };
    std::vector<double> toggled, fresh;
    uint32_t nonZeroToggled = 0, nonZeroFresh = 0;
    run([](uint32_t frame) { return frame < 12 || frame >= 15; }, toggled, nonZeroToggled);
    run([](uint32_t frame) { return frame >= 15; }, fresh, nonZeroFresh);
    std::printf("SIGMA_SHADOW a lamp off for 3 frames: penumbra relMSE before %.5f, on the frame back %.5f, restarted %.5f\n",
                toggled[offFrom - 1], toggled[onAgain], fresh[onAgain]);
    CHECK(nonZeroToggled == 0);
    CHECK(toggled[onAgain] <= 1.2 * toggled[offFrom - 1]);
    CHECK(toggled[onAgain] * 1.3 <= fresh[onAgain]);
    CHECK(context->ValidationMessageCount() == 0);
}

// A still view reprojects each pixel onto its own texel's centre only up to the rounding of the
// matrices and of uv * size; the bilinear weight that rounding gives a lit neighbour must not reach
// the history of a hard shadow's umbra (Shaders/Include/Reprojection.glsl, NRD_FOOTPRINT_SNAP).
TEST_CASE("SIGMA outputs exactly 0 in a still hard shadow's umbra beside its lit side", "[vulkan][sigma]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        Scene scene;
        scene.width = 200; // Texel coordinates up to 199: larger roundings of uv * size.
        scene.height = 72;
        scene.penumbraRadius = 0.3f; // Sub-pixel: a hard shadow.
        scene.edgeOffset = 37.3f;
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();
        size_t umbra = 0, lit = 0;
        for (uint32_t frame = 0; frame < 16; frame++)
        {
            FrameData f = MakeFrame(rig.scene, 12500 + frame);
            std::vector<float> output = rig.Frame(frame, f);
            size_t notDark = 0, notLit = 0;
            umbra = lit = 0;
            for (size_t i = 0; i < output.size(); i += 4)
            {
                umbra += f.truth[i] == 0.0f;
                lit += f.truth[i] == 1.0f;
                notDark += f.truth[i] == 0.0f && output[i] != 0.0f;
                notLit += f.truth[i] == 1.0f && output[i] != 1.0f;
            }
            INFO("frame " << frame);
            CHECK(notDark == 0);
            CHECK(notLit == 0);
        }
        CHECK(umbra > 2000);
        CHECK(lit > 2000);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA keeps no history of hard shadows that a moving light carries", "[vulkan][sigma]")
{
    // A hard shadow edge (penumbra radius 0.3 pixel) that moves 0.25 pixel a frame without motion
    // vectors. The light moves 0.833 penumbra radii a frame: an infinite light turning by tan 0.00833
    // a frame under tan(radius) 0.01 (SigmaSettings::tanOfLightAngularRadius and a lightDirection
    // that turns), or a sphere light of radius 0.1, five units above and in front of the plane, moving
    // 0.12 a frame along +x (about 1.2 radii across the direction to the pixels): every pixel outputs
    // its sample. The same frames with the light's size unknown, or with a light that stays, keep
    // history.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    enum class Light { INFINITE, SPHERE };
    auto run = [&](Light type, float size, float step, size_t& changed)
    {
        Scene scene;
        scene.width = 64;
        scene.height = 64;
        scene.penumbraRadius = 0.3f;
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();
        changed = 0;
        for (uint32_t frame = 0; frame < 8; frame++)
        {
            SigmaSettings settings = {};
            test::SetMovingTestLight(settings, type == Light::INFINITE, size, step, frame, kPlaneViewZ);
            REQUIRE(rig.integration.SetMethodSettings(SIGMA_ID, settings) == Result::SUCCESS);
            rig.scene.edgeOffset = 0.25f * float(frame);
            FrameData f = MakeFrame(rig.scene, (type == Light::INFINITE ? 13000 : 14000) + frame);
            std::vector<float> output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
            if (frame == 0)
                continue; // No previous light yet.
            for (size_t i = 0; i < output.size(); i += 4)
                changed += std::abs(output[i] - f.noisy[i]) > 1e-3f;
        }
    };
    size_t turning = 0, moving = 0, unknownSize = 0, unknownRadius = 0, stillSun = 0, stillLamp = 0;
    run(Light::INFINITE, 0.01f, 0.00833f, turning);
    run(Light::SPHERE, 0.1f, 0.12f, moving);
    run(Light::INFINITE, 0.0f, 0.00833f, unknownSize);
    run(Light::SPHERE, 0.0f, 0.12f, unknownRadius);
    run(Light::INFINITE, 0.01f, 0.0f, stillSun);
    run(Light::SPHERE, 0.1f, 0.0f, stillLamp);
    INFO("pixels unlike their sample over 7 frames: turning light " << turning << ", moving sphere light " << moving
                                                                     << ", sizes unknown " << unknownSize << " and " << unknownRadius
                                                                     << ", still lights " << stillSun << " and " << stillLamp);
    CHECK(turning == 0);
    CHECK(moving == 0);
    // 29 and 26 on lavapipe.
    CHECK(unknownSize >= 10);
    CHECK(unknownRadius >= 10);
    CHECK(stillSun >= 10);
    CHECK(stillLamp >= 10);
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA outputs the lit samples that a moving light's shadow leaves, also beside a zero penumbra", "[vulkan][sigma]")
{
    // A hard shadow edge whose shadowed samples report a penumbra of 0 (a contact shadow: the motion
    // estimate of ShadowMotion.glsl reads 0 there) leaves one pixel a frame, without motion vectors.
    // While a sphere light moves, every pixel that its departure lights outputs its lit sample. With
    // the light still, the tile's departures (a column a frame, no arrival) read as a light switched on
    // over a sharp edge, and a lit sample restarts next to one departed neighbour: none stays below 0.5
    // either. On lavapipe: 0 and 0; 0 and 256 before the switched-on tile (the lit column has two
    // departed neighbours only, under the departure rows' three), 256 and 256 before the moving-light
    // rule (Shaders/Sigma/README.md, "Lit samples under dark history while the light moves", "Passed
    // samples restart the history; lights switched on over sharp edges").
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    auto run = [&](float step)
    {
        Scene scene;
        scene.width = 64;
        scene.height = 64;
        scene.penumbraRadius = 1e-4f;
        scene.edgeAngle = 0.0f; // A vertical edge: x > 32 - frame lit.
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();
        size_t darkened = 0;
        for (uint32_t frame = 0; frame < 8; frame++)
        {
            SigmaSettings settings = {};
            test::SetMovingTestLight(settings, false, 0.1f, step, frame, kPlaneViewZ);
            REQUIRE(rig.integration.SetMethodSettings(SIGMA_ID, settings) == Result::SUCCESS);
            rig.scene.edgeOffset = -float(frame);
            FrameData f = MakeFrame(rig.scene, 15000 + frame);
            for (size_t i = 0; i < f.shadowData.size(); i += 2)
                f.shadowData[i + 1] = f.shadowData[i] == 0.0f ? 0.0f : f.shadowData[i + 1];
            std::vector<float> output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
            for (size_t i = 0; frame > 0 && i < output.size(); i += 4)
                darkened += f.noisy[i] == 1.0f && output[i] < 0.5f;
        }
        return darkened;
    };
    size_t moving = run(0.12f), still = run(0.0f);
    INFO("lit samples output below 0.5 over 7 frames: moving light " << moving << ", still light " << still);
    CHECK(moving == 0);
    CHECK(still == 0);
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA starts a restarted penumbra about a pixel wide from its 3x3 mean and not its sample", "[vulkan][sigma]")
{
    // A lamp switched on after 6 dark frames over a still edge whose penumbra is 1.2 pixels in
    // radius (kernel 0.72 pixel: a hard shadow, which the blurs copy). Its lit samples under the
    // dark history restart (departure rows); where their 3x3 holds lit and shadowed samples they
    // take HARD_SHADOW_RESTART_BLEND of the 3x3 mean, and the shadowed samples beside them under the
    // dark history HARD_SHADOW_FOLLOWER_BLEND (the tile's hard shadows depart). On lavapipe the first
    // lit frame's relMSE is 0.24 of the samples' (0.31 with the restarted pixels' rule alone, 0.50
    // without either: the restarted pixels output their samples, the others keep their dark
    // history), and pixels whose 3x3 truth is exactly 0 or 1 keep their exact samples.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    Scene scene;
    scene.width = 64;
    scene.height = 64;
    scene.penumbraRadius = 1.2f;
    scene.edgeAngle = 0.2f;
    SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
    rig.Create();
    const uint32_t darkFrames = 6;
    for (uint32_t frame = 0; frame <= darkFrames; frame++)
    {
        FrameData f = MakeFrame(scene, 16000 + frame);
        if (frame < darkFrames) // The lamp is off: every sample shadowed, with the edge's penumbra.
        {
            for (size_t i = 0; i < f.shadowData.size() / 2; i++)
            {
                f.shadowData[i * 2 + 0] = 0.0f;
                f.shadowData[i * 2 + 1] = scene.PenumbraOverViewZ();
            }
        }
        std::vector<float> output = rig.Frame(frame, f);
        REQUIRE(AllFinite(output));
        if (frame < darkFrames)
            continue;
        double noisy = RelMse(scene, f.noisy, f.truth), denoised = RelMse(scene, output, f.truth);
        size_t changedOutsidePenumbra = 0; // Pixels whose 3x3 truth is uniform keep their exact value.
        for (uint32_t y = 1; y + 1 < scene.height; y++)
        {
            for (uint32_t x = 1; x + 1 < scene.width; x++)
            {
                bool uniform = true;
                for (int j = -1; j <= 1; j++)
                    for (int i = -1; i <= 1; i++)
                        uniform = uniform && scene.Truth(x + i, y + j) == scene.Truth(x, y) &&
                                  (scene.Truth(x, y) == 0.0f || scene.Truth(x, y) == 1.0f);
                size_t k = (size_t(y) * scene.width + x) * 4;
                changedOutsidePenumbra += uniform && output[k] != f.noisy[k];
            }
        }
        INFO("first lit frame: relMSE of the samples " << noisy << ", of the output " << denoised << " ("
                                                      << denoised / noisy << "x); pixels changed outside the penumbra "
                                                      << changedOutsidePenumbra);
        CHECK(denoised < 0.28 * noisy);
        CHECK(changedOutsidePenumbra == 0);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA reads no history of the sky under motion", "[vulkan][sigma]")
{
    // A penumbra that reaches the sky (the top quarter), moving a fraction of a pixel a frame on both
    // axes: the soft shadow's history is resampled with Catmull-Rom, whose outer taps next to the sky
    // lie in it, where no history exists. Before every frame, one run fills the sky's texels of every
    // float permanent texture (the histories) with a value no pass writes; the output must be the
    // same bit for bit as without.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    auto run = [&](bool poison)
    {
        Scene scene;
        scene.width = 96;
        scene.height = 96;
        scene.penumbraRadius = 12.0f;
        scene.hasSky = true;
        SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
        rig.Create();
        const DenoiserDesc& desc = rig.integration.GetDenoiserDesc();
        std::vector<float> output;
        for (uint32_t frame = 0; frame < 6; frame++)
        {
            for (uint16_t k = 0; poison && frame > 0 && k < desc.permanentPoolSize; k++)
            {
                Integration::PoolImage image = rig.integration.GetPoolImage(ResourceType::PERMANENT_POOL, k);
                rhi::Format format = rhi::FromVkFormat(image.format);
                if (format == rhi::Format::R32_UINT)
                    continue; // viewZ | history length: kept (it marks the sky as having no history).
                std::vector<float> pixels = test::ReadbackPoolTexture(*context, rig.integration, ResourceType::PERMANENT_POOL, k);
                uint32_t channels = uint32_t(pixels.size() / (size_t(image.width) * image.height));
                for (uint32_t y = 0; y < image.height; y++)
                    for (uint32_t x = 0; x < image.width && scene.IsSky(x, y); x++)
                        for (uint32_t c = 0; c < channels; c++)
                            pixels[(size_t(y) * image.width + x) * channels + c] = 0.8125f;
                test::WritePoolTexture(*context, rig.integration, ResourceType::PERMANENT_POOL, k, pixels);
            }
            // 2D motion vectors of a sub-pixel motion on both axes (uvPrev = uv + mv): every tap of the
            // Catmull-Rom footprint has a weight.
            FrameData f = MakeFrame(rig.scene, 9100 + frame);
            for (size_t i = 0; i < f.mv.size(); i += 2)
            {
                f.mv[i + 0] = 0.37f / float(scene.width);
                f.mv[i + 1] = 0.41f / float(scene.height);
            }
            output = rig.Frame(frame, f);
            REQUIRE(AllFinite(output));
        }
        return output;
    };
    std::vector<float> clean = run(false), poisoned = run(true);
    REQUIRE(clean.size() == poisoned.size());
    size_t differ = 0;
    for (size_t i = 0; i < clean.size(); i++)
        differ += clean[i] != poisoned[i];
    INFO(differ << " output values differ");
    CHECK(differ == 0);
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA outputs a lit sample of a mostly dark sub-pixel penumbra under camera motion as its samples' mean",
          "[vulkan][sigma]")
{
    // A hard shadow (penumbra 0.9 pixel wide) under a camera moving 1.3 pixels a frame (matrices only):
    // its history needs resampling. A lit sample where the truth is under a quarter is the costliest
    // error of the input; it takes most of the running mean of the samples that the motion carried
    // over that point (mean output 0.55 on lavapipe, 0.95 without). Lit pixels away from the edge and
    // dark samples of the umbra stay exact.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    Scene scene;
    scene.width = 128;
    scene.height = 128;
    scene.penumbraRadius = 0.45f;
    SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
    rig.Create();
    const float speed = 1.3f;
    double litInDarkSum = 0.0, noisy = 0.0, denoised = 0.0;
    size_t litInDarkNum = 0, inexactLit = 0, inexactDark = 0;
    for (uint32_t frame = 0; frame < 14; frame++)
    {
        CommonSettings settings = TranslatingCamera(rig.scene, frame, speed);
        FrameData f = MakeFrame(rig.scene, 15000 + frame);
        settings.motionVectorScale[0] = settings.motionVectorScale[1] = settings.motionVectorScale[2] = 0.0f;
        std::vector<float> output = rig.Frame(settings, f);
        REQUIRE(AllFinite(output));
        if (frame < 4)
            continue;
        noisy += RelMse(rig.scene, f.noisy, f.truth);
        denoised += RelMse(rig.scene, output, f.truth);
        for (uint32_t y = 1; y + 1 < scene.height; y++)
        {
            for (uint32_t x = 1; x + 1 < scene.width; x++)
            {
                size_t i = (size_t(y) * scene.width + x) * 4;
                float truth = f.truth[i], sample = f.noisy[i];
                if (sample == 1.0f && truth > 0.0f && truth < 0.25f)
                {
                    litInDarkSum += output[i];
                    litInDarkNum++;
                }
                // Away from the edge: the 3x3 truth is uniform.
                float lo = 1.0f, hi = 0.0f;
                for (int j = -1; j <= 1; j++)
                    for (int k = -1; k <= 1; k++)
                    {
                        float t = rig.scene.Truth(uint32_t(int(x) + k), uint32_t(int(y) + j));
                        lo = std::min(lo, t);
                        hi = std::max(hi, t);
                    }
                inexactLit += lo == 1.0f && output[i] != 1.0f;
                inexactDark += hi == 0.0f && output[i] != 0.0f;
            }
        }
    }
    double litInDarkMean = litInDarkSum / double(std::max<size_t>(litInDarkNum, 1));
    std::printf("SIGMA lit samples of a dark sub-pixel penumbra under camera motion: %zu, mean output %.3f; "
                "relMSE factor %.2fx\n", litInDarkNum, litInDarkMean, noisy / denoised);
    CHECK(litInDarkNum >= 20);
    CHECK(litInDarkMean < 0.65);
    CHECK(inexactLit == 0);
    CHECK(inexactDark == 0);
    CHECK(denoised < noisy);
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("SIGMA keeps the lit side of a sharp edge exact once a moving camera stops", "[vulkan][sigma]")
{
    // A sharp shadow edge (penumbra 0.1 pixel wide: its samples are exact) under a camera that moves 1.3
    // pixels a frame for 8 frames (matrices only) and then stays. Under motion the hard-shadow history is
    // the running mean of the samples, greyed near the edge by resampling across it; once the view is
    // still, that mean must not be blended into the exact samples beside the edge.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    Scene scene;
    scene.width = 64;
    scene.height = 64;
    scene.penumbraRadius = 0.05f;
    SigmaRig rig(*context, Method::SIGMA_SHADOW, scene);
    rig.Create();
    const float speed = 1.3f;
    const uint32_t movingFrames = 8;
    size_t exactNum = 0, inexactLit = 0, inexactDark = 0;
    float worstLit = 1.0f;
    for (uint32_t frame = 0; frame < movingFrames + 5; frame++)
    {
        CommonSettings settings = TranslatingCamera(rig.scene, std::min(frame, movingFrames), speed);
        if (frame > movingFrames) // Still: this frame's camera is the previous frame's.
            std::copy(settings.worldToViewMatrix, settings.worldToViewMatrix + 16, settings.worldToViewMatrixPrev);
        settings.frameIndex = frame;
        FrameData f = MakeFrame(rig.scene, 17000 + frame);
        settings.motionVectorScale[0] = settings.motionVectorScale[1] = settings.motionVectorScale[2] = 0.0f;
        std::vector<float> output = rig.Frame(settings, f);
        REQUIRE(AllFinite(output));
        if (frame <= movingFrames)
            continue;
        for (size_t i = 0; i < output.size(); i += 4)
        {
            float truth = f.truth[i];
            if (truth != 0.0f && truth != 1.0f)
                continue;
            exactNum++;
            if (truth == 1.0f && output[i] != 1.0f)
            {
                inexactLit++;
                worstLit = std::min(worstLit, output[i]);
            }
            inexactDark += truth == 0.0f && output[i] != 0.0f;
        }
    }
    std::printf("SIGMA after a moving camera stops: %zu of %zu exact pixels lit are inexact (lowest %.3f), %zu dark\n", inexactLit,
                exactNum, worstLit, inexactDark);
    CHECK(exactNum > 4 * 64 * 60);
    CHECK(inexactLit == 0);
    CHECK(inexactDark == 0);
    CHECK(context->ValidationMessageCount() == 0);
}
