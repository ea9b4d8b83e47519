// Vulkan integration layer (Integration/): the executor runs the core's dispatches correctly, with
// clean barriers, under VK_LAYER_KHRONOS_validation with synchronization validation. Runs on
// lavapipe; images are small.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include "RHIVulkan.h"

#include <cstdint>
#include <cstring>
#include <string>

using namespace nrd;
using nrd::test::Bindings;

namespace
{
#include "RhiTestArgs.h"
#include "RhiTestFill.h"
} // namespace

namespace
{

constexpr Identifier REFERENCE_ID = 7;
constexpr rhi::Format RGBA32F = rhi::Format::RGBA32_SFLOAT;
constexpr rhi::Format RGBA16F = rhi::Format::RGBA16_SFLOAT;

// One REFERENCE denoiser with its input and output textures.
struct ReferenceRig
{
    lab::VulkanContext& context;
    Integration integration;
    lab::LabTexture input;
    lab::LabTexture output;
    rhi::Format inputFormat;
    rhi::Format outputFormat;
    uint16_t width = 0;
    uint16_t height = 0;

    ReferenceRig(lab::VulkanContext& c, rhi::Format inFormat, rhi::Format outFormat)
        : context(c), inputFormat(inFormat), outputFormat(outFormat)
    {
    }

    ~ReferenceRig()
    {
        integration.Destroy();
        context.DestroyTexture(input);
        context.DestroyTexture(output);
    }

    VkResult Create(uint16_t w, uint16_t h, uint32_t framesInFlight = 2, const MethodDesc* methods = nullptr,
                    uint32_t methodsNum = 0)
    {
        MethodDesc reference = {REFERENCE_ID, Method::REFERENCE};
        DenoiserCreationDesc desc = {};
        desc.methods = methods ? methods : &reference;
        desc.methodsNum = methods ? methodsNum : 1;
        desc.renderWidth = w;
        desc.renderHeight = h;
        IntegrationCreationDesc integrationDesc = context.GetIntegrationCreationDesc();
        integrationDesc.framesInFlight = framesInFlight;
        integrationDesc.name = "REFERENCE test";
        VkResult result = integration.Create(integrationDesc, desc);
        if (result == VK_SUCCESS)
            result = CreateTextures(w, h);
        return result;
    }

    VkResult CreateTextures(uint16_t w, uint16_t h)
    {
        context.DestroyTexture(input);
        context.DestroyTexture(output);
        width = w;
        height = h;
        VkResult result = context.CreateTexture(inputFormat, w, h, "IN_RADIANCE", input);
        if (result == VK_SUCCESS)
            result = context.CreateTexture(outputFormat, w, h, "OUT_RADIANCE", output);
        return result;
    }

    // Uploads 'pixels' (RGBA) as this frame's input, denoises, returns the output.
    std::vector<float> Frame(uint32_t frameIndex, const std::vector<float>& pixels)
    {
        REQUIRE(context.UploadTexture(input, pixels.data(), rhi::Layout::COPY_DESTINATION) == VK_SUCCESS);
        REQUIRE(integration.SetCommonSettings(test::StillCameraSettings(frameIndex)) == Result::SUCCESS);
        Bindings bindings = {{ResourceType::IN_RADIANCE, &input}, {ResourceType::OUT_RADIANCE, &output}};
        REQUIRE(test::DenoiseAndWait(context, integration, bindings) == VK_SUCCESS);
        std::vector<float> result;
        REQUIRE(context.ReadbackTexture(output, result) == VK_SUCCESS);
        return result;
    }
};

size_t PixelsOf(uint32_t w, uint32_t h)
{
    return (size_t)w * h * 4;
}

// Runs 'frames' frames of random input from 'firstFrame' on and checks each output against the
// running mean of the inputs since 'firstFrame'.
void CheckRunningMean(ReferenceRig& rig, uint32_t firstFrame, uint32_t frames, uint32_t seed, float tolerance)
{
    size_t num = PixelsOf(rig.width, rig.height);
    std::vector<double> sum(num, 0.0);
    for (uint32_t f = 0; f < frames; f++)
    {
        std::vector<float> pixels = test::RandomFloats(num, seed + f, 0.0f, 4.0f);
        std::vector<float> quantized = test::Quantize(rig.inputFormat, pixels);
        std::vector<float> mean(num);
        for (size_t i = 0; i < num; i++)
        {
            sum[i] += quantized[i];
            mean[i] = float(sum[i] / (f + 1));
        }
        std::vector<float> output = rig.Frame(firstFrame + f, pixels);
        INFO("frame " << firstFrame + f << " at " << rig.width << "x" << rig.height);
        CHECK(test::CountMismatches(output, mean, 1e-5f, tolerance) == 0);
    }
}

} // namespace

