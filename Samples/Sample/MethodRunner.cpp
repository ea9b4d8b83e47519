#include "MethodRunner.h"

#include "Metrics.h"
#include "NRDIntegration.h"
#include "ReuseBounds.h"
#include "SceneLab.h"
#include "VulkanContext.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>

namespace nrdlab
{

namespace
{

constexpr nrd::Identifier kId = 0;

// What a method reads and writes, and which scene-lab signals feed it.
struct MethodIo
{
    bool none = false;   // "NONE": pass the noisy input through.
    nrd::Method method = nrd::Method::MAX_NUM;
    std::string signal;  // Report name: shadow, diffuse, specular.
    SignalMask labSignals = 0;
    uint32_t channels = 1; // Channels compared against the truth.
};

bool ResolveMethod(const RunOptions& o, MethodIo& io, std::string& error)
{
    io.none = o.method == "NONE";
    if (!io.none && !nrd::GetMethodFromString(o.method.c_str(), io.method))
    {
        error = "unknown method '" + o.method + "' (";
        const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
        for (uint32_t i = 0; i < lib.supportedMethodsNum; i++)
            error += std::string(nrd::GetMethodString(lib.supportedMethods[i])) + ", ";
        error += "NONE)";
        return false;
    }
    io.signal = o.signal.empty() ? "shadow" : o.signal;
    bool shadowOnly = !io.none && io.method != nrd::Method::REFERENCE;
    if (io.signal != "shadow" && (shadowOnly || (io.signal != "diffuse" && io.signal != "specular")))
    {
        error = "signal '" + io.signal + "' is not available for method " + o.method;
        return false;
    }
    bool translucency = !io.none && io.method == nrd::Method::SIGMA_SHADOW_TRANSLUCENCY;
    if (io.signal == "shadow")
    {
        io.labSignals = translucency ? SIGNAL_TRANSLUCENCY : SIGNAL_SHADOW;
        io.channels = translucency ? 4 : 1;
    }
    else
    {
        io.labSignals = io.signal == "diffuse" ? SIGNAL_DIFFUSE : SIGNAL_SPECULAR;
        io.channels = 3;
    }
    return true;
}

// Keeps the first 'channels' channels of an image.
Image Channels(const Image& src, uint32_t channels)
{
    Image out(src.width, src.height, channels);
    for (uint32_t i = 0; i < src.width * src.height; i++)
        for (uint32_t c = 0; c < channels; c++)
            out.pixels[i * channels + c] = c < src.channels ? src.pixels[i * src.channels + c] : 0.0f;
    return out;
}

// Widens an image to 'channels' channels (missing ones get 'fill').
std::vector<float> Expand(const Image& src, uint32_t channels, float fill = 0.0f)
{
    std::vector<float> out(size_t(src.width) * src.height * channels, fill);
    for (uint32_t i = 0; i < src.width * src.height; i++)
        for (uint32_t c = 0; c < channels && c < src.channels; c++)
            out[size_t(i) * channels + c] = src.pixels[size_t(i) * src.channels + c];
    return out;
}

// Noisy input and truth of the signal, in the compared channels.
void SignalImages(const FrameData& f, const MethodIo& io, Image& noisy, Image& truth)
{
    if (io.signal == "shadow")
    {
        if (io.labSignals & SIGNAL_TRANSLUCENCY)
        {
            noisy = Channels(f.translucency, 4);
            truth = Channels(f.translucencyTruth, 4);
        }
        else
        {
            noisy = Channels(f.shadowVisibility, 1);
            truth = Channels(f.shadowTruth, 1);
        }
    }
    else
    {
        const Image& n = io.signal == "diffuse" ? f.diffuse : f.specular;
        const Image& t = io.signal == "diffuse" ? f.diffuseTruth : f.specularTruth;
        noisy = Channels(n, 3);
        truth = Channels(t, 3);
    }
}

template <class T>
void ReadField(const nlohmann::json& j, const char* key, T& value)
{
    if (j.contains(key))
        value = j.at(key).get<T>();
}

bool ParseSettings(const std::string& text, nrd::CommonSettings& common, nrd::SigmaSettings& sigma,
                   nrd::ReferenceSettings& reference, nrd::TiledShadowSettings& tiled, bool& motion3d, bool& motionNone,
                   std::string& error)
{
    if (text.empty())
        return true;
    try
    {
        nlohmann::json j = nlohmann::json::parse(text);
        for (auto it = j.begin(); it != j.end(); ++it)
            if (it.key() != "common" && it.key() != "sigma" && it.key() != "reference" && it.key() != "tiledShadow")
            {
                error = "settings: unknown key '" + it.key() + "' (common, sigma, reference, tiledShadow)";
                return false;
            }
        if (j.contains("common"))
        {
            const auto& c = j["common"];
            ReadField(c, "denoisingRange", common.denoisingRange);
            ReadField(c, "disocclusionThreshold", common.disocclusionThreshold);
            std::string motion = motion3d ? "3d" : "2d";
            ReadField(c, "motion", motion);
            if (motion != "2d" && motion != "3d" && motion != "none")
            {
                error = "settings: common.motion must be 2d, 3d or none";
                return false;
            }
            motion3d = motion == "3d";
            motionNone = motion == "none";
        }
        if (j.contains("sigma"))
        {
            const auto& s = j["sigma"];
            ReadField(s, "planeDistanceSensitivity", sigma.planeDistanceSensitivity);
            ReadField(s, "blurRadiusScale", sigma.blurRadiusScale);
            ReadField(s, "maxStabilizedFrameNum", sigma.maxStabilizedFrameNum);
        }
        if (j.contains("reference"))
            ReadField(j["reference"], "maxAccumulatedFrameNum", reference.maxAccumulatedFrameNum);
        if (j.contains("tiledShadow"))
        {
            const auto& t = j["tiledShadow"];
            ReadField(t, "enableTileSkipping", tiled.enableTileSkipping);
            ReadField(t, "neighborhoodRadius", tiled.neighborhoodRadius);
            ReadField(t, "historyClampSigma", tiled.historyClampSigma);
            ReadField(t, "atrousPassNum", tiled.atrousPassNum);
            ReadField(t, "maxHistoryFrameNum", tiled.maxHistoryFrameNum);
            ReadField(t, "planeDistanceSensitivity", tiled.planeDistanceSensitivity);
            ReadField(t, "normalPower", tiled.normalPower);
            if (t.contains("debugView"))
                tiled.debugView = nrd::TiledShadowDebug(t["debugView"].get<int>());
        }
    }
    catch (const std::exception& e)
    {
        error = std::string("settings: ") + e.what();
        return false;
    }
    return true;
}

struct Textures
{
    nrd::lab::VulkanContext* vk = nullptr;
    std::map<nrd::ResourceType, nrd::lab::LabTexture> map;
    ~Textures()
    {
        for (auto& t : map)
            vk->DestroyTexture(t.second);
    }
};

// Application texture format of each resource this runner binds.
nrd::rhi::Format FormatOf(nrd::ResourceType type, uint32_t& channels)
{
    using F = nrd::rhi::Format;
    switch (type)
    {
    case nrd::ResourceType::IN_VIEWZ: channels = 1; return F::R32_SFLOAT;
    case nrd::ResourceType::IN_SHADOWDATA: channels = 2; return F::RG16_SFLOAT;
    case nrd::ResourceType::IN_SHADOW_VISIBILITY: channels = 1; return F::R8_UNORM;
    case nrd::ResourceType::IN_RADIANCE: channels = 4; return F::RGBA32_SFLOAT;
    case nrd::ResourceType::OUT_RADIANCE: channels = 4; return F::RGBA32_SFLOAT;
    case nrd::ResourceType::IN_SHADOW_BITMASK: channels = 1; return F::R32_UINT;
    default: channels = 4; return F::RGBA16_SFLOAT;
    }
}

} // namespace

bool RunMethod(const RunOptions& o, RunReport& report, std::string& error)
{
    report = {};
    MethodIo io;
    if (!ResolveMethod(o, io, error))
        return false;
    if (o.width == 0 || o.height == 0 || o.width > 8192 || o.height > 8192)
    {
        error = "size must be within 1x1 .. 8192x8192";
        return false;
    }

    Scene scene;
    if (!LoadScene(o.scene, scene, error))
        return false;

    nrd::CommonSettings common;
    nrd::SigmaSettings sigma;
    nrd::ReferenceSettings reference;
    nrd::TiledShadowSettings tiled;
    bool motion3d = true, motionNone = false;
    if (!ParseSettings(o.settingsJson, common, sigma, reference, tiled, motion3d, motionNone, error))
        return false;

    nrd::lab::VulkanContextDesc vkDesc;
    vkDesc.enableValidation = o.validation;
    vkDesc.deviceIndex = o.device;
    vkDesc.quiet = true;
    nrd::lab::VulkanContext vk;
    if (vk.Create(vkDesc) != VK_SUCCESS)
    {
        error = "could not create a Vulkan device (index " + std::to_string(o.device) + ")";
        return false;
    }

    SceneLabDesc labDesc;
    labDesc.cacheDirectory = o.cacheDirectory == "none" ? "" : (o.cacheDirectory.empty() ? GetDefaultCacheDirectory() : o.cacheDirectory);
    SceneLab lab(vk, labDesc);
    if (!lab.IsValid())
    {
        error = "scene lab: " + lab.GetError();
        return false;
    }

    report.scene = scene.name.empty() ? o.scene : scene.name;
    report.method = o.method;
    report.signal = io.signal;
    report.device = vk.GetProperties().deviceName;
    report.width = o.width;
    report.height = o.height;
    report.frames = o.frames ? o.frames : scene.frameNum;
    report.warmup = std::min(o.warmup, report.frames > 0 ? report.frames - 1 : 0u);
    report.truthSpp = o.truthSpp;

    // The denoiser and its textures.
    nrd::Integration integration;
    std::unique_ptr<Textures> textures(new Textures());
    textures->vk = &vk;
    std::vector<nrd::ResourceType> inputs, outputs;
    if (!io.none)
    {
        nrd::MethodDesc method = {kId, io.method};
        nrd::DenoiserCreationDesc desc;
        desc.methods = &method;
        desc.methodsNum = 1;
        desc.renderWidth = uint16_t(o.width);
        desc.renderHeight = uint16_t(o.height);
        if (integration.Create(vk.GetIntegrationCreationDesc(), desc) != VK_SUCCESS)
        {
            error = "could not create the denoiser";
            return false;
        }
        nrd::Result r = nrd::Result::SUCCESS;
        if (io.method == nrd::Method::REFERENCE)
            r = integration.SetMethodSettings(kId, reference);
        else if (io.method == nrd::Method::TILED_SHADOW)
            r = integration.SetMethodSettings(kId, tiled);
        else
            r = integration.SetMethodSettings(kId, sigma);
        if (r != nrd::Result::SUCCESS)
        {
            error = std::string("method settings rejected: ") + nrd::GetResultString(r);
            return false;
        }
        report.memoryBytes = integration.GetMemoryReport().totalBytes;
        report.pipelines = integration.GetDenoiserDesc().pipelinesNum;
    }

    std::vector<Image> denoisedFrames, truthFrames, noisyFrames;
    // The reported oracle (blend 0.25, kBoundAlphas[1]) first.
    ReuseBounds bounds(std::vector<float>{kBoundAlphas[1], kBoundAlphas[0], kBoundAlphas[2]});
    std::vector<double> truthChange;
    std::map<std::string, double> passSum;
    uint32_t timedFrames = 0;

    for (uint32_t f = 0; f < report.frames; f++)
    {
        if (o.progress)
            o.progress(f, report.frames);
        RenderParams params;
        params.width = o.width;
        params.height = o.height;
        params.frameIndex = f;
        params.truthSpp = o.truthSpp;
        params.seed = o.seed;
        params.signals = io.labSignals;
        FrameData frame;
        if (!lab.Render(scene, params, frame, error))
            return false;
        report.renderNoisyMs += frame.noisyMs;
        report.renderTruthMs += frame.truthMs;

        Image noisy, truth, denoised;
        SignalImages(frame, io, noisy, truth);

        if (io.none)
            denoised = noisy;
        else
        {
            // Common settings from the scene camera.
            memcpy(common.worldToViewMatrix, frame.camera.worldToView, sizeof(common.worldToViewMatrix));
            memcpy(common.viewToClipMatrix, frame.camera.viewToClip, sizeof(common.viewToClipMatrix));
            memcpy(common.worldToViewMatrixPrev, frame.camera.worldToViewPrev, sizeof(common.worldToViewMatrixPrev));
            memcpy(common.viewToClipMatrixPrev, frame.camera.viewToClipPrev, sizeof(common.viewToClipMatrixPrev));
            common.frameIndex = f;
            // motion3d is posPrev - pos (scale 1 on all axes), motion2d is uvPrev - uv (no z).
            common.isMotionVectorInWorldSpace = motion3d;
            bool ignoreMotion = motionNone;
            for (int a = 0; a < 3; a++)
                common.motionVectorScale[a] = ignoreMotion || (!motion3d && a == 2) ? 0.0f : 1.0f;
            if (io.method != nrd::Method::REFERENCE && io.method != nrd::Method::TILED_SHADOW)
            {
                memcpy(sigma.lightDirection, frame.light.direction, sizeof(sigma.lightDirection));
                integration.SetMethodSettings(kId, sigma);
            }
            if (integration.SetCommonSettings(common) != nrd::Result::SUCCESS)
            {
                error = "common settings rejected";
                return false;
            }

            // Application textures: the G-buffer, the signal, the output.
            std::map<nrd::ResourceType, std::vector<float>> data;
            data[nrd::ResourceType::IN_VIEWZ] = Expand(frame.viewZ, 1);
            data[nrd::ResourceType::IN_NORMAL_ROUGHNESS] = Expand(frame.normalRoughness, 4);
            data[nrd::ResourceType::IN_MV] = Expand(motion3d ? frame.motion3d : frame.motion2d, 4);
            if (io.labSignals & SIGNAL_TRANSLUCENCY)
            {
                data[nrd::ResourceType::IN_SHADOWDATA] = Expand(frame.translucencyShadowData, 2);
                data[nrd::ResourceType::IN_SHADOW_TRANSLUCENCY] = Expand(frame.translucency, 4);
            }
            else if (io.labSignals & SIGNAL_SHADOW)
            {
                data[nrd::ResourceType::IN_SHADOWDATA] = Expand(frame.shadowData, 2);
                data[nrd::ResourceType::IN_SHADOW_VISIBILITY] = Expand(frame.shadowVisibility, 1);
            }
            data[nrd::ResourceType::IN_RADIANCE] = Expand(noisy, 4);

            nrd::UserPool pool;
            for (auto& d : data)
            {
                uint32_t channels = 0;
                nrd::rhi::Format format = FormatOf(d.first, channels);
                auto& tex = textures->map[d.first];
                if (!tex.texture && vk.CreateTexture(format, o.width, o.height, nrd::GetResourceTypeString(d.first), tex) != VK_SUCCESS)
                {
                    error = "texture creation failed";
                    return false;
                }
                if (d.second.size() != size_t(o.width) * o.height * channels || vk.UploadTexture(tex, d.second.data()) != VK_SUCCESS)
                {
                    error = "upload failed";
                    return false;
                }
                pool[d.first] = tex.AsUserTexture();
            }
            nrd::ResourceType outType = io.method == nrd::Method::REFERENCE ? nrd::ResourceType::OUT_RADIANCE
                                                                             : nrd::ResourceType::OUT_SHADOW_TRANSLUCENCY;
            uint32_t outChannels = 0;
            auto& outTex = textures->map[outType];
            if (!outTex.texture && vk.CreateTexture(FormatOf(outType, outChannels), o.width, o.height, "output", outTex) != VK_SUCCESS)
            {
                error = "texture creation failed";
                return false;
            }
            // Sky pixels are not written: start from the noisy input so they compare as "passed through".
            std::vector<float> init = Expand(noisy, 4, 1.0f);
            vk.UploadTexture(outTex, init.data(), nrd::rhi::Layout::GENERAL);
            pool[outType] = outTex.AsUserTexture();

            VkCommandBuffer cmd;
            if (vk.BeginCommands(cmd) != VK_SUCCESS || integration.Denoise(cmd, &kId, 1, pool) != VK_SUCCESS ||
                vk.SubmitAndWait(cmd) != VK_SUCCESS)
            {
                error = "denoising failed on the device";
                return false;
            }
            for (auto& t : textures->map)
                t.second.FromUserTexture(pool[t.first]);

            std::vector<float> out;
            if (vk.ReadbackTexture(outTex, out) != VK_SUCCESS)
            {
                error = "readback failed";
                return false;
            }
            Image full(o.width, o.height, 4);
            full.pixels = out;
            denoised = Channels(full, io.channels);
            if (io.signal == "shadow")
                for (float& v : denoised.pixels) // SIGMA_BackEnd_UnpackShadow
                    v = std::isfinite(v) ? std::min(std::max(v, 0.0f), 1.0f) : 1.0f;

            double total = 0.0;
            std::vector<nrd::DispatchTiming> timings = integration.GetLastTimings(&total);
            report.dispatchesPerFrame = uint32_t(timings.size());
            FrameMetrics m;
            m.gpuMs = total;
            report.perFrame.push_back(m);
            if (f >= report.warmup)
            {
                timedFrames++;
                for (const auto& t : timings)
                    passSum[t.name] += t.milliseconds;
            }
        }
        if (io.none)
            report.perFrame.push_back(FrameMetrics{});

        FrameMetrics& m = report.perFrame.back();
        if (o.bounds)
        {
            // The object index is an exact disocclusion test on the lab's convex objects.
            const Image* surfaceId = frame.objectIndex.isValid() ? &frame.objectIndex : nullptr;
            ReuseBoundsFrame b = bounds.Add(noisy, truth, frame.motion2d, surfaceId);
            m.boundReprojectedTruth = b.reprojectedTruthRelmse;
            m.boundOracle = b.oracleRelmse;
            m.boundOracleInstability = b.oracleInstability;
            if (b.oracleRelmseByAlpha.size() == 3)
            {
                m.boundOracleByAlpha[0] = b.oracleRelmseByAlpha[1];
                m.boundOracleByAlpha[1] = b.oracleRelmseByAlpha[0];
                m.boundOracleByAlpha[2] = b.oracleRelmseByAlpha[2];
            }
        }
        m.relmseNoisy = RelMSE(noisy, truth);
        m.relmseDenoised = RelMSE(denoised, truth);
        m.psnrNoisy = Psnr(noisy, truth);
        m.psnrDenoised = Psnr(denoised, truth);
        m.ssimNoisy = Ssim(noisy, truth);
        m.ssimDenoised = Ssim(denoised, truth);
        m.flipNoisy = Flip(noisy, truth);
        m.flipDenoised = Flip(denoised, truth);
        if (f > 0)
        {
            m.temporalInstabilityNoisy = TemporalInstability(noisyFrames.back(), noisy, truthFrames.back(), truth);
            m.temporalInstabilityDenoised = TemporalInstability(denoisedFrames.back(), denoised, truthFrames.back(), truth);
            // The truth's own frame-to-frame change (mean absolute difference).
            double sum = 0.0;
            for (size_t i = 0; i < truth.pixels.size(); i++)
                sum += std::fabs(double(truth.pixels[i]) - double(truthFrames.back().pixels[i]));
            m.temporalInstabilityTruth = truth.pixels.empty() ? 0.0 : sum / double(truth.pixels.size());
        }
        truthChange.push_back(m.temporalInstabilityTruth);
        // Only the previous frame is needed from here on.
        noisyFrames.assign(1, noisy);
        denoisedFrames.assign(1, denoised);
        truthFrames.assign(1, truth);
        if (o.keepImages && f + 1 == report.frames)
        {
            report.noisy = noisy;
            report.denoised = denoised;
            report.truth = truth;
        }
    }

    // Averages after the warm-up.
    uint32_t n = report.frames - report.warmup;
    FrameMetrics& mean = report.mean;
    for (uint32_t f = report.warmup; f < report.frames; f++)
    {
        const FrameMetrics& m = report.perFrame[f];
        mean.relmseNoisy += m.relmseNoisy / n;
        mean.relmseDenoised += m.relmseDenoised / n;
        mean.psnrNoisy += m.psnrNoisy / n;
        mean.psnrDenoised += m.psnrDenoised / n;
        mean.ssimNoisy += m.ssimNoisy / n;
        mean.ssimDenoised += m.ssimDenoised / n;
        mean.flipNoisy += m.flipNoisy / n;
        mean.flipDenoised += m.flipDenoised / n;
        mean.temporalInstabilityNoisy += m.temporalInstabilityNoisy / n;
        mean.temporalInstabilityDenoised += m.temporalInstabilityDenoised / n;
        mean.temporalInstabilityTruth += m.temporalInstabilityTruth / n;
        mean.gpuMs += m.gpuMs / n;
    }
    if (o.bounds)
    {
        // Means over the measured frames that have a value (the first frame has no previous one).
        double* fields[6] = {&mean.boundReprojectedTruth,  &mean.boundOracle,           &mean.boundOracleInstability,
                             &mean.boundOracleByAlpha[0], &mean.boundOracleByAlpha[1], &mean.boundOracleByAlpha[2]};
        for (int k = 0; k < 6; k++)
        {
            double sum = 0.0;
            uint32_t count = 0;
            for (uint32_t f = report.warmup; f < report.frames; f++)
            {
                const FrameMetrics& m = report.perFrame[f];
                const double values[6] = {m.boundReprojectedTruth,  m.boundOracle,           m.boundOracleInstability,
                                          m.boundOracleByAlpha[0], m.boundOracleByAlpha[1], m.boundOracleByAlpha[2]};
                const double v = values[k];
                if (v >= 0.0)
                {
                    sum += v;
                    count++;
                }
            }
            *fields[k] = count ? sum / count : -1.0;
        }
    }
    report.gpuMsPerFrame = mean.gpuMs;
    for (auto& p : passSum)
        report.passMs.push_back({p.first, timedFrames ? p.second / timedFrames : 0.0});
    report.renderNoisyMs /= report.frames;
    report.renderTruthMs /= report.frames;

    // Lag: per sudden change of the truth (a light switched, a jump), up to the next one.
    std::vector<double> errors;
    for (const FrameMetrics& m : report.perFrame)
        errors.push_back(m.relmseDenoised);
    SuddenChangeLag lag = LagAfterSuddenChanges(errors, truthChange, report.warmup);
    report.lagFrames = lag.frames;
    report.lagEventFrame = lag.eventFrame;

    report.validationMessages = vk.ValidationMessageCount();
    if (o.validation && report.validationMessages)
    {
        error = std::to_string(report.validationMessages) + " validation messages";
        return false;
    }
    return true;
}

std::string ReportToJson(const RunReport& r)
{
    auto metrics = [](const FrameMetrics& m, const RunReport& rep, bool withLag) {
        nlohmann::json j;
        j["relmse_noisy"] = m.relmseNoisy;
        j["relmse_denoised"] = m.relmseDenoised;
        j["psnr_noisy"] = m.psnrNoisy;
        j["psnr_denoised"] = m.psnrDenoised;
        j["ssim_noisy"] = m.ssimNoisy;
        j["ssim_denoised"] = m.ssimDenoised;
        j["flip_noisy"] = m.flipNoisy;
        j["flip_denoised"] = m.flipDenoised;
        j["temporal_instability_noisy"] = m.temporalInstabilityNoisy;
        j["temporal_instability_denoised"] = m.temporalInstabilityDenoised;
        j["temporal_instability_truth"] = m.temporalInstabilityTruth;
        if (m.boundOracle >= 0.0)
        {
            j["bounds"]["reprojected_truth_relmse"] = m.boundReprojectedTruth;
            j["bounds"]["oracle_relmse"] = m.boundOracle;
            j["bounds"]["oracle_temporal_instability"] = m.boundOracleInstability;
            for (int k = 0; k < 3; k++)
            {
                char alpha[16];
                std::snprintf(alpha, sizeof(alpha), "%.2f", double(kBoundAlphas[k]));
                j["bounds"]["oracle_relmse_by_alpha"][alpha] = m.boundOracleByAlpha[k];
            }
        }
        if (withLag)
        {
            j["lag_frames"] = rep.lagFrames;
            j["lag_event_frame"] = rep.lagEventFrame;
        }
        return j;
    };
    nlohmann::json j;
    j["scene"] = r.scene;
    j["method"] = r.method;
    j["width"] = r.width;
    j["height"] = r.height;
    j["frames"] = r.frames;
    j["warmup"] = r.warmup;
    j["truth_spp"] = r.truthSpp;
    j["device"] = r.device;
    j["gpu_ms_per_frame"] = r.gpuMsPerFrame;
    j["memory_bytes"] = r.memoryBytes;
    j["pipelines"] = r.pipelines;
    j["dispatches_per_frame"] = r.dispatchesPerFrame;
    j["render_noisy_ms_per_frame"] = r.renderNoisyMs;
    j["render_truth_ms_per_frame"] = r.renderTruthMs;
    nlohmann::json passes = nlohmann::json::object();
    for (const auto& p : r.passMs)
        passes[p.first] = p.second;
    j["gpu_ms_per_pass"] = passes;
    j["signals"][r.signal] = metrics(r.mean, r, true);
    nlohmann::json perFrame = nlohmann::json::array();
    for (size_t f = 0; f < r.perFrame.size(); f++)
    {
        nlohmann::json e = metrics(r.perFrame[f], r, false);
        e["frame"] = f;
        e["gpu_ms"] = r.perFrame[f].gpuMs;
        perFrame.push_back(e);
    }
    j["per_frame"] = perFrame;
    return j.dump(2);
}

} // namespace nrdlab
