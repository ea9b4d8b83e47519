// Runs one denoising method on a scene-lab scene through the Vulkan integration layer and measures
// it against the scene's ground truth. Shared by nrd-sample, the benchmark and the quality tests.
#pragma once

#include "ByteModel.h"
#include "Image.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace nrd
{
namespace lab
{
class VulkanContext;
}
} // namespace nrd

namespace nrdlab
{

// Timing on fixed inputs (the benchmark): once the last frame is rendered and denoised, the
// denoiser runs 'warmupFrames' + 'frames' more frames on that frame's inputs (only frameIndex
// advances), 'framesPerSubmission' of them recorded back to back into one command buffer; the GPU
// timestamps of the last 'frames' go to RunReport::timing. The scene lab is not timed.
struct TimingOptions
{
    uint32_t frames = 0;               // Timed frames; 0: no timing.
    uint32_t warmupFrames = 32;        // Untimed frames first (clocks settle, caches and history fill),
    uint32_t warmupMs = 0;             // for at least this long (first settings variant only, and the
                                       // second after the first's isolated frames idled the GPU).
    uint32_t framesPerSubmission = 16; // 1: one frame per submission, waited for (nrd-sample's way).
    uint32_t idleMs = 0;               // Host pause after each submission (nrd-sample spends it in the
                                       // scene lab and the metrics).
    bool skipQuality = false;          // Render only the last frame, without truth; no metrics.
    uint64_t copyBytes = 0;            // Bandwidth probe: copies from one buffer of this many bytes into
                                       // another, 8 by a compute dispatch and 8 by the transfer path,
                                       // after the warm-up; 0: none.
    // Method settings JSON texts (as RunOptions::settingsJson, no "common") timed one after the
    // other on the same inputs and denoiser, one TimingReport each (the bandwidth probe runs with
    // the first); empty: RunOptions::settingsJson.
    std::vector<std::string> settingsVariants;
    // nrd-sample's pattern, after the first variant's timed frames: 'isolatedFrames' frames each
    // submitted alone and waited for, right away, then each after 'isolatedIdleMs' of host idle
    // time (TimingReport::aloneMs / isolatedMs); 0: not measured.
    uint32_t isolatedIdleMs = 0;
    uint32_t isolatedFrames = 8;
    std::function<void(uint32_t variant, uint32_t variants)> progress; // (Optional) Before each variant.
};

struct RunOptions
{
    std::string scene = "static";   // Built-in scene name (Samples/Scenes) or a JSON file path.
    std::string method = "SIGMA_SHADOW"; // nrd::GetMethodString name, or "NONE" (noisy input passes through).
    std::string signal;             // shadow | diffuse | specular; empty: the method's own signal.
    uint32_t frames = 0;            // 0: the scene's frame count.
    uint32_t width = 256, height = 256;
    uint32_t truthSpp = 256;
    uint32_t seed = 0xFFFFFFFFu;    // Scene seed unless set.
    uint32_t warmup = 8;            // Frames excluded from the averages.
    int32_t device = -1;            // Vulkan physical device index; -1: first discrete GPU, else first.
    bool validation = false;        // VK_LAYER_KHRONOS_validation; messages fail the run.
    // (Optional) Run on this context ('device' and 'validation' are then the context's). Without
    // one, the run takes the process's context for 'device' and 'validation' (created by the first
    // run that asks for it, kept until the process ends): every instance and device a driver creates
    // and destroys costs it state that not every driver gives back (the H100's and H200's drivers
    // refused new instances after a few dozen in one process).
    nrd::lab::VulkanContext* context = nullptr;
    std::string settingsJson;       // (Optional) JSON text with "common", "sigma", "reference", "tiledShadow".
    std::string cacheDirectory;     // Scene-lab frame cache; empty: the default one; "none": off.
    bool keepImages = true;         // Keep the last frame's noisy / denoised / truth images in the report.
    bool bounds = false;            // Also measure the temporal-reuse bounds of the scene (ReuseBounds.h).
    // CONFIDENCE runs in front of the method on the lab's temporal gradients; its outputs are the
    // method's IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE (the adapter turns the method's confidence
    // inputs on; settings under "confidence"). Methods without confidence inputs fail.
    bool confidence = false;
    std::function<void(uint32_t frame, uint32_t frames)> progress; // (Optional)
    TimingOptions timing;
};

// Block size of FrameMetrics::relmseLowpassDenoised, in pixels.
constexpr uint32_t kLowpassBlock = 8;

// Blend factors of the reuse bounds' oracle (the second is the one reported as 'oracle').
constexpr float kBoundAlphas[3] = {0.15f, 0.25f, 0.35f};

struct FrameMetrics
{
    double relmseNoisy = 0, relmseDenoised = 0;
    // RelMSE of kLowpassBlock x kLowpassBlock block means (Metrics.h, BlockMeans): the error that
    // noise leaves out, such as light that lags behind a change.
    double relmseLowpassDenoised = 0;
    double psnrNoisy = 0, psnrDenoised = 0;
    double ssimNoisy = 0, ssimDenoised = 0;
    double flipNoisy = 0, flipDenoised = 0;
    double temporalInstabilityNoisy = 0, temporalInstabilityDenoised = 0, temporalInstabilityTruth = 0;
    double gpuMs = 0;
    // Mean value of the compared channels over every pixel (sky included, passed through): a
    // denoiser that loses or adds energy has meanDenoised away from meanTruth.
    double meanNoisy = 0, meanDenoised = 0, meanTruth = 0;
    // ReuseBounds.h (with RunOptions::bounds; -1 otherwise and where a frame has no previous one):
    // the oracle with blend factor 0.25, and with each of kBoundAlphas.
    double boundReprojectedTruth = -1, boundOracle = -1, boundOracleInstability = -1;
    double boundOracleByAlpha[3] = {-1, -1, -1};
};

// One dispatch name of the timed frames (a name dispatched twice in a frame is summed).
struct PassTiming
{
    std::string name;
    std::vector<double> ms; // GPU time per timed frame (from the previous dispatch's end, barriers included).
    DispatchBytes bytes;    // ByteModel.h, per frame.
};

struct TimingReport
{
    uint32_t frames = 0, warmupFrames = 0, framesPerSubmission = 0, idleMs = 0; // warmupFrames: as run.
    std::vector<double> frameMs;  // First dispatch's start to last dispatch's end, per timed frame.
    std::vector<PassTiming> passes; // In dispatch order.
    uint64_t copyBytes = 0;       // Bytes read by one probe copy (as many are written).
    std::vector<double> copyMs;   // GPU time of each probe copy by a compute dispatch,
    std::vector<double> transferCopyMs; // and by vkCmdCopyBuffer.
    double wallSeconds = 0.0;     // Host time of the timed frames, submissions and waits included.
    std::vector<double> aloneMs, isolatedMs; // TimingOptions::isolatedIdleMs, per frame.
};

struct RunReport
{
    std::string scene, method, signal, device;
    bool confidence = false;       // RunOptions::confidence (memory, GPU time and passes include it).
    std::string driver;            // Vulkan driver name and version.
    uint32_t width = 0, height = 0, frames = 0, warmup = 0, truthSpp = 0;
    double gpuMsPerFrame = 0;      // Mean over the frames after the warm-up (0 for NONE).
    uint64_t memoryBytes = 0;      // The integration layer's device memory (pools, constants).
    uint64_t permanentPoolBytes = 0, transientPoolBytes = 0, bufferPoolBytes = 0, constantRingBytes = 0;
    uint32_t dispatchesPerFrame = 0, pipelines = 0;
    FrameMetrics mean;             // Averages over the frames after the warm-up.
    int32_t lagFrames = 0;         // Frames to recover after a sudden change, the longest over the
                                   // changes (each counted up to the next one; 0 if none).
    int32_t lagEventFrame = -1;    // That change's frame, -1 if the truth never changes suddenly.
    // The same on relmseLowpassDenoised: frames until the low frequencies are back, the lag of the
    // lighting itself (lagFrames also counts the frames a history restarted by the change takes to
    // average its noise down again).
    int32_t lagLowpassFrames = 0;
    int32_t lagLowpassEventFrame = -1;
    std::vector<FrameMetrics> perFrame;
    std::vector<std::pair<std::string, double>> passMs; // Mean GPU time per dispatch name.
    double renderNoisyMs = 0, renderTruthMs = 0;        // Scene-lab time per frame (wall, incl. cache),
                                                        // mean over the frames after the warm-up
                                                        // (the lab creates its pipelines on first use).
    struct MeshInfo
    {
        std::string file;
        uint32_t triangles = 0, bvhNodes = 0, bvhDepth = 0;
        double bvhBuildMs = 0; // Once per process (LoadMeshShared).
    };
    std::vector<MeshInfo> meshes; // The scene's triangle meshes, each once.
    // Methods that trace a ray list (MethodAdapter::IsRayListTraced), means over the frames after
    // the warm-up: rays the lab traced, rays of the full-rate input (one per non-sky pixel), ratio.
    double raysTraced = 0, raysFullRate = 0, rayRatio = 0;
    uint32_t validationMessages = 0;
    Image noisy, denoised, truth;  // Last frame (if keepImages).
    std::vector<TimingReport> timing; // With RunOptions::timing.frames: one per settings variant.
};

// Returns false with 'error' set on bad options or a device failure.
bool RunMethod(const RunOptions& options, RunReport& report, std::string& error);

// The JSON report (the nrd-sample contract).
std::string ReportToJson(const RunReport& report);

} // namespace nrdlab
