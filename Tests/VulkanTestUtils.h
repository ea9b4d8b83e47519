// Helpers for Vulkan tests (label "vulkan"): a validated context, random images, camera settings,
// and "run one Denoise with these textures and wait". Header-only.
#pragma once

#include <catch2/catch.hpp>

#include "NRDIntegration.h"
#include "RHIVulkan.h"
#include "VulkanContext.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <utility>
#include <vector>

namespace nrd
{
namespace test
{

// False when NRD_TEST_VALIDATION=0: the sanitizer job (Tests/Sanitize.cmake) runs the tests without
// the validation layer. The layer is not instrumented, keeps per-object state (debug names) in
// strings whose leak stacks end inside libstdc++ and cannot be told apart from the project's, and
// the Release job runs every one of these tests under it anyway.
inline bool ValidationRequested()
{
    const char* value = std::getenv("NRD_TEST_VALIDATION");
    return !(value && std::strcmp(value, "0") == 0);
}

// A context with VK_LAYER_KHRONOS_validation (+ synchronization validation) on the default device
// (lavapipe where there is no GPU), unless ValidationRequested() is false. Tests end with
// CHECK(context->ValidationMessageCount() == 0).
inline std::unique_ptr<lab::VulkanContext> CreateValidatedContext()
{
    lab::VulkanContextDesc desc = {};
    desc.enableValidation = ValidationRequested();
    desc.enableSynchronizationValidation = true;
    desc.applicationName = "NRD tests";
    desc.quiet = true;
    std::unique_ptr<lab::VulkanContext> context(new lab::VulkanContext());
    if (context->Create(desc) != VK_SUCCESS)
        return nullptr;
    return context;
}

// 'num' uniform random floats in [lo, hi), deterministic for a seed.
inline std::vector<float> RandomFloats(size_t num, uint32_t seed, float lo = 0.0f, float hi = 1.0f)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> distribution(lo, hi);
    std::vector<float> values(num);
    for (float& v : values)
        v = distribution(rng);
    return values;
}

// 'pixels' as the GPU sees them after a round trip through 'format' (e.g. fp16 rounding).
inline std::vector<float> Quantize(rhi::Format format, const std::vector<float>& pixels)
{
    uint32_t channels = rhi::GetFormatInfo(format).channelNum;
    size_t pixelsNum = pixels.size() / channels;
    std::vector<uint8_t> bytes(pixelsNum * rhi::GetFormatBytesPerPixel(format));
    std::vector<float> result(pixels.size());
    lab::PackPixels(format, pixels.data(), pixelsNum, bytes.data());
    lab::UnpackPixels(format, bytes.data(), pixelsNum, result.data());
    return result;
}

// Number of values where |actual - expected| > absTolerance + relTolerance * |expected| (or
// either is non-finite); prints the first few.
inline size_t CountMismatches(const std::vector<float>& actual, const std::vector<float>& expected,
                              float absTolerance, float relTolerance)
{
    if (actual.size() != expected.size())
        return actual.size() > expected.size() ? actual.size() : expected.size();
    size_t mismatches = 0;
    for (size_t i = 0; i < actual.size(); i++)
    {
        float difference = std::fabs(actual[i] - expected[i]);
        bool ok = std::isfinite(actual[i]) && difference <= absTolerance + relTolerance * std::fabs(expected[i]);
        if (!ok && mismatches++ < 5)
            std::printf("  value %zu: got %.7g, expected %.7g\n", i, actual[i], expected[i]);
    }
    return mismatches;
}

// A still camera: identity view, a perspective projection with clip w = +viewZ.
inline CommonSettings StillCameraSettings(uint32_t frameIndex, uint16_t width = 0, uint16_t height = 0)
{
    CommonSettings settings = {};
    float projection[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0.1f, 0}; // Column-major.
    float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    for (int i = 0; i < 16; i++)
    {
        settings.viewToClipMatrix[i] = settings.viewToClipMatrixPrev[i] = projection[i];
        settings.worldToViewMatrix[i] = settings.worldToViewMatrixPrev[i] = identity[i];
    }
    settings.frameIndex = frameIndex;
    settings.resourceSize[0] = width;
    settings.resourceSize[1] = height;
    return settings;
}

// The application textures of one Denoise call.
typedef std::vector<std::pair<ResourceType, lab::LabTexture*>> Bindings;

// Records Denoise for 'identifiers' (all methods if empty) with 'textures' into a one-shot
// command buffer, submits it and waits; the textures' states follow what Denoise left them in.
inline VkResult DenoiseAndWait(lab::VulkanContext& context, Integration& integration, const Bindings& textures,
                               const std::vector<Identifier>& identifiers = {})
{
    UserPool pool = {};
    for (const auto& binding : textures)
        pool[binding.first] = binding.second->AsUserTexture();

    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    VkResult result = context.BeginCommands(commandBuffer);
    if (result != VK_SUCCESS)
        return result;
    result = integration.Denoise(commandBuffer, identifiers.data(), (uint32_t)identifiers.size(), pool);
    VkResult submitted = context.SubmitAndWait(commandBuffer);
    if (result != VK_SUCCESS)
        return result;
    for (const auto& binding : textures)
        binding.second->FromUserTexture(pool[binding.first]);
    return submitted;
}

// A float rounded to fp16, as an RG16F texture stores it: to nearest (ties to even) or toward zero
// (the rounding of a 16-bit float conversion is the implementation's choice; lavapipe truncates).
inline float RoundToHalf(float x, bool truncate)
{
    if (x == 0.0f || !std::isfinite(x))
        return x;
    int exponent = 0;
    std::frexp(x, &exponent);
    double quantum = std::ldexp(1.0, std::max(exponent - 11, -24)); // 11 significant bits, denormals 2^-24.
    double q = double(x) / quantum;
    return float((truncate ? std::trunc(q) : std::nearbyint(q)) * quantum);
}

// A pool texture of 'integration' as a lab texture (in the state the Integration tracks).
inline lab::LabTexture PoolTextureView(const Integration::PoolImage& image)
{
    lab::LabTexture view;
    view.texture = image.texture;
    view.format = rhi::FromVkFormat(image.format);
    view.width = image.width;
    view.height = image.height;
    view.state = image.state;
    return view;
}

// After a copy from or to a pool texture ('view' left in the copy's state): back to the state the
// Integration tracks, for the next Denoise.
inline void RestorePoolTextureState(lab::VulkanContext& context, const lab::LabTexture& view, const Integration::PoolImage& image)
{
    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    REQUIRE(context.BeginCommands(commandBuffer) == VK_SUCCESS);
    rhi::TextureBarrier back = {image.texture, view.state, image.state};
    context.GetDevice().CmdBarrier(rhi::GetCommandBuffer(commandBuffer), {nullptr, 0, nullptr, 0, &back, 1});
    REQUIRE(context.SubmitAndWait(commandBuffer) == VK_SUCCESS);
}

// Reads a pool texture ('type' PERMANENT_POOL or TRANSIENT_POOL) back as the last Denoise of
// 'integration' left it (that Denoise must have completed), then restores the state it tracks.
inline std::vector<float> ReadbackPoolTexture(lab::VulkanContext& context, Integration& integration, ResourceType type,
                                              uint16_t index)
{
    Integration::PoolImage image = integration.GetPoolImage(type, index);
    REQUIRE(image.texture != nullptr);
    lab::LabTexture view = PoolTextureView(image);
    std::vector<float> pixels;
    REQUIRE(context.ReadbackTexture(view, pixels) == VK_SUCCESS);
    RestorePoolTextureState(context, view, image);
    return pixels;
}

// Overwrites a pool texture with 'pixels' (ReadbackPoolTexture's layout) between two Denoise calls.
inline void WritePoolTexture(lab::VulkanContext& context, Integration& integration, ResourceType type, uint16_t index,
                             const std::vector<float>& pixels)
{
    Integration::PoolImage image = integration.GetPoolImage(type, index);
    REQUIRE(image.texture != nullptr);
    lab::LabTexture view = PoolTextureView(image);
    REQUIRE(context.UploadTexture(view, pixels.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
    RestorePoolTextureState(context, view, image);
}

// Runs a compute shader of 64 threads per group with two storage buffers, binding 0 the cases
// ('input', read only) and binding 1 the results ('resultFloats' floats, returned), and the case
// count 'caseNum' as its only push constant (one thread per case). For tests of the shared shader
// includes: the shader evaluates them and the test compares with a CPU evaluation.
inline std::vector<float> RunBufferShader(lab::VulkanContext& context, const uint32_t* spirv, size_t spirvSize,
                                          const char* name, const std::vector<float>& input, size_t resultFloats,
                                          uint32_t caseNum)
{
    rhi::Device& device = context.GetDevice();
    rhi::Buffer* casesBuffer = nullptr;
    rhi::Buffer* resultsBuffer = nullptr;
    rhi::BufferDesc desc = {std::max<size_t>(input.size(), 1) * sizeof(float), rhi::BUFFER_USAGE_STORAGE,
                            rhi::MemoryLocation::HOST_UPLOAD, "cases"};
    REQUIRE(device.CreateBuffer(desc, casesBuffer) == rhi::Result::SUCCESS);
    desc = {std::max<size_t>(resultFloats, 1) * sizeof(float), rhi::BUFFER_USAGE_STORAGE, rhi::MemoryLocation::HOST_READBACK,
            "results"};
    REQUIRE(device.CreateBuffer(desc, resultsBuffer) == rhi::Result::SUCCESS);
    if (!input.empty())
        std::memcpy(device.MapBuffer(*casesBuffer), input.data(), input.size() * sizeof(float));

    rhi::DescriptorBindingDesc bindings[] = {{0, rhi::DescriptorType::BUFFER, 1, nullptr},
                                             {1, rhi::DescriptorType::STORAGE_BUFFER, 1, nullptr}};
    rhi::DescriptorSetDesc sets[] = {{bindings, 2}};
    rhi::ComputePipelineDesc pipelineDesc = {};
    pipelineDesc.spirv = spirv;
    pipelineDesc.spirvSize = spirvSize;
    pipelineDesc.sets = sets;
    pipelineDesc.setsNum = 1;
    pipelineDesc.pushConstantsSize = 4;
    pipelineDesc.name = name;
    rhi::Pipeline* pipeline = nullptr;
    REQUIRE(device.CreateComputePipeline(pipelineDesc, pipeline) == rhi::Result::SUCCESS);

    rhi::DescriptorPoolDesc poolDesc = {};
    poolDesc.setsMaxNum = 1;
    poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::BUFFER] = 1;
    poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_BUFFER] = 1;
    rhi::DescriptorPool* pool = nullptr;
    REQUIRE(device.CreateDescriptorPool(poolDesc, pool) == rhi::Result::SUCCESS);
    rhi::DescriptorSet* set = nullptr;
    REQUIRE(device.AllocateDescriptorSet(*pool, *pipeline, 0, set) == rhi::Result::SUCCESS);
    rhi::DescriptorWrite writes[2] = {};
    writes[0].type = rhi::DescriptorType::BUFFER;
    writes[0].buffer = casesBuffer;
    writes[1].binding = 1;
    writes[1].type = rhi::DescriptorType::STORAGE_BUFFER;
    writes[1].buffer = resultsBuffer;
    device.UpdateDescriptorSet(*set, writes, 2);

    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    REQUIRE(context.BeginCommands(commandBuffer) == VK_SUCCESS);
    rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
    // RAW: the shader reads what the host wrote.
    rhi::BufferBarrier toShader = {casesBuffer, rhi::ACCESS_HOST_WRITE, rhi::ACCESS_SHADER_READ};
    device.CmdBarrier(cmd, {nullptr, 0, &toShader, 1, nullptr, 0});
    device.CmdBindPipeline(cmd, *pipeline);
    device.CmdBindDescriptorSet(cmd, *pipeline, 0, *set);
    device.CmdPushConstants(cmd, *pipeline, &caseNum, sizeof(caseNum));
    device.CmdDispatch(cmd, (caseNum + 63) / 64, 1, 1);
    // RAW: the host reads what the shader wrote.
    rhi::BufferBarrier toHost = {resultsBuffer, rhi::ACCESS_SHADER_READ_WRITE, rhi::ACCESS_HOST_READ};
    device.CmdBarrier(cmd, {nullptr, 0, &toHost, 1, nullptr, 0});
    REQUIRE(context.SubmitAndWait(commandBuffer) == VK_SUCCESS);

    std::vector<float> results(resultFloats);
    if (resultFloats > 0)
        std::memcpy(results.data(), device.MapBuffer(*resultsBuffer), resultFloats * sizeof(float));
    device.DestroyDescriptorPool(pool);
    device.DestroyPipeline(pipeline);
    device.DestroyBuffer(casesBuffer);
    device.DestroyBuffer(resultsBuffer);
    return results;
}

// The light of the shadow denoisers' moving-light tests (SigmaSettings, TiledShadowSettings) on
// frame 'frame': an infinite light turning by atan(step) a frame with tan(angular radius) 'size', or
// a sphere light of radius 'size' five units above and in front of the plane at depth 'planeViewZ'
// (the still camera's), moving 'step' a frame along +x.
template <class Settings>
void SetMovingTestLight(Settings& s, bool isInfinite, float size, float step, uint32_t frame, float planeViewZ)
{
    if (isInfinite)
    {
        float angle = std::atan(step) * float(frame);
        s.lightDirection[0] = std::sin(angle);
        s.lightDirection[1] = std::cos(angle);
        s.tanOfLightAngularRadius = size;
    }
    else
    {
        s.lightPosition[0] = step * float(frame);
        s.lightPosition[1] = -5.0f;
        s.lightPosition[2] = planeViewZ - 5.0f;
        s.lightRadius = size;
    }
}

} // namespace test
} // namespace nrd
