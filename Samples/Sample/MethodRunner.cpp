#include "MethodRunner.h"

#include "Adapters/Adapters.h"

#include "Metrics.h"
#include "NRDIntegration.h"
#include "ReuseBounds.h"
#include "SceneLab.h"
#include "VulkanContext.h"

#include "CopyProbe.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>

namespace nrdlab
{

namespace
{

constexpr nrd::Identifier kId = 0;
constexpr nrd::Identifier kConfidenceId = 1; // RunOptions::confidence: CONFIDENCE in front of kId.

// The method's adapter and the signal it is run on.
struct MethodIo
{
    bool none = false; // "NONE": pass the noisy input through.
    nrd::Method method = nrd::Method::MAX_NUM;
    std::string signal; // Report name: shadow, diffuse, specular.
    std::unique_ptr<MethodAdapter> adapter;
    std::unique_ptr<MethodAdapter> confidence; // RunOptions::confidence: the CONFIDENCE adapter.
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
    if (o.confidence)
    {
        if (io.none || io.method == nrd::Method::CONFIDENCE || !io.adapter->EnableConfidenceInputs())
        {
            error = "--confidence: " + o.method + " does not read IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE";
            return false;
        }
        if (o.timing.frames)
        {
            error = "--confidence: timing runs the consumer alone (time CONFIDENCE on its own)";
            return false;
        }
        io.confidence = CreateMethodAdapter("CONFIDENCE");
    }
    return true;
}

// Reads the common settings and the method's own settings object; other methods' keys are
// accepted (one settings file may serve several methods), unknown keys are not.
bool ParseSettings(const std::string& text, nrd::CommonSettings& common, MethodAdapter& adapter, bool& motion3d,
                   bool& motionNone, std::string& error, std::vector<uint32_t>* restartFrames = nullptr,
                   std::array<double, 3>* worldOrigin = nullptr)
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
            // Frames on which every history restarts (accumulationMode RESTART): a perfect
            // invalidation at known lighting changes, the bound a confidence input can reach.
            if (restartFrames && c.contains("restartFrames"))
                *restartFrames = c["restartFrames"].get<std::vector<uint32_t>>();
            // Where the scene lies in the world the denoiser sees (the camera matrices and the
            // lights' positions move with it): a world far from the origin, as in a large level.
            if (worldOrigin && c.contains("worldOrigin"))
                *worldOrigin = c["worldOrigin"].get<std::array<double, 3>>();
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

// The context of runs that bring none: one per device index and validation setting, created on
// first use and kept until the process ends, so that a process running many methods (the quality
// tests) does not create and destroy an instance and a device per run (the NVIDIA H200's driver
// refused new instances with VK_ERROR_INCOMPATIBLE_DRIVER after about 28 of them in one process).
// Null if it cannot be created (tried again on the next run). The contexts are never destroyed: at
// exit the driver's own state may already be gone (the NVIDIA driver crashed in vkDestroyDevice
// from a static destructor), and the process's end releases them.
nrd::lab::VulkanContext* ProcessContext(int32_t device, bool validation)
{
    static std::mutex mutex;
    static auto* contexts = new std::map<std::pair<int32_t, bool>, std::unique_ptr<nrd::lab::VulkanContext>>();
    std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<nrd::lab::VulkanContext>& context = (*contexts)[{device, validation}];
    if (!context)
    {
        nrd::lab::VulkanContextDesc desc;
        desc.enableValidation = validation;
        desc.deviceIndex = device;
        desc.quiet = true;
        std::unique_ptr<nrd::lab::VulkanContext> created(new nrd::lab::VulkanContext());
        if (created->Create(desc) != VK_SUCCESS)
            return nullptr;
        context = std::move(created);
    }
    return context.get();
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

// The ray list of the classification stage just run, read back from the denoiser's pool buffers
// (BufferContent::RAY_LIST / RAY_COUNTERS of method 'id').
bool ReadRayList(nrd::lab::VulkanContext& vk, nrd::Integration& integration, nrd::Identifier id,
                 std::vector<uint32_t>& rays, std::string& error)
{
    const nrd::DenoiserDesc& desc = integration.GetDenoiserDesc();
    int32_t list = -1, counters = -1;
    for (uint32_t i = 0; i < desc.buffersNum; i++)
    {
        if (desc.buffers[i].identifier == id && desc.buffers[i].content == nrd::BufferContent::RAY_LIST)
            list = int32_t(i);
        if (desc.buffers[i].identifier == id && desc.buffers[i].content == nrd::BufferContent::RAY_COUNTERS)
            counters = int32_t(i);
    }
    if (list < 0 || counters < 0)
    {
        error = "the method has no ray list";
        return false;
    }
    // Last touched by the classification's shaders (the stage was submitted and waited for).
    const uint32_t written = nrd::rhi::ACCESS_SHADER_READ_WRITE | nrd::rhi::ACCESS_INDIRECT_ARGUMENTS;
    std::vector<uint32_t> words;
    if (vk.ReadbackBuffer(*integration.GetPoolBuffer(uint32_t(counters)), written, 16, words) != VK_SUCCESS ||
        uint64_t(words[3]) * sizeof(uint32_t) > desc.buffers[list].size ||
        (words[3] && vk.ReadbackBuffer(*integration.GetPoolBuffer(uint32_t(list)), written, words[3] * sizeof(uint32_t), rays) !=
                         VK_SUCCESS))
    {
        error = "reading the ray list back failed";
        return false;
    }
    if (words[3] == 0)
        rays.clear();
    return true;
}

// "driverName driverInfo" (Vulkan 1.2), else the raw driverVersion.
std::string DriverString(nrd::lab::VulkanContext& vk)
{
    const VkPhysicalDeviceProperties& properties = vk.GetProperties();
    if (properties.apiVersion >= VK_API_VERSION_1_2)
    {
        VkPhysicalDeviceDriverProperties driver = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
        VkPhysicalDeviceProperties2 properties2 = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        properties2.pNext = &driver;
        vkGetPhysicalDeviceProperties2(vk.GetPhysicalDevice(), &properties2);
        return std::string(driver.driverName) + " " + driver.driverInfo;
    }
    return "driverVersion " + std::to_string(properties.driverVersion);
}

// Device bandwidth from 'repeats' compute copies of 'bytes' bytes between two device buffers, then
// as many copies by the transfer path (vkCmdCopyBuffer), each timed with timestamps (one warm-up
// copy first). Where the compute copy is slow (lavapipe's storage buffers) the transfer copy shows
// what the memory allows.
bool MeasureCopy(nrd::rhi::Device& device, uint64_t bytes, uint32_t repeats, std::vector<double>& ms,
                 std::vector<double>& transferMs, std::string& error)
{
    using namespace nrd::rhi;
    bytes = bytes / 16 * 16;
    if (!bytes || !device.GetDesc().timestampsSupported)
        return true;
    Buffer* buffers[2] = {};
    Pipeline* pipeline = nullptr;
    DescriptorPool* pool = nullptr;
    QueryPool* queries = nullptr;
    CommandBuffer* cmd = nullptr;
    bool ok = false;
    do
    {
        BufferDesc bufferDesc = {};
        bufferDesc.size = bytes;
        bufferDesc.usage = BUFFER_USAGE_STORAGE | BUFFER_USAGE_COPY_SOURCE | BUFFER_USAGE_COPY_DESTINATION;
        bufferDesc.name = "copy probe";
        if (device.CreateBuffer(bufferDesc, buffers[0]) != Result::SUCCESS ||
            device.CreateBuffer(bufferDesc, buffers[1]) != Result::SUCCESS)
            break;
        DescriptorBindingDesc bindings[2] = {{0, DescriptorType::BUFFER}, {1, DescriptorType::STORAGE_BUFFER}};
        DescriptorSetDesc set = {bindings, 2};
        ComputePipelineDesc pipelineDesc = {};
        pipelineDesc.spirv = g_CopyProbe;
        pipelineDesc.spirvSize = sizeof(g_CopyProbe);
        pipelineDesc.sets = &set;
        pipelineDesc.setsNum = 1;
        pipelineDesc.pushConstantsSize = 4;
        pipelineDesc.name = "copy probe";
        if (device.CreateComputePipeline(pipelineDesc, pipeline) != Result::SUCCESS)
            break;
        DescriptorPoolDesc poolDesc = {};
        poolDesc.setsMaxNum = 1;
        poolDesc.descriptorsMaxNum[(size_t)DescriptorType::BUFFER] = 1;
        poolDesc.descriptorsMaxNum[(size_t)DescriptorType::STORAGE_BUFFER] = 1;
        DescriptorSet* descriptors = nullptr;
        if (device.CreateDescriptorPool(poolDesc, pool) != Result::SUCCESS ||
            device.AllocateDescriptorSet(*pool, *pipeline, 0, descriptors) != Result::SUCCESS)
            break;
        DescriptorWrite writes[2] = {};
        writes[0].binding = 0;
        writes[0].type = DescriptorType::BUFFER;
        writes[0].buffer = buffers[0];
        writes[1].binding = 1;
        writes[1].type = DescriptorType::STORAGE_BUFFER;
        writes[1].buffer = buffers[1];
        device.UpdateDescriptorSet(*descriptors, writes, 2);
        const uint32_t queriesNum = 4 * (repeats + 1);
        if (device.CreateQueryPool(queriesNum, queries) != Result::SUCCESS ||
            device.CreateCommandBuffer(cmd) != Result::SUCCESS || device.BeginCommandBuffer(*cmd) != Result::SUCCESS)
            break;

        device.CmdFillBuffer(*cmd, *buffers[0], 0, 0, 0x3F800000u);
        // The fill before the first copy's reads; each copy's writes before the next one's (WAW).
        GlobalBarrier filled = {ACCESS_COPY_DESTINATION, ACCESS_SHADER_READ | ACCESS_SHADER_READ_WRITE};
        BarrierDesc barrier = {&filled, 1};
        device.CmdBarrier(*cmd, barrier);
        device.CmdResetQueries(*cmd, *queries, 0, queriesNum);
        const uint32_t count = uint32_t(std::min<uint64_t>(bytes / 16, 0xFFFFFFFFu));
        const uint32_t groups = std::min<uint32_t>((count + 255) / 256, std::min(65535u, device.GetDesc().dispatchMaxNum[0]));
        device.CmdBindPipeline(*cmd, *pipeline);
        device.CmdBindDescriptorSet(*cmd, *pipeline, 0, *descriptors);
        device.CmdPushConstants(*cmd, *pipeline, &count, 4);
        GlobalBarrier between = {ACCESS_SHADER_READ_WRITE, ACCESS_SHADER_READ_WRITE};
        BarrierDesc betweenDesc = {&between, 1};
        for (uint32_t r = 0; r <= repeats; r++)
        {
            device.CmdWriteTimestamp(*cmd, *queries, 2 * r);
            device.CmdDispatch(*cmd, groups, 1, 1);
            device.CmdWriteTimestamp(*cmd, *queries, 2 * r + 1);
            device.CmdBarrier(*cmd, betweenDesc);
        }
        GlobalBarrier toTransfer = {ACCESS_SHADER_READ_WRITE, ACCESS_COPY_SOURCE | ACCESS_COPY_DESTINATION};
        BarrierDesc toTransferDesc = {&toTransfer, 1};
        device.CmdBarrier(*cmd, toTransferDesc);
        GlobalBarrier transfers = {ACCESS_COPY_DESTINATION, ACCESS_COPY_DESTINATION};
        BarrierDesc transfersDesc = {&transfers, 1};
        const uint32_t base = 2 * (repeats + 1);
        for (uint32_t r = 0; r <= repeats; r++)
        {
            device.CmdWriteTimestamp(*cmd, *queries, base + 2 * r);
            device.CmdCopyBuffer(*cmd, *buffers[1], 0, *buffers[0], 0, bytes);
            device.CmdWriteTimestamp(*cmd, *queries, base + 2 * r + 1);
            device.CmdBarrier(*cmd, transfersDesc);
        }
        if (device.EndCommandBuffer(*cmd) != Result::SUCCESS || device.SubmitAndWait(*cmd) != Result::SUCCESS)
            break;
        std::vector<uint64_t> ticks(queriesNum);
        if (device.GetTimestamps(*queries, 0, queriesNum, ticks.data()) != Result::SUCCESS)
            break;
        const double msPerTick = device.GetDesc().timestampPeriodNs * 1e-6;
        for (uint32_t r = 1; r <= repeats; r++)
        {
            ms.push_back(double(ticks[2 * r + 1] - ticks[2 * r]) * msPerTick);
            transferMs.push_back(double(ticks[base + 2 * r + 1] - ticks[base + 2 * r]) * msPerTick);
        }
        ok = true;
    } while (false);
    device.DestroyCommandBuffer(cmd);
    device.DestroyQueryPool(queries);
    device.DestroyDescriptorPool(pool);
    device.DestroyPipeline(pipeline);
    device.DestroyBuffer(buffers[0]);
    device.DestroyBuffer(buffers[1]);
    if (!ok)
        error = "bandwidth probe failed (" + std::to_string(bytes >> 20) + " MiB buffers)";
    return ok;
}

// RunOptions::timing: more frames on the inputs bound in 'pool', back to back; 'common.frameIndex'
// advances by one per frame.
bool TimeFixedInputs(const TimingOptions& t, nrd::lab::VulkanContext& vk, nrd::Integration& integration,
                     nrd::CommonSettings& common, nrd::UserPool& pool, uint32_t width, uint32_t height,
                     const std::function<uint32_t(nrd::ResourceType)>& userBytesPerPixel, TimingReport& out,
                     std::string& error)
{
    out.frames = t.frames;
    out.warmupFrames = 0;
    out.framesPerSubmission = std::max(1u, t.framesPerSubmission);
    out.idleMs = t.idleMs;
    out.copyBytes = t.copyBytes;
    std::map<std::string, size_t> passIndex;

    // Records 'n' frames into one command buffer and submits it, waiting; keeps their timings if 'timed'.
    auto runBatch = [&](uint32_t n, bool timed) {
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        if (vk.BeginCommands(cmd) != VK_SUCCESS)
        {
            error = "timing: no command buffer";
            return false;
        }
        for (uint32_t k = 0; k < n; k++)
        {
            common.frameIndex++;
            if (integration.SetCommonSettings(common) != nrd::Result::SUCCESS ||
                integration.Denoise(cmd, &kId, 1, pool) != VK_SUCCESS)
            {
                error = "timing: denoising failed";
                vk.SubmitAndWait(cmd);
                return false;
            }
        }
        if (vk.SubmitAndWait(cmd) != VK_SUCCESS)
        {
            error = "timing: submission failed";
            return false;
        }
        for (uint32_t k = 0; k < n && timed; k++)
        {
            double frameMs = 0.0;
            std::vector<nrd::DispatchTiming> timings = integration.GetTimings(n - 1 - k, &frameMs);
            if (timings.empty())
                continue; // No timestamps on this queue.
            out.frameMs.push_back(frameMs);
            std::map<size_t, double> sums;
            for (const nrd::DispatchTiming& timing : timings)
            {
                auto it = passIndex.find(timing.name);
                if (it == passIndex.end())
                {
                    it = passIndex.emplace(timing.name, out.passes.size()).first;
                    out.passes.push_back({timing.name, {}, {}});
                }
                sums[it->second] += timing.milliseconds;
            }
            for (auto& sum : sums)
                out.passes[sum.first].ms.push_back(sum.second);
        }
        if (t.idleMs)
            std::this_thread::sleep_for(std::chrono::milliseconds(t.idleMs));
        return true;
    };

    // Warm-up: at least 'warmupFrames' frames and 'warmupMs' of host time.
    auto start = std::chrono::steady_clock::now();
    auto elapsedMs = [&] {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    };
    for (uint32_t done = 0; done < t.warmupFrames || elapsedMs() < double(t.warmupMs);)
    {
        uint32_t n = done < t.warmupFrames ? std::min(out.framesPerSubmission, t.warmupFrames - done) : out.framesPerSubmission;
        if (!runBatch(n, false))
            return false;
        done += n;
        out.warmupFrames = std::max(out.warmupFrames, done);
    }
    if (t.copyBytes && !MeasureCopy(vk.GetDevice(), t.copyBytes, 8, out.copyMs, out.transferCopyMs, error))
        return false;
    start = std::chrono::steady_clock::now();
    for (uint32_t done = 0; done < t.frames;)
    {
        uint32_t n = std::min(out.framesPerSubmission, t.frames - done);
        if (!runBatch(n, true))
            return false;
        done += n;
    }
    out.wallSeconds = elapsedMs() * 1e-3;

    // nrd-sample's pattern: one frame per submission, waited for, right away and after idle time.
    if (t.isolatedIdleMs)
    {
        TimingReport alone;
        TimingOptions one = {};
        one.frames = t.isolatedFrames;
        one.warmupFrames = 1;
        one.framesPerSubmission = 1;
        for (uint32_t idle : {0u, t.isolatedIdleMs})
        {
            one.idleMs = idle;
            alone = {};
            if (!TimeFixedInputs(one, vk, integration, common, pool, width, height, userBytesPerPixel, alone, error))
                return false;
            (idle ? out.isolatedMs : out.aloneMs) = alone.frameMs;
        }
    }

    const nrd::DenoiserDesc& desc = integration.GetDenoiserDesc();
    for (const nrd::RecordedDispatch& dispatch : integration.GetLastDispatches())
    {
        auto it = passIndex.find(dispatch.name);
        if (it == passIndex.end())
            continue;
        DispatchBytes bytes = CountDispatchBytes(dispatch.resources.data(), uint32_t(dispatch.resources.size()), desc,
                                                 width, height, userBytesPerPixel);
        out.passes[it->second].bytes.read += bytes.read;
        out.passes[it->second].bytes.written += bytes.written;
    }
    return true;
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
    for (const Object& object : scene.objects)
    {
        if (!object.mesh || std::any_of(report.meshes.begin(), report.meshes.end(),
                                        [&](const RunReport::MeshInfo& m) { return m.file == object.mesh->file; }))
            continue;
        const MeshData& m = *object.mesh;
        report.meshes.push_back({m.file, uint32_t(m.triangles.size()), uint32_t(m.nodes.size()), m.depth, m.buildMs});
    }

    nrd::CommonSettings common;
    bool motion3d = true, motionNone = false;
    std::vector<uint32_t> restartFrames;
    std::array<double, 3> worldOrigin = {0.0, 0.0, 0.0};
    if (!ParseSettings(o.settingsJson, common, *io.adapter, motion3d, motionNone, error, &restartFrames, &worldOrigin))
        return false;
    if (io.confidence)
    {
        nrd::CommonSettings ignoredCommon;
        bool ignored3d = motion3d, ignoredNone = motionNone;
        if (!ParseSettings(o.settingsJson, ignoredCommon, *io.confidence, ignored3d, ignoredNone, error))
            return false;
    }

    nrd::lab::VulkanContext* context = o.context ? o.context : ProcessContext(o.device, o.validation);
    if (!context)
    {
        error = "could not create a Vulkan device (index " + std::to_string(o.device) + ")";
        return false;
    }
    nrd::lab::VulkanContext& vk = *context;
    if (!vk.GetVkDevice())
    {
        error = "the given Vulkan context is not created";
        return false;
    }
    // A shared context counts the messages of earlier runs too.
    const uint32_t validationMessagesBefore = vk.ValidationMessageCount();

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
    report.confidence = o.confidence;
    report.signal = io.signal;
    report.device = vk.GetProperties().deviceName;
    report.driver = DriverString(vk);
    report.width = o.width;
    report.height = o.height;
    report.frames = o.frames ? o.frames : scene.frameNum;
    report.warmup = std::min(o.warmup, report.frames > 0 ? report.frames - 1 : 0u);
    report.truthSpp = o.timing.skipQuality ? 0 : o.truthSpp;

    // The denoiser and its textures.
    nrd::Integration integration;
    std::unique_ptr<Textures> textures(new Textures());
    textures->vk = &vk;
    if (!io.none)
    {
        nrd::MethodDesc methods[2] = {{kId, io.method}, {kConfidenceId, nrd::Method::CONFIDENCE}};
        nrd::DenoiserCreationDesc desc;
        desc.methods = methods;
        desc.methodsNum = io.confidence ? 2 : 1;
        desc.renderWidth = uint16_t(o.width);
        desc.renderHeight = uint16_t(o.height);
        nrd::IntegrationCreationDesc integrationDesc = vk.GetIntegrationCreationDesc();
        // Timed frames recorded back to back each hold a slot (descriptors, constants, queries).
        if (o.timing.frames)
            integrationDesc.framesInFlight = std::max(integrationDesc.framesInFlight, o.timing.framesPerSubmission);
        if (integration.Create(integrationDesc, desc) != VK_SUCCESS)
        {
            error = "could not create the denoiser";
            return false;
        }
        nrd::Result r = io.adapter->ApplySettings(integration, kId);
        if (r == nrd::Result::SUCCESS && io.confidence)
            r = io.confidence->ApplySettings(integration, kConfidenceId);
        if (r != nrd::Result::SUCCESS)
        {
            error = std::string("method settings rejected: ") + nrd::GetResultString(r);
            return false;
        }
        nrd::MemoryReport memory = integration.GetMemoryReport();
        report.memoryBytes = memory.totalBytes;
        report.permanentPoolBytes = memory.permanentPoolBytes;
        report.transientPoolBytes = memory.transientPoolBytes;
        report.bufferPoolBytes = memory.bufferPoolBytes;
        report.constantRingBytes = memory.constantRingBytes;
        report.pipelines = integration.GetDenoiserDesc().pipelinesNum;
    }

    std::vector<Image> denoisedFrames, truthFrames, noisyFrames;
    // The reported oracle (blend 0.25, kBoundAlphas[1]) first.
    ReuseBounds bounds(std::vector<float>{kBoundAlphas[1], kBoundAlphas[0], kBoundAlphas[2]});
    std::vector<double> truthChange;
    std::map<std::string, double> passSum;
    uint32_t timedFrames = 0, renderTimedFrames = 0;

    // Timing only: the last frame's inputs suffice.
    for (uint32_t f = o.timing.skipQuality ? report.frames - 1 : 0; f < report.frames; f++)
    {
        if (o.progress)
            o.progress(f, report.frames);
        RenderParams params;
        params.width = o.width;
        params.height = o.height;
        params.frameIndex = f;
        params.truthSpp = report.truthSpp;
        params.seed = o.seed;
        params.signals = io.adapter->GetLabSignals(io.signal) | (io.confidence ? SignalMask(SIGNAL_GRADIENTS) : 0u);
        FrameData frame;
        if (!lab.Render(scene, params, frame, error))
            return false;
        if (f >= report.warmup || o.timing.skipQuality)
        {
            report.renderNoisyMs += frame.noisyMs;
            report.renderTruthMs += frame.truthMs;
            renderTimedFrames++;
        }

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
            if (worldOrigin[0] != 0.0 || worldOrigin[1] != 0.0 || worldOrigin[2] != 0.0)
            {
                // X' = X + origin: worldToView' = worldToView * translate(-origin), rounded to float
                // as an engine's matrices are.
                for (float* m : {common.worldToViewMatrix, common.worldToViewMatrixPrev})
                    for (int row = 0; row < 3; row++)
                        m[12 + row] = float(double(m[12 + row]) - double(m[row]) * worldOrigin[0] - double(m[4 + row]) * worldOrigin[1] -
                                            double(m[8 + row]) * worldOrigin[2]);
                for (int a = 0; a < 3; a++)
                    frame.light.position[a] = float(double(frame.light.position[a]) + worldOrigin[a]);
            }
            common.frameIndex = f;
            common.accumulationMode = std::find(restartFrames.begin(), restartFrames.end(), f) != restartFrames.end()
                                          ? nrd::AccumulationMode::RESTART
                                          : nrd::AccumulationMode::CONTINUE;
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
            if (io.confidence)
                io.confidence->GetInputs(frame, io.signal, noisy, inputs);

            nrd::UserPool pool;
            for (const AdapterTexture& input : inputs)
            {
                const uint32_t w = input.width ? input.width : o.width, h = input.height ? input.height : o.height;
                auto& tex = textures->map[input.type];
                if (!tex.texture &&
                    vk.CreateTexture(input.format, w, h, nrd::GetResourceTypeString(input.type), tex) != VK_SUCCESS)
                {
                    error = "texture creation failed";
                    return false;
                }
                const size_t channels = nrd::rhi::GetFormatInfo(input.format).channelNum;
                if (input.pixels.size() != size_t(w) * h * channels ||
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

            // A method that denoises several signals (REBLUR_DIFFUSE_SPECULAR) writes every one of
            // its outputs: bind the ones that are not compared too (sky pixels keep zeros there).
            for (const std::string& other : io.adapter->GetSignals())
            {
                const nrd::ResourceType otherType = io.adapter->GetOutput(other);
                if (otherType == outType)
                    continue;
                auto& otherTex = textures->map[otherType];
                if (!otherTex.texture)
                {
                    const nrd::rhi::Format otherFormat = io.adapter->GetOutputFormat(other);
                    const size_t floats = size_t(o.width) * o.height * nrd::rhi::GetFormatInfo(otherFormat).channelNum;
                    if (vk.CreateTexture(otherFormat, o.width, o.height, "output", otherTex) != VK_SUCCESS)
                    {
                        error = "texture creation failed";
                        return false;
                    }
                    vk.UploadTexture(otherTex, std::vector<float>(floats, 0.0f).data(), nrd::rhi::Layout::GENERAL);
                }
                pool[otherType] = otherTex.AsUserTexture();
            }

            // CONFIDENCE's outputs, bound as the consumer's confidence inputs (1 where never written: sky).
            const nrd::ResourceType confidenceTypes[2][2] = {
                {nrd::ResourceType::OUT_DIFF_CONFIDENCE, nrd::ResourceType::IN_DIFF_CONFIDENCE},
                {nrd::ResourceType::OUT_SPEC_CONFIDENCE, nrd::ResourceType::IN_SPEC_CONFIDENCE}};
            if (io.confidence)
                for (const auto& types : confidenceTypes)
                {
                    auto& confTex = textures->map[types[0]];
                    if (!confTex.texture)
                    {
                        if (vk.CreateTexture(F::R16_SFLOAT, o.width, o.height, nrd::GetResourceTypeString(types[0]), confTex) != VK_SUCCESS)
                        {
                            error = "texture creation failed";
                            return false;
                        }
                        vk.UploadTexture(confTex, std::vector<float>(size_t(o.width) * o.height, 1.0f).data(), nrd::rhi::Layout::GENERAL);
                    }
                    pool[types[0]] = confTex.AsUserTexture();
                }

            VkCommandBuffer cmd;
            const bool isRayList = io.adapter->IsRayListTraced();
            if (isRayList)
            {
                // Classification, then the lab traces exactly the listed rays into the input.
                std::vector<uint32_t> rays;
                Image traced;
                if (vk.BeginCommands(cmd) != VK_SUCCESS ||
                    integration.Denoise(cmd, &kId, 1, pool, nrd::DispatchStage::CLASSIFICATION) != VK_SUCCESS ||
                    vk.SubmitAndWait(cmd) != VK_SUCCESS || !ReadRayList(vk, integration, kId, rays, error) ||
                    !lab.TraceSpecularRays(scene, params, rays, traced, error))
                {
                    error = "ray list tracing failed: " + error;
                    return false;
                }
                for (auto& t : textures->map)
                    t.second.FromUserTexture(pool[t.first]);
                auto& in = textures->map[nrd::ResourceType::IN_SPEC_RADIANCE_HITDIST];
                if (vk.UploadTexture(in, ExpandChannels(traced, 4).data()) != VK_SUCCESS)
                {
                    error = "upload failed: traced rays";
                    return false;
                }
                for (auto& t : textures->map)
                    pool[t.first] = t.second.AsUserTexture();
                if (f >= report.warmup)
                {
                    size_t fullRate = 0;
                    for (float z : frame.viewZ.pixels)
                        fullRate += z < kSkyViewZ ? 1 : 0;
                    report.raysTraced += double(rays.size());
                    report.raysFullRate += double(fullRate);
                }
            }
            bool recorded = vk.BeginCommands(cmd) == VK_SUCCESS;
            if (recorded && io.confidence)
            {
                recorded = integration.Denoise(cmd, &kConfidenceId, 1, pool) == VK_SUCCESS;
                for (const auto& types : confidenceTypes)
                    pool[types[1]] = pool[types[0]];
            }
            recorded = recorded && integration.Denoise(cmd, &kId, 1, pool,
                                                        isRayList ? nrd::DispatchStage::DENOISING : nrd::DispatchStage::ALL) ==
                                        VK_SUCCESS;
            if (io.confidence)
                for (const auto& types : confidenceTypes)
                    pool[types[0]].layout = pool[types[1]].layout; // The consumer read them last.
            if (!recorded || vk.SubmitAndWait(cmd) != VK_SUCCESS)
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
            if (io.confidence)
            {
                double confidenceTotal = 0.0;
                std::vector<nrd::DispatchTiming> confidenceTimings = integration.GetTimings(1, &confidenceTotal);
                timings.insert(timings.begin(), confidenceTimings.begin(), confidenceTimings.end());
                total += confidenceTotal;
            }
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
            if (o.timing.frames && f + 1 == report.frames)
            {
                // Application textures at the formats they were created with.
                auto userBytesPerPixel = [&](nrd::ResourceType type) {
                    auto it = textures->map.find(type);
                    return it == textures->map.end() ? 0u : nrd::rhi::GetFormatBytesPerPixel(it->second.format);
                };
                // The readback left the output in another layout than the last Denoise.
                for (auto& t : textures->map)
                    pool[t.first] = t.second.AsUserTexture();
                std::vector<std::string> variants = o.timing.settingsVariants;
                if (variants.empty())
                    variants.push_back(o.settingsJson);
                report.timing.resize(variants.size());
                for (size_t v = 0; v < variants.size(); v++)
                {
                    if (!variants[v].empty() && variants[v].find("\"common\"") != std::string::npos)
                    {
                        error = "timing: a settings variant cannot change \"common\" (the inputs depend on it)";
                        return false;
                    }
                    // The variant's method settings over the defaults, through a fresh adapter;
                    // the per-frame ones (the light) stay this frame's.
                    std::unique_ptr<MethodAdapter> adapter = CreateMethodAdapter(o.method);
                    nrd::CommonSettings ignoredCommon;
                    bool ignored3d = motion3d, ignoredNone = motionNone;
                    if (!adapter || !ParseSettings(variants[v], ignoredCommon, *adapter, ignored3d, ignoredNone, error))
                        return false;
                    if (adapter->ApplySettings(integration, kId) != nrd::Result::SUCCESS)
                    {
                        error = "timing: settings variant " + std::to_string(v) + " rejected";
                        return false;
                    }
                    adapter->ApplyFrameSettings(integration, kId, frame);
                    if (o.timing.progress)
                        o.timing.progress(uint32_t(v), uint32_t(variants.size()));
                    TimingOptions t = o.timing;
                    if (v > 0)
                    {
                        t.isolatedIdleMs = 0; // nrd-sample's pattern for the first variant only.
                        // The clocks settled during the first variant, unless its isolated frames
                        // idled the GPU since: the second variant then warms up as long again
                        // (without it, on the H100 it ran at idle clocks, 2-3x slower).
                        t.warmupMs = v == 1 && o.timing.isolatedIdleMs ? o.timing.warmupMs : 0;
                        t.copyBytes = 0;      // One bandwidth probe per run.
                    }
                    if (!TimeFixedInputs(t, vk, integration, common, pool, o.width, o.height, userBytesPerPixel,
                                         report.timing[v], error))
                        return false;
                }
                for (auto& t : textures->map)
                    t.second.FromUserTexture(pool[t.first]);
            }
        }
        if (o.timing.skipQuality)
            continue;
        if (io.none)
            report.perFrame.push_back(FrameMetrics{});

        FrameMetrics& m = report.perFrame.back();
        if (o.bounds)
        {
            // Object index and depth: a disocclusion test that holds on meshes hiding parts of
            // themselves (an object index alone is exact only on convex objects).
            const Image surfaceIds = SurfaceIds(frame);
            ReuseBoundsFrame b = bounds.Add(noisy, truth, frame.motion2d, surfaceIds.isValid() ? &surfaceIds : nullptr);
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
        m.relmseLowpassDenoised = RelMSE(BlockMeans(denoised, kLowpassBlock), BlockMeans(truth, kLowpassBlock));
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

    if (o.timing.skipQuality)
    {
        report.perFrame.clear();
        report.validationMessages = vk.ValidationMessageCount() - validationMessagesBefore;
        return !(o.validation && report.validationMessages);
    }

    // Averages after the warm-up.
    uint32_t n = report.frames - report.warmup;
    FrameMetrics& mean = report.mean;
    for (uint32_t f = report.warmup; f < report.frames; f++)
    {
        const FrameMetrics& m = report.perFrame[f];
        mean.relmseNoisy += m.relmseNoisy / n;
        mean.relmseDenoised += m.relmseDenoised / n;
        mean.relmseLowpassDenoised += m.relmseLowpassDenoised / n;
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
    report.renderNoisyMs /= std::max(renderTimedFrames, 1u);
    report.renderTruthMs /= std::max(renderTimedFrames, 1u);
    if (report.frames > report.warmup && report.raysFullRate > 0.0)
    {
        report.rayRatio = report.raysTraced / report.raysFullRate;
        report.raysTraced /= double(report.frames - report.warmup);
        report.raysFullRate /= double(report.frames - report.warmup);
    }

    // Lag: per sudden change of the truth (a light switched, a jump), up to the next one.
    std::vector<double> errors;
    for (const FrameMetrics& m : report.perFrame)
        errors.push_back(m.relmseDenoised);
    SuddenChangeLag lag = LagAfterSuddenChanges(errors, truthChange, report.warmup);
    report.lagFrames = lag.frames;
    report.lagEventFrame = lag.eventFrame;
    errors.clear();
    for (const FrameMetrics& m : report.perFrame)
        errors.push_back(m.relmseLowpassDenoised);
    lag = LagAfterSuddenChanges(errors, truthChange, report.warmup);
    report.lagLowpassFrames = lag.frames;
    report.lagLowpassEventFrame = lag.eventFrame;

    report.validationMessages = vk.ValidationMessageCount() - validationMessagesBefore;
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
        j["relmse_lowpass_denoised"] = m.relmseLowpassDenoised;
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
            j["lag_lowpass_frames"] = rep.lagLowpassFrames;
            j["lag_lowpass_event_frame"] = rep.lagLowpassEventFrame;
        }
        return j;
    };
    nlohmann::json j;
    j["scene"] = r.scene;
    j["method"] = r.method;
    j["confidence"] = r.confidence;
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
    if (r.raysFullRate > 0.0)
    {
        j["rays_traced_per_frame"] = r.raysTraced;
        j["rays_full_rate_per_frame"] = r.raysFullRate;
        j["ray_ratio"] = r.rayRatio;
    }
    j["meshes"] = nlohmann::json::array();
    for (const RunReport::MeshInfo& m : r.meshes)
        j["meshes"].push_back({{"file", m.file},
                               {"triangles", m.triangles},
                               {"bvh_nodes", m.bvhNodes},
                               {"bvh_depth", m.bvhDepth},
                               {"bvh_build_ms", m.bvhBuildMs}});
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
