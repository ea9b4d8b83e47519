// Denoises with the Vulkan integration layer over the application's own Vulkan objects: REFERENCE
// (plain accumulation) on a small RGBA32F frame, and checks the output against the known answer.
//   frame 0: output = input 0 (history restarts)
//   frame 1: output = (input 0 + input 1) / 2
//   frame 2 with AccumulationMode::RESTART: output = input 2
// Runs on any Vulkan 1.1 device with shaderStorageImageWriteWithoutFormat (Mesa lavapipe on a CPU).
// Exit code 0 when every output matches, 1 on a mismatch, 2 when no device can run it.
#include <NRDIntegration.h>
#include <RHIVulkan.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

namespace
{

constexpr uint16_t kWidth = 16;
constexpr uint16_t kHeight = 8;
constexpr nrd::Identifier kReferenceId = 1;

// The application side: instance, device, queue. An engine has these already.
struct App
{
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    nrd::rhi::Device* rhi = nullptr; // Textures, uploads and readbacks of this example.

    bool Create()
    {
        VkApplicationInfo appInfo = {VK_STRUCTURE_TYPE_APPLICATION_INFO};
        appInfo.pApplicationName = "NRD example";
        appInfo.apiVersion = VK_API_VERSION_1_1;
        VkInstanceCreateInfo instanceInfo = {VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        instanceInfo.pApplicationInfo = &appInfo;
        if (vkCreateInstance(&instanceInfo, nullptr, &instance) != VK_SUCCESS)
            return false;

        uint32_t num = 0;
        vkEnumeratePhysicalDevices(instance, &num, nullptr);
        std::vector<VkPhysicalDevice> devices(num);
        vkEnumeratePhysicalDevices(instance, &num, devices.data());
        for (VkPhysicalDevice candidate : devices)
        {
            VkPhysicalDeviceFeatures features = {};
            vkGetPhysicalDeviceFeatures(candidate, &features);
            uint32_t familiesNum = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(candidate, &familiesNum, nullptr);
            std::vector<VkQueueFamilyProperties> families(familiesNum);
            vkGetPhysicalDeviceQueueFamilyProperties(candidate, &familiesNum, families.data());
            for (uint32_t f = 0; f < familiesNum && !physicalDevice; f++)
            {
                if ((families[f].queueFlags & VK_QUEUE_COMPUTE_BIT) && features.shaderStorageImageWriteWithoutFormat)
                {
                    physicalDevice = candidate;
                    queueFamily = f;
                }
            }
        }
        if (!physicalDevice)
            return false;

        // The integration layer writes application outputs as storage images without a format.
        VkPhysicalDeviceFeatures enabled = {};
        enabled.shaderStorageImageWriteWithoutFormat = VK_TRUE;
        float priority = 1.0f;
        VkDeviceQueueCreateInfo queueInfo = {VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        queueInfo.queueFamilyIndex = queueFamily;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;
        VkDeviceCreateInfo deviceInfo = {VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        deviceInfo.queueCreateInfoCount = 1;
        deviceInfo.pQueueCreateInfos = &queueInfo;
        deviceInfo.pEnabledFeatures = &enabled;
        if (vkCreateDevice(physicalDevice, &deviceInfo, nullptr, &device) != VK_SUCCESS)
            return false;
        vkGetDeviceQueue(device, queueFamily, 0, &queue);

        nrd::rhi::DeviceVulkanDesc rhiDesc = {};
        rhiDesc.physicalDevice = physicalDevice;
        rhiDesc.device = device;
        rhiDesc.queueFamilyIndex = queueFamily;
        rhiDesc.queue = queue;
        rhiDesc.storageImageWriteWithoutFormatEnabled = true;
        return nrd::rhi::CreateDeviceVulkan(rhiDesc, rhi) == nrd::rhi::Result::SUCCESS;
    }

    void Destroy()
    {
        nrd::rhi::DestroyDevice(rhi);
        if (device)
            vkDestroyDevice(device, nullptr);
        if (instance)
            vkDestroyInstance(instance, nullptr);
    }
};

// An RGBA32F texture the application owns, with the state it was last left in.
struct Texture
{
    nrd::rhi::Texture* texture = nullptr;
    nrd::rhi::TextureState state = {};
};

bool CreateTexture(App& app, const char* name, Texture& out)
{
    nrd::rhi::TextureDesc desc = {};
    desc.format = nrd::rhi::Format::RGBA32_SFLOAT;
    desc.width = kWidth;
    desc.height = kHeight;
    desc.usage = nrd::rhi::TEXTURE_USAGE_SAMPLED | nrd::rhi::TEXTURE_USAGE_STORAGE |
                 nrd::rhi::TEXTURE_USAGE_COPY_SOURCE | nrd::rhi::TEXTURE_USAGE_COPY_DESTINATION;
    desc.name = name;
    return app.rhi->CreateTexture(desc, out.texture) == nrd::rhi::Result::SUCCESS;
}

void Transition(App& app, nrd::rhi::CommandBuffer& cmd, Texture& texture, nrd::rhi::TextureState after)
{
    nrd::rhi::TextureBarrier barrier = {texture.texture, texture.state, after};
    nrd::rhi::BarrierDesc desc = {};
    desc.textures = &barrier;
    desc.texturesNum = 1;
    app.rhi->CmdBarrier(cmd, desc);
    texture.state = after;
}

nrd::UserTexture ToUser(const Texture& texture)
{
    nrd::UserTexture user = {};
    user.image = nrd::rhi::GetVkImage(*texture.texture);
    user.view = nrd::rhi::GetVkImageView(*texture.texture);
    user.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    user.layout = nrd::rhi::ToVkImageLayout(texture.state.layout);
    return user;
}

// A still camera: identity view, perspective projection with clip w = +viewZ.
nrd::CommonSettings CommonSettingsFor(uint32_t frameIndex)
{
    nrd::CommonSettings settings = {};
    const float projection[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0.1f, 0};
    const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    std::memcpy(settings.viewToClipMatrix, projection, sizeof(projection));
    std::memcpy(settings.viewToClipMatrixPrev, projection, sizeof(projection));
    std::memcpy(settings.worldToViewMatrix, identity, sizeof(identity));
    std::memcpy(settings.worldToViewMatrixPrev, identity, sizeof(identity));
    settings.resourceSize[0] = kWidth;
    settings.resourceSize[1] = kHeight;
    settings.frameIndex = frameIndex;
    return settings;
}

// One frame: upload 'pixels' into the input, denoise, read the output back into 'result'.
bool Frame(App& app, nrd::Integration& integration, Texture& input, Texture& output, nrd::rhi::Buffer& upload,
           nrd::rhi::Buffer& readback, const std::vector<float>& pixels, std::vector<float>& result)
{
    std::memcpy(app.rhi->MapBuffer(upload), pixels.data(), pixels.size() * sizeof(float));

    nrd::rhi::CommandBuffer* cmd = nullptr;
    if (app.rhi->CreateCommandBuffer(cmd) != nrd::rhi::Result::SUCCESS)
        return false;
    app.rhi->BeginCommandBuffer(*cmd);
    Transition(app, *cmd, input, {nrd::rhi::ACCESS_COPY_DESTINATION, nrd::rhi::Layout::COPY_DESTINATION});
    app.rhi->CmdCopyBufferToTexture(*cmd, *input.texture, upload, 0);

    // The denoiser records its own barriers from the layouts given here and hands back the final ones.
    nrd::UserPool pool;
    pool[nrd::ResourceType::IN_RADIANCE] = ToUser(input);
    pool[nrd::ResourceType::OUT_RADIANCE] = ToUser(output);
    VkResult denoised = integration.Denoise(nrd::rhi::GetVkCommandBuffer(*cmd), &kReferenceId, 1, pool);
    if (denoised == VK_SUCCESS)
    {
        // Both last written / read by a compute shader, in the layouts the denoiser reports.
        nrd::rhi::FromVkImageLayout(pool[nrd::ResourceType::IN_RADIANCE].layout, input.state.layout);
        nrd::rhi::FromVkImageLayout(pool[nrd::ResourceType::OUT_RADIANCE].layout, output.state.layout);
        input.state.access = nrd::rhi::ACCESS_SHADER_READ;
        output.state.access = nrd::rhi::ACCESS_SHADER_READ_WRITE;
        Transition(app, *cmd, output, {nrd::rhi::ACCESS_COPY_SOURCE, nrd::rhi::Layout::COPY_SOURCE});
        app.rhi->CmdCopyTextureToBuffer(*cmd, readback, 0, *output.texture);
        nrd::rhi::BufferBarrier toHost = {&readback, nrd::rhi::ACCESS_COPY_DESTINATION, nrd::rhi::ACCESS_HOST_READ};
        nrd::rhi::BarrierDesc barrier = {};
        barrier.buffers = &toHost;
        barrier.buffersNum = 1;
        app.rhi->CmdBarrier(*cmd, barrier);
    }
    app.rhi->EndCommandBuffer(*cmd);
    bool ok = denoised == VK_SUCCESS && app.rhi->SubmitAndWait(*cmd) == nrd::rhi::Result::SUCCESS;
    app.rhi->DestroyCommandBuffer(cmd);

    result.resize(pixels.size());
    if (ok)
        std::memcpy(result.data(), app.rhi->MapBuffer(readback), result.size() * sizeof(float));
    return ok;
}

// Largest |actual - expected| relative to max(1, |expected|); infinite on a non-finite value.
double MaxError(const std::vector<float>& actual, const std::vector<float>& expected)
{
    double worst = 0.0;
    for (size_t i = 0; i < expected.size(); i++)
    {
        double error = std::fabs(double(actual[i]) - expected[i]) / std::fmax(1.0, std::fabs(expected[i]));
        worst = std::isfinite(actual[i]) ? std::fmax(worst, error) : INFINITY;
    }
    return worst;
}

void Log(void*, nrd::LogSeverity, const char* message)
{
    std::fprintf(stderr, "NRD: %s\n", message);
}

} // namespace

int main()
{
    App app;
    if (!app.Create())
    {
        std::fprintf(stderr, "no Vulkan 1.1 device with compute and shaderStorageImageWriteWithoutFormat\n");
        app.Destroy();
        return 2;
    }

    nrd::MethodDesc method = {kReferenceId, nrd::Method::REFERENCE};
    nrd::DenoiserCreationDesc denoiserDesc = {};
    denoiserDesc.methods = &method;
    denoiserDesc.methodsNum = 1;
    denoiserDesc.renderWidth = kWidth;
    denoiserDesc.renderHeight = kHeight;
    denoiserDesc.logCallback = Log;

    nrd::IntegrationCreationDesc integrationDesc = {};
    integrationDesc.instance = app.instance;
    integrationDesc.physicalDevice = app.physicalDevice;
    integrationDesc.device = app.device;
    integrationDesc.queueFamilyIndex = app.queueFamily;
    integrationDesc.framesInFlight = 1; // Every frame below waits for its submission.

    int exitCode = 2;
    {
        nrd::Integration integration;
        Texture input, output;
        nrd::rhi::Buffer* upload = nullptr;
        nrd::rhi::Buffer* readback = nullptr;
        const uint64_t bytes = uint64_t(kWidth) * kHeight * 4 * sizeof(float);
        nrd::rhi::BufferDesc uploadDesc = {bytes, nrd::rhi::BUFFER_USAGE_COPY_SOURCE,
                                           nrd::rhi::MemoryLocation::HOST_UPLOAD, "upload"};
        nrd::rhi::BufferDesc readbackDesc = {bytes, nrd::rhi::BUFFER_USAGE_COPY_DESTINATION,
                                             nrd::rhi::MemoryLocation::HOST_READBACK, "readback"};
        bool ready = integration.Create(integrationDesc, denoiserDesc) == VK_SUCCESS &&
                     integration.SetMethodSettings(kReferenceId, nrd::ReferenceSettings{}) == nrd::Result::SUCCESS &&
                     CreateTexture(app, "IN_RADIANCE", input) && CreateTexture(app, "OUT_RADIANCE", output) &&
                     app.rhi->CreateBuffer(uploadDesc, upload) == nrd::rhi::Result::SUCCESS &&
                     app.rhi->CreateBuffer(readbackDesc, readback) == nrd::rhi::Result::SUCCESS;

        // Three frames of distinct inputs; the known answers are in the file comment.
        const size_t values = size_t(kWidth) * kHeight * 4;
        std::vector<float> inputs[3];
        for (uint32_t f = 0; f < 3; f++)
        {
            inputs[f].resize(values);
            for (size_t i = 0; i < values; i++)
                inputs[f][i] = float((i * 7 + f * 13) % 29) * 0.25f - 1.0f;
        }
        std::vector<float> expected[3] = {inputs[0], inputs[1], inputs[2]};
        for (size_t i = 0; i < values; i++)
            expected[1][i] = (inputs[0][i] + inputs[1][i]) * 0.5f;

        double worst = 0.0;
        for (uint32_t f = 0; f < 3 && ready; f++)
        {
            nrd::CommonSettings settings = CommonSettingsFor(f);
            if (f == 2)
                settings.accumulationMode = nrd::AccumulationMode::RESTART;
            std::vector<float> result;
            ready = integration.SetCommonSettings(settings) == nrd::Result::SUCCESS &&
                    Frame(app, integration, input, output, *upload, *readback, inputs[f], result);
            double error = ready ? MaxError(result, expected[f]) : INFINITY;
            std::printf("frame %u: max relative error %.3g\n", f, error);
            worst = std::fmax(worst, error);
        }
        if (ready)
        {
            std::printf("REFERENCE on %s, %ux%u: %s\n", app.rhi->GetDesc().adapterName, kWidth, kHeight,
                        worst <= 1e-6 ? "matches the known answer" : "WRONG");
            exitCode = worst <= 1e-6 ? 0 : 1;
        }

        integration.Destroy();
        app.rhi->DestroyBuffer(upload);
        app.rhi->DestroyBuffer(readback);
        app.rhi->DestroyTexture(input.texture);
        app.rhi->DestroyTexture(output.texture);
    }
    app.Destroy();
    return exitCode;
}
