#include "MethodRunner.h"

#include "Adapters/Adapters.h"

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

// The method's adapter and the signal it is run on.
struct MethodIo
{
    bool none = false; // "NONE": pass the noisy input through.
    nrd::Method method = nrd::Method::MAX_NUM;
    std::string signal; // Report name: shadow, diffuse, specular.
    std::unique_ptr<MethodAdapter> adapter;
};

bool ResolveMethod(const RunOptions& o, MethodIo& io, std::string& error)
{
    io.none = o.method == "NONE";
    if (!io.none && !nrd::GetMethodFromString(o.method.c_str(), io.method))
        io.method = nrd::Method::MAX_NUM;
    if (io.none || io.method != nrd::Method::MAX_NUM)
        io.adapter = CreateMethodAdapter(o.method);
    if (!io.adapter && io.method != nrd::Method::MAX_NUM)
    {
        error = "method " + o.method + " has no adapter in the sample (Samples/Sample/MethodAdapter.h)";
        return false;
    }
    if (!io.adapter)
    {
        error = "unknown method '" + o.method + "' (";
        const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
        for (uint32_t i = 0; i < lib.supportedMethodsNum; i++)
            error += std::string(nrd::GetMethodString(lib.supportedMethods[i])) + ", ";
        error += "NONE)";
        return false;
    }
    const std::vector<std::string> signals = io.adapter->GetSignals();
    io.signal = o.signal.empty() ? signals.front() : o.signal;
    if (std::find(signals.begin(), signals.end(), io.signal) == signals.end())
    {
        error = "signal '" + io.signal + "' is not available for method " + o.method + " (";
        for (size_t i = 0; i < signals.size(); i++)
            error += (i ? ", " : "") + signals[i];
        error += ")";
        return false;
    }
    return true;
}

// Reads the common settings and the method's own settings object; other methods' keys are
// accepted (one settings file may serve several methods), unknown keys are not.
bool ParseSettings(const std::string& text, nrd::CommonSettings& common, MethodAdapter& adapter, bool& motion3d,
                   bool& motionNone, std::string& error)
{
    if (text.empty())
        return true;
    try
    {
        nlohmann::json j = nlohmann::json::parse(text);
        std::vector<std::string> keys = GetAdapterSettingsKeys();
        keys.insert(keys.begin(), "common");
        for (auto it = j.begin(); it != j.end(); ++it)
            if (std::find(keys.begin(), keys.end(), it.key()) == keys.end())
            {
                error = "settings: unknown key '" + it.key() + "' (";
                for (size_t i = 0; i < keys.size(); i++)
                    error += (i ? ", " : "") + keys[i];
                error += ")";
                return false;
            }
        if (j.contains("common"))
        {
            const auto& c = j["common"];
            ReadSetting(c, "denoisingRange", common.denoisingRange);
            ReadSetting(c, "disocclusionThreshold", common.disocclusionThreshold);
            std::string motion = motion3d ? "3d" : "2d";
            ReadSetting(c, "motion", motion);
            if (motion != "2d" && motion != "3d" && motion != "none")
            {
                error = "settings: common.motion must be 2d, 3d or none";
                return false;
            }
            motion3d = motion == "3d";
            motionNone = motion == "none";
        }
        const char* key = adapter.GetSettingsKey();
        if (key && j.contains(key) && !adapter.ParseSettings(j[key], error))
        {
            error = std::string("settings: ") + key + ": " + error;
            return false;
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
    bool motion3d = true, motionNone = false;
    if (!ParseSettings(o.settingsJson, common, *io.adapter, motion3d, motionNone, error))
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
        nrd::Result r = io.adapter->ApplySettings(integration, kId);
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
        params.signals = io.adapter->GetLabSignals(io.signal);
        FrameData frame;
        if (!lab.Render(scene, params, frame, error))
            return false;
        report.renderNoisyMs += frame.noisyMs;
        report.renderTruthMs += frame.truthMs;

        Image noisy, truth, denoised;
        io.adapter->GetSignalImages(frame, io.signal, noisy, truth);

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
            io.adapter->ApplyFrameSettings(integration, kId, frame);
            if (integration.SetCommonSettings(common) != nrd::Result::SUCCESS)
            {
                error = "common settings rejected";
                return false;
            }

            // Application textures: the G-buffer, the method's signal inputs, the output.
            using F = nrd::rhi::Format;
            std::vector<AdapterTexture> inputs = {
                {nrd::ResourceType::IN_VIEWZ, F::R32_SFLOAT, ExpandChannels(frame.viewZ, 1)},
                {nrd::ResourceType::IN_NORMAL_ROUGHNESS, F::RGBA16_SFLOAT, ExpandChannels(frame.normalRoughness, 4)},
                {nrd::ResourceType::IN_MV, F::RGBA16_SFLOAT, ExpandChannels(motion3d ? frame.motion3d : frame.motion2d, 4)},
            };
            io.adapter->GetInputs(frame, io.signal, noisy, inputs);

            nrd::UserPool pool;
            for (const AdapterTexture& input : inputs)
            {
                auto& tex = textures->map[input.type];
                if (!tex.texture &&
                    vk.CreateTexture(input.format, o.width, o.height, nrd::GetResourceTypeString(input.type), tex) != VK_SUCCESS)
                {
                    error = "texture creation failed";
                    return false;
                }
                const size_t channels = nrd::rhi::GetFormatInfo(input.format).channelNum;
                if (input.pixels.size() != size_t(o.width) * o.height * channels ||
                    vk.UploadTexture(tex, input.pixels.data()) != VK_SUCCESS)
                {
                    error = std::string("upload failed: ") + nrd::GetResourceTypeString(input.type);
                    return false;
                }
                pool[input.type] = tex.AsUserTexture();
            }
            const nrd::ResourceType outType = io.adapter->GetOutput(io.signal);
            const nrd::rhi::Format outFormat = io.adapter->GetOutputFormat(io.signal);
            auto& outTex = textures->map[outType];
            if (!outTex.texture && vk.CreateTexture(outFormat, o.width, o.height, "output", outTex) != VK_SUCCESS)
            {
                error = "texture creation failed";
                return false;
            }
            std::vector<float> init = io.adapter->GetOutputInitialization(io.signal, noisy);
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
            Image full(o.width, o.height, nrd::rhi::GetFormatInfo(outFormat).channelNum);
            full.pixels = out;
            denoised = io.adapter->DecodeOutput(io.signal, full);

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
        m.meanNoisy = MeanValue(noisy);
        m.meanDenoised = MeanValue(denoised);
        m.meanTruth = MeanValue(truth);
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
        mean.meanNoisy += m.meanNoisy / n;
        mean.meanDenoised += m.meanDenoised / n;
        mean.meanTruth += m.meanTruth / n;
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
        j["mean_noisy"] = m.meanNoisy;
        j["mean_denoised"] = m.meanDenoised;
        j["mean_truth"] = m.meanTruth;
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