TEST_CASE("Reference accumulation converges to the mean of its inputs", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);

    SECTION("fp32 input and output")
    {
        ReferenceRig rig(*context, RGBA32F, RGBA32F);
        REQUIRE(rig.Create(64, 64) == VK_SUCCESS);
        CheckRunningMean(rig, 0, 6, 100, 1e-5f);
    }

    SECTION("fp16 input and output")
    {
        ReferenceRig rig(*context, RGBA16F, RGBA16F);
        REQUIRE(rig.Create(48, 80) == VK_SUCCESS);
        CheckRunningMean(rig, 0, 5, 200, 1e-3f); // fp16 output: 11-bit mantissa.
    }

    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Reference frameIndex 0 restarts accumulation", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ReferenceRig rig(*context, RGBA32F, RGBA32F);
        REQUIRE(rig.Create(64, 64) == VK_SUCCESS);
        CheckRunningMean(rig, 0, 3, 300, 1e-5f);

        // Restart: the first output is exactly the new input, then the mean of the new frames.
        CheckRunningMean(rig, 0, 3, 400, 1e-5f);

        // RESTART mode does the same without touching frameIndex.
        std::vector<float> pixels = test::RandomFloats(PixelsOf(64, 64), 500, 0.0f, 4.0f);
        CommonSettings settings = test::StillCameraSettings(3);
        settings.accumulationMode = AccumulationMode::RESTART;
        REQUIRE(context->UploadTexture(rig.input, pixels.data()) == VK_SUCCESS);
        REQUIRE(rig.integration.SetCommonSettings(settings) == Result::SUCCESS);
        Bindings bindings = {{ResourceType::IN_RADIANCE, &rig.input}, {ResourceType::OUT_RADIANCE, &rig.output}};
        REQUIRE(test::DenoiseAndWait(*context, rig.integration, bindings) == VK_SUCCESS);
        std::vector<float> output;
        REQUIRE(context->ReadbackTexture(rig.output, output) == VK_SUCCESS);
        CHECK(test::CountMismatches(output, pixels, 0.0f, 0.0f) == 0);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Reference history is limited by maxAccumulatedFrameNum", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ReferenceRig rig(*context, RGBA32F, RGBA32F);
        REQUIRE(rig.Create(32, 32) == VK_SUCCESS);
        ReferenceSettings settings = {};
        settings.maxAccumulatedFrameNum = 1; // Output = input every frame.
        REQUIRE(rig.integration.SetMethodSettings(REFERENCE_ID, settings) == Result::SUCCESS);
        for (uint32_t f = 0; f < 3; f++)
        {
            std::vector<float> pixels = test::RandomFloats(PixelsOf(32, 32), 600 + f, 0.0f, 4.0f);
            CHECK(test::CountMismatches(rig.Frame(f, pixels), pixels, 0.0f, 0.0f) == 0);
        }
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Resize mid-sequence restarts history and keeps the output correct", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ReferenceRig rig(*context, RGBA32F, RGBA16F);
        REQUIRE(rig.Create(96, 64) == VK_SUCCESS);
        ReferenceSettings settings = {};
        settings.maxAccumulatedFrameNum = 100;
        REQUIRE(rig.integration.SetMethodSettings(REFERENCE_ID, settings) == Result::SUCCESS);
        CheckRunningMean(rig, 0, 3, 700, 1e-3f);

        // Smaller: history restarts (new pools, cleared), frame numbering continues.
        REQUIRE(rig.integration.Resize(40, 24) == VK_SUCCESS);
        CHECK(rig.integration.GetDenoiserDesc().renderWidth == 40);
        REQUIRE(rig.CreateTextures(40, 24) == VK_SUCCESS);
        CheckRunningMean(rig, 3, 3, 800, 1e-3f);

        // Larger, odd sizes.
        REQUIRE(rig.integration.Resize(131, 77) == VK_SUCCESS);
        REQUIRE(rig.CreateTextures(131, 77) == VK_SUCCESS);
        CheckRunningMean(rig, 6, 2, 900, 1e-3f);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Two Denoise calls in one command buffer keep their own constants", "[vulkan]")
{
    // Frame 0 (weight 1) and frame 1 (weight 1/2) recorded back to back: their constants live in
    // different ring slots and the history written by the first is read by the second.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        const uint16_t w = 64, h = 32;
        ReferenceRig rig(*context, RGBA32F, RGBA32F);
        REQUIRE(rig.Create(w, h, 2) == VK_SUCCESS);
        lab::LabTexture second;
        REQUIRE(context->CreateTexture(RGBA32F, w, h, "IN_RADIANCE 2", second) == VK_SUCCESS);
        std::vector<float> a = test::RandomFloats(PixelsOf(w, h), 1000, 0.0f, 4.0f);
        std::vector<float> b = test::RandomFloats(PixelsOf(w, h), 1001, 0.0f, 4.0f);
        REQUIRE(context->UploadTexture(rig.input, a.data()) == VK_SUCCESS);
        REQUIRE(context->UploadTexture(second, b.data(), rhi::Layout::GENERAL) == VK_SUCCESS);

        VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
        REQUIRE(context->BeginCommands(commandBuffer) == VK_SUCCESS);
        UserPool pool = {};
        pool[ResourceType::OUT_RADIANCE] = rig.output.AsUserTexture();
        for (uint32_t frame = 0; frame < 2; frame++)
        {
            pool[ResourceType::IN_RADIANCE] = (frame == 0 ? rig.input : second).AsUserTexture();
            REQUIRE(rig.integration.SetCommonSettings(test::StillCameraSettings(frame)) == Result::SUCCESS);
            REQUIRE(rig.integration.Denoise(commandBuffer, nullptr, 0, pool) == VK_SUCCESS);
            (frame == 0 ? rig.input : second).FromUserTexture(pool[ResourceType::IN_RADIANCE]);
        }
        REQUIRE(context->SubmitAndWait(commandBuffer) == VK_SUCCESS);
        rig.output.FromUserTexture(pool[ResourceType::OUT_RADIANCE]);
        CHECK(pool[ResourceType::OUT_RADIANCE].layout == VK_IMAGE_LAYOUT_GENERAL);
        CHECK(pool[ResourceType::IN_RADIANCE].layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

        std::vector<float> expected(a.size());
        for (size_t i = 0; i < a.size(); i++)
            expected[i] = (a[i] + b[i]) * 0.5f;
        std::vector<float> output;
        REQUIRE(context->ReadbackTexture(rig.output, output) == VK_SUCCESS);
        CHECK(test::CountMismatches(output, expected, 1e-6f, 1e-6f) == 0);
        context->DestroyTexture(second);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Timestamps are reported for each dispatch", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    if (!context->GetDevice().GetDesc().timestampsSupported)
    {
        WARN("Timestamps are not supported by " << context->GetProperties().deviceName);
        return;
    }
    {
        // Two REFERENCE methods writing the same output: two dispatches, a WAW between them.
        MethodDesc methods[] = {{1, Method::REFERENCE}, {2, Method::REFERENCE}};
        ReferenceRig rig(*context, RGBA32F, RGBA32F);
        REQUIRE(rig.Create(64, 64, 3, methods, 2) == VK_SUCCESS);
        CHECK(rig.integration.GetLastTimings().empty()); // Nothing ran yet.

        std::vector<float> pixels = test::RandomFloats(PixelsOf(64, 64), 1100);
        rig.Frame(0, pixels);
        double total = -1.0;
        std::vector<DispatchTiming> timings = rig.integration.GetLastTimings(&total);
        REQUIRE(timings.size() == 2);
        for (const DispatchTiming& timing : timings)
        {
            REQUIRE(timing.name != nullptr);
            CHECK(std::string(timing.name).find("REFERENCE") != std::string::npos);
            CHECK(timing.milliseconds >= 0.0);
        }
        CHECK(total >= 0.0);

        // Only one method: one dispatch.
        REQUIRE(rig.integration.SetCommonSettings(test::StillCameraSettings(1)) == Result::SUCCESS);
        Bindings bindings = {{ResourceType::IN_RADIANCE, &rig.input}, {ResourceType::OUT_RADIANCE, &rig.output}};
        REQUIRE(test::DenoiseAndWait(*context, rig.integration, bindings, {2}) == VK_SUCCESS);
        CHECK(rig.integration.GetLastTimings().size() == 1);

        // The call before stays readable while its slot is not reused (3 frames in flight); the
        // recorded dispatch lists its resources in binding order.
        CHECK(rig.integration.GetTimings(1).size() == 2);
        CHECK(rig.integration.GetTimings(2).empty()); // Only two calls so far.
        CHECK(rig.integration.GetTimings(3).empty()); // Beyond the frames in flight.
        std::vector<RecordedDispatch> recorded = rig.integration.GetLastDispatches();
        REQUIRE(recorded.size() == 1);
        CHECK(std::string(recorded[0].name) == timings[1].name);
        bool readsInput = false, writesOutput = false;
        for (const ResourceDesc& resource : recorded[0].resources)
        {
            readsInput |= resource.type == ResourceType::IN_RADIANCE && resource.descriptorType == DescriptorType::TEXTURE;
            writesOutput |= resource.type == ResourceType::OUT_RADIANCE &&
                            resource.descriptorType == DescriptorType::STORAGE_TEXTURE;
        }
        CHECK(readsInput);
        CHECK(writesOutput);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Memory report matches the pool descriptions", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ReferenceRig rig(*context, RGBA32F, RGBA32F);
        REQUIRE(rig.Create(100, 60) == VK_SUCCESS);

        auto expectedMinimum = [](const DenoiserDesc& desc, const TextureDesc* pool, uint32_t num) {
            uint64_t bytes = 0;
            for (uint32_t i = 0; i < num; i++)
            {
                uint64_t w = (desc.renderWidth + pool[i].downsampleX - 1) / pool[i].downsampleX;
                uint64_t h = (desc.renderHeight + pool[i].downsampleY - 1) / pool[i].downsampleY;
                bytes += w * h * GetFormatBytesPerPixel(pool[i].format);
            }
            return bytes;
        };
        auto check = [&]() {
            const DenoiserDesc& desc = rig.integration.GetDenoiserDesc();
            MemoryReport report = rig.integration.GetMemoryReport();
            uint64_t permanent = expectedMinimum(desc, desc.permanentPool, desc.permanentPoolSize);
            uint64_t transient = expectedMinimum(desc, desc.transientPool, desc.transientPoolSize);
            uint64_t buffers = 0;
            for (uint32_t i = 0; i < desc.buffersNum; i++)
                buffers += desc.buffers[i].size;
            CHECK(permanent > 0); // REFERENCE keeps an RGBA32F history.
            CHECK(report.permanentPoolBytes >= permanent);
            CHECK(report.transientPoolBytes >= transient);
            CHECK(report.bufferPoolBytes >= buffers);
            CHECK(report.totalBytes == report.permanentPoolBytes + report.transientPoolBytes +
                                           report.bufferPoolBytes + report.constantRingBytes);
            return report;
        };

        MemoryReport before = check();
        CHECK(before.permanentPoolBytes >= 100u * 60u * 16u);
        rig.Frame(0, test::RandomFloats(PixelsOf(100, 60), 1200));
        CHECK(rig.integration.GetMemoryReport().constantRingBytes > 0); // Allocated by the first Denoise.

        REQUIRE(rig.integration.Resize(50, 30) == VK_SUCCESS);
        MemoryReport after = check();
        CHECK(after.permanentPoolBytes < before.permanentPoolBytes);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Denoise without a required user texture fails and records nothing", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        ReferenceRig rig(*context, RGBA32F, RGBA32F);
        REQUIRE(rig.Create(32, 32) == VK_SUCCESS);
        REQUIRE(rig.integration.SetCommonSettings(test::StillCameraSettings(0)) == Result::SUCCESS);
        Bindings onlyInput = {{ResourceType::IN_RADIANCE, &rig.input}}; // OUT_RADIANCE missing.
        rhi::TextureState before = rig.input.state;
        CHECK(test::DenoiseAndWait(*context, rig.integration, onlyInput) == VK_ERROR_INITIALIZATION_FAILED);
        CHECK(rig.input.state.layout == before.layout);

        // The next, complete frame works.
        std::vector<float> pixels = test::RandomFloats(PixelsOf(32, 32), 1300);
        CHECK(test::CountMismatches(rig.Frame(0, pixels), pixels, 0.0f, 0.0f) == 0);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Pixel conversions round-trip through every uploadable format", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const rhi::Format formats[] = {rhi::Format::R8_UNORM,     rhi::Format::RGBA8_UNORM,   rhi::Format::R16_SFLOAT,
                                   rhi::Format::RG16_SFLOAT,  rhi::Format::RGBA16_SFLOAT, rhi::Format::R32_SFLOAT,
                                   rhi::Format::RGBA32_SFLOAT, rhi::Format::R32_UINT,     rhi::Format::R10_G10_B10_A2_UNORM};
    for (rhi::Format format : formats)
    {
        INFO(rhi::GetFormatInfo(format).name);
        const uint32_t w = 17, h = 9;
        std::vector<float> pixels = test::RandomFloats((size_t)w * h * rhi::GetFormatInfo(format).channelNum, 1400,
                                                       0.0f, rhi::GetFormatInfo(format).isInteger ? 1000.0f : 1.0f);
        std::vector<float> expected = test::Quantize(format, pixels);
        lab::LabTexture texture;
        REQUIRE(context->CreateTexture(format, w, h, "round trip", texture) == VK_SUCCESS);
        REQUIRE(context->UploadTexture(texture, pixels.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
        std::vector<float> readback;
        REQUIRE(context->ReadbackTexture(texture, readback) == VK_SUCCESS);
        CHECK(test::CountMismatches(readback, expected, 0.0f, 0.0f) == 0);
        context->DestroyTexture(texture);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Rhi runs pipelines with storage buffers, push constants and indirect dispatch", "[vulkan]")
{
    // A pass writes indirect arguments (3 x 2 groups of 8x8); a second pass, dispatched
    // indirectly, fills that corner of a cleared storage image from a buffer and a uniform block.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        rhi::Device& device = context->GetDevice();
        const uint32_t w = 40, h = 24, groupsX = 3, groupsY = 2;

        lab::LabTexture image;
        REQUIRE(context->CreateTexture(RGBA32F, w, h, "rhi test image", image) == VK_SUCCESS);
        rhi::Buffer* values = nullptr;
        rhi::Buffer* constants = nullptr;
        rhi::Buffer* args = nullptr;
        rhi::BufferDesc desc = {};
        desc.size = w * h * sizeof(float);
        desc.usage = rhi::BUFFER_USAGE_STORAGE;
        desc.location = rhi::MemoryLocation::HOST_UPLOAD;
        REQUIRE(device.CreateBuffer(desc, values) == rhi::Result::SUCCESS);
        desc = {256, rhi::BUFFER_USAGE_UNIFORM, rhi::MemoryLocation::HOST_UPLOAD, "constants"};
        REQUIRE(device.CreateBuffer(desc, constants) == rhi::Result::SUCCESS);
        desc = {16, rhi::BUFFER_USAGE_STORAGE | rhi::BUFFER_USAGE_INDIRECT_ARGUMENTS, rhi::MemoryLocation::DEVICE, "args"};
        REQUIRE(device.CreateBuffer(desc, args) == rhi::Result::SUCCESS);
        std::vector<float> data = test::RandomFloats(w * h, 1500);
        std::memcpy(device.MapBuffer(*values), data.data(), data.size() * sizeof(float));
        const float scale[4] = {2.5f, 0.0f, 0.0f, 0.0f};
        std::memcpy(device.MapBuffer(*constants), scale, sizeof(scale));

        rhi::DescriptorBindingDesc argsBindings[] = {{0, rhi::DescriptorType::STORAGE_BUFFER, 1, nullptr}};
        rhi::DescriptorSetDesc argsSets[] = {{argsBindings, 1}};
        rhi::ComputePipelineDesc pipelineDesc = {};
        pipelineDesc.spirv = g_RhiTestArgs;
        pipelineDesc.spirvSize = sizeof(g_RhiTestArgs);
        pipelineDesc.sets = argsSets;
        pipelineDesc.setsNum = 1;
        pipelineDesc.pushConstantsSize = 8;
        pipelineDesc.name = "RhiTestArgs";
        rhi::Pipeline* argsPipeline = nullptr;
        REQUIRE(device.CreateComputePipeline(pipelineDesc, argsPipeline) == rhi::Result::SUCCESS);

        rhi::DescriptorBindingDesc fillBindings0[] = {{0, rhi::DescriptorType::STORAGE_TEXTURE, 1, nullptr},
                                                      {1, rhi::DescriptorType::BUFFER, 1, nullptr}};
        rhi::DescriptorBindingDesc fillBindings1[] = {{0, rhi::DescriptorType::UNIFORM_BUFFER, 1, nullptr}};
        rhi::DescriptorSetDesc fillSets[] = {{fillBindings0, 2}, {fillBindings1, 1}};
        pipelineDesc.spirv = g_RhiTestFill;
        pipelineDesc.spirvSize = sizeof(g_RhiTestFill);
        pipelineDesc.sets = fillSets;
        pipelineDesc.setsNum = 2;
        pipelineDesc.name = "RhiTestFill";
        rhi::Pipeline* fillPipeline = nullptr;
        REQUIRE(device.CreateComputePipeline(pipelineDesc, fillPipeline) == rhi::Result::SUCCESS);

        rhi::DescriptorPoolDesc poolDesc = {};
        poolDesc.setsMaxNum = 3;
        poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_BUFFER] = 1;
        poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::BUFFER] = 1;
        poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_TEXTURE] = 1;
        poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::UNIFORM_BUFFER] = 1;
        rhi::DescriptorPool* pool = nullptr;
        REQUIRE(device.CreateDescriptorPool(poolDesc, pool) == rhi::Result::SUCCESS);
        rhi::DescriptorSet* argsSet = nullptr;
        rhi::DescriptorSet* fillSet0 = nullptr;
        rhi::DescriptorSet* fillSet1 = nullptr;
        REQUIRE(device.AllocateDescriptorSet(*pool, *argsPipeline, 0, argsSet) == rhi::Result::SUCCESS);
        REQUIRE(device.AllocateDescriptorSet(*pool, *fillPipeline, 0, fillSet0) == rhi::Result::SUCCESS);
        REQUIRE(device.AllocateDescriptorSet(*pool, *fillPipeline, 1, fillSet1) == rhi::Result::SUCCESS);
        rhi::DescriptorSet* overflow = nullptr;
        CHECK(device.AllocateDescriptorSet(*pool, *argsPipeline, 0, overflow) == rhi::Result::OUT_OF_MEMORY);

        rhi::DescriptorWrite argsWrite = {};
        argsWrite.type = rhi::DescriptorType::STORAGE_BUFFER;
        argsWrite.buffer = args;
        device.UpdateDescriptorSet(*argsSet, &argsWrite, 1);
        rhi::DescriptorWrite fillWrites[2] = {};
        fillWrites[0].type = rhi::DescriptorType::STORAGE_TEXTURE;
        fillWrites[0].texture = image.texture;
        fillWrites[1].binding = 1;
        fillWrites[1].type = rhi::DescriptorType::BUFFER;
        fillWrites[1].buffer = values;
        device.UpdateDescriptorSet(*fillSet0, fillWrites, 2);
        rhi::DescriptorWrite constantsWrite = {};
        constantsWrite.type = rhi::DescriptorType::UNIFORM_BUFFER;
        constantsWrite.buffer = constants;
        constantsWrite.range = 16;
        device.UpdateDescriptorSet(*fillSet1, &constantsWrite, 1);

        VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
        REQUIRE(context->BeginCommands(commandBuffer) == VK_SUCCESS);
        rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);

        // Layout transition for the clear (first use).
        rhi::TextureState clearState = {rhi::ACCESS_COPY_DESTINATION, rhi::Layout::COPY_DESTINATION};
        rhi::TextureBarrier toClear = {image.texture, image.state, clearState};
        device.CmdBarrier(cmd, {nullptr, 0, nullptr, 0, &toClear, 1});
        const float minusOne[4] = {-1.0f, -1.0f, -1.0f, -1.0f};
        device.CmdClearTexture(cmd, *image.texture, rhi::Layout::COPY_DESTINATION, minusOne);

        const uint32_t groups[2] = {groupsX, groupsY};
        device.CmdBindPipeline(cmd, *argsPipeline);
        device.CmdBindDescriptorSet(cmd, *argsPipeline, 0, *argsSet);
        device.CmdPushConstants(cmd, *argsPipeline, groups, sizeof(groups));
        device.CmdDispatch(cmd, 1, 1, 1);

        // RAW: the indirect read waits for the argument writes; RAW: the fill waits for the clear.
        rhi::BufferBarrier argsBarrier = {args, rhi::ACCESS_SHADER_READ_WRITE, rhi::ACCESS_INDIRECT_ARGUMENTS};
        rhi::TextureBarrier toStorage = {image.texture, clearState, {rhi::ACCESS_SHADER_READ_WRITE, rhi::Layout::GENERAL}};
        device.CmdBarrier(cmd, {nullptr, 0, &argsBarrier, 1, &toStorage, 1});
        image.state = toStorage.after;

        const uint32_t size[2] = {w, h};
        device.CmdBindPipeline(cmd, *fillPipeline);
        device.CmdBindDescriptorSet(cmd, *fillPipeline, 0, *fillSet0);
        device.CmdBindDescriptorSet(cmd, *fillPipeline, 1, *fillSet1);
        device.CmdPushConstants(cmd, *fillPipeline, size, sizeof(size));
        device.CmdDispatchIndirect(cmd, *args, 0);
        REQUIRE(context->SubmitAndWait(commandBuffer) == VK_SUCCESS);

        std::vector<float> pixels;
        REQUIRE(context->ReadbackTexture(image, pixels) == VK_SUCCESS);
        std::vector<float> expected(w * h * 4, -1.0f);
        for (uint32_t y = 0; y < groupsY * 8; y++)
        {
            for (uint32_t x = 0; x < groupsX * 8; x++)
            {
                float* p = &expected[(y * w + x) * 4];
                p[0] = (float)x;
                p[1] = (float)y;
                p[2] = data[y * w + x];
                p[3] = 2.5f;
            }
        }
        CHECK(test::CountMismatches(pixels, expected, 0.0f, 0.0f) == 0);

        REQUIRE(device.ResetDescriptorPool(*pool) == rhi::Result::SUCCESS);
        REQUIRE(device.AllocateDescriptorSet(*pool, *argsPipeline, 0, argsSet) == rhi::Result::SUCCESS);

        device.DestroyDescriptorPool(pool);
        device.DestroyPipeline(argsPipeline);
        device.DestroyPipeline(fillPipeline);
        device.DestroyBuffer(values);
        device.DestroyBuffer(constants);
        device.DestroyBuffer(args);
        context->DestroyTexture(image);
    }
    CHECK(context->ValidationMessageCount() == 0);
}
