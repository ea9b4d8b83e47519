// Shaders/Include/Reprojection.glsl (history reprojection shared by the radiance and shadow
// denoisers) equals a CPU evaluation of the same formulas on random cases: footprint, per-tap
// disocclusion, bilinear and Catmull-Rom history fetches, specular virtual motion, history length
// packing.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include "RHIVulkan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace
{
#include "ReprojectionTest.h"
} // namespace

using namespace nrd;

namespace
{

constexpr uint32_t kHeader = 5;
constexpr uint32_t kCaseInputs = 5;
constexpr uint32_t kCaseOutputs = 8;
constexpr int kSize = 8; // History texture size.

typedef std::array<float, 4> Vec4;

struct Case
{
    float uv[2], expectedViewZ, viewZ;
    float NoV, threshold, projectY, roughness;
    Vec4 prevViewZ;
    float X[3], hitDist;
    float motion[3], packedLength;
};

// CPU mirror of Reprojection.glsl.
Vec4 BilinearWeights(float fx, float fy)
{
    return {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
}

Vec4 CatmullRomWeights(float t)
{
    return {t * (-0.5f + t * (1.0f - 0.5f * t)), 1.0f + t * t * (-2.5f + 1.5f * t), t * (0.5f + t * (2.0f - 1.5f * t)),
            t * t * (-0.5f + 0.5f * t)};
}

float Tolerance(float viewZ, float expectedViewZ, float NoV, float threshold, float projectY)
{
    float tanTheta = std::min(std::sqrt(std::max(1.0f - NoV * NoV, 0.0f)) / std::max(NoV, 0.05f), 5.0f);
    return threshold * std::fabs(expectedViewZ) + std::fabs(viewZ) / std::max(projectY, 1e-6f) * tanTheta;
}

void Project(const float* m, const float* X, float* uv)
{
    float clip[4];
    for (int row = 0; row < 4; row++)
        clip[row] = m[0 * 4 + row] * X[0] + m[1 * 4 + row] * X[1] + m[2 * 4 + row] * X[2] + m[3 * 4 + row];
    if (!(clip[3] > 1e-6f))
    {
        uv[0] = uv[1] = -1.0f;
        return;
    }
    uv[0] = clip[0] / clip[3] * 0.5f + 0.5f;
    uv[1] = clip[1] / clip[3] * 0.5f + 0.5f;
}

float DominantFactor(float r)
{
    r = std::min(std::max(r, 0.0f), 1.0f);
    float s = 1.0f - r;
    return s * (std::sqrt(s) + r);
}

void VirtualUv(const float* m, const float* cameraPos, const Case& c, float* uv)
{
    float V[3] = {c.X[0] - cameraPos[0], c.X[1] - cameraPos[1], c.X[2] - cameraPos[2]};
    float len = std::sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
    float d = std::max(c.hitDist * DominantFactor(c.roughness), 0.0f) / len;
    float P[3];
    for (int i = 0; i < 3; i++)
        P[i] = c.X[i] + V[i] * d + c.motion[i];
    Project(m, P, uv);
}

} // namespace

TEST_CASE("Reprojection helpers equal a CPU evaluation", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    {
        rhi::Device& device = context->GetDevice();

        // Previous camera at (0.3, -0.2, -1) looking along +z, perspective with w = z (no rotation
        // needed: the helpers only see the matrix).
        const float cameraPos[3] = {0.1f, 0.05f, -0.5f};
        const float camPrev[3] = {0.3f, -0.2f, -1.0f};
        float m[16] = {};
        m[0 * 4 + 0] = 1.2f;
        m[1 * 4 + 1] = -1.4f;
        m[2 * 4 + 2] = 1.001f;
        m[2 * 4 + 3] = 1.0f;
        m[3 * 4 + 2] = -0.1f;
        m[3 * 4 + 0] = -1.2f * camPrev[0];
        m[3 * 4 + 1] = 1.4f * camPrev[1];
        m[3 * 4 + 2] += -1.001f * camPrev[2];
        m[3 * 4 + 3] = -camPrev[2];

        std::mt19937 rng(1313);
        std::uniform_real_distribution<float> u01(0.0f, 1.0f);
        const uint32_t caseNum = 1024;
        std::vector<Case> cases(caseNum);
        for (uint32_t i = 0; i < caseNum; i++)
        {
            Case& c = cases[i];
            c.uv[0] = -0.15f + 1.3f * u01(rng);
            c.uv[1] = -0.15f + 1.3f * u01(rng);
            if (i == 7)
                c.uv[0] = std::numeric_limits<float>::quiet_NaN();
            if (i == 8)
                c.uv[1] = std::numeric_limits<float>::infinity();
            if (i == 9)
                c.uv[0] = 1e30f;
            // A still view's reprojection: texel centres off by a rounding (or by more than the snap).
            if (i % 16 == 11)
            {
                for (int a = 0; a < 2; a++)
                {
                    float offset = (i % 32 == 11 ? 3e-4f : 0.02f) * (u01(rng) < 0.5f ? -1.0f : 1.0f);
                    c.uv[a] = (std::floor(u01(rng) * kSize) + 0.5f + offset) / kSize;
                }
            }
            c.viewZ = 0.5f + 20.0f * u01(rng);
            c.expectedViewZ = c.viewZ * (0.9f + 0.2f * u01(rng));
            c.NoV = u01(rng);
            c.threshold = 0.005f + 0.02f * u01(rng);
            c.projectY = 4.0f + 200.0f * u01(rng);
            c.roughness = u01(rng);
            float tolerance = Tolerance(c.viewZ, c.expectedViewZ, c.NoV, c.threshold, c.projectY);
            for (int k = 0; k < 4; k++)
            {
                // Clearly inside or clearly outside the tolerance (or NaN), so float differences
                // between the CPU and the GPU cannot flip a tap.
                float pick = u01(rng);
                float factor = pick < 0.8f ? (u01(rng) * 1.6f - 0.8f) : (1.25f + 2.0f * u01(rng)) * (pick < 0.9f ? 1 : -1);
                c.prevViewZ[k] = pick > 0.97f ? std::numeric_limits<float>::quiet_NaN() : c.expectedViewZ + tolerance * factor;
            }
            c.X[0] = -3.0f + 6.0f * u01(rng);
            c.X[1] = -3.0f + 6.0f * u01(rng);
            c.X[2] = 2.0f + 8.0f * u01(rng);
            c.hitDist = i % 5 == 0 ? 0.0f : 10.0f * u01(rng);
            for (int k = 0; k < 3; k++)
                c.motion[k] = i % 3 == 0 ? 0.0f : 0.2f * u01(rng) - 0.1f;
            c.packedLength = u01(rng);
        }

        std::vector<float> caseData;
        caseData.insert(caseData.end(), m, m + 16);
        caseData.insert(caseData.end(), {cameraPos[0], cameraPos[1], cameraPos[2], float(kSize)});
        for (const Case& c : cases)
        {
            caseData.insert(caseData.end(), {c.uv[0], c.uv[1], c.expectedViewZ, c.viewZ});
            caseData.insert(caseData.end(), {c.NoV, c.threshold, c.projectY, c.roughness});
            caseData.insert(caseData.end(), c.prevViewZ.begin(), c.prevViewZ.end());
            caseData.insert(caseData.end(), {c.X[0], c.X[1], c.X[2], c.hitDist});
            caseData.insert(caseData.end(), {c.motion[0], c.motion[1], c.motion[2], c.packedLength});
        }
        REQUIRE(caseData.size() == (kHeader + caseNum * kCaseInputs) * 4);

        // History: random values with a few non-finite texels (sanitized to 0 by the fetches).
        std::vector<float> history = test::RandomFloats(kSize * kSize * 4, 1314, -1.0f, 4.0f);
        history[5 * 4 + 2] = std::numeric_limits<float>::quiet_NaN();
        history[20 * 4 + 0] = std::numeric_limits<float>::infinity();
        // Previous viewZ of the texels (the footprint's own taps come with each case): depths around
        // the middle of the cases' range, so that Catmull-Rom's outer taps are valid for some
        // cases, invalid for others, and a mix for the rest.
        std::vector<float> prevViewZ = test::RandomFloats(kSize * kSize, 1315, 8.0f, 12.0f);

        lab::LabTexture historyTexture, viewZTexture;
        REQUIRE(context->CreateTexture(rhi::Format::RGBA32_SFLOAT, kSize, kSize, "history", historyTexture) == VK_SUCCESS);
        REQUIRE(context->CreateTexture(rhi::Format::R32_SFLOAT, kSize, kSize, "prev viewZ", viewZTexture) == VK_SUCCESS);
        REQUIRE(context->UploadTexture(historyTexture, history.data()) == VK_SUCCESS);
        REQUIRE(context->UploadTexture(viewZTexture, prevViewZ.data()) == VK_SUCCESS);

        rhi::Buffer* caseBuffer = nullptr;
        rhi::Buffer* resultBuffer = nullptr;
        rhi::BufferDesc desc = {};
        desc.size = caseData.size() * sizeof(float);
        desc.usage = rhi::BUFFER_USAGE_STORAGE;
        desc.location = rhi::MemoryLocation::HOST_UPLOAD;
        REQUIRE(device.CreateBuffer(desc, caseBuffer) == rhi::Result::SUCCESS);
        std::memcpy(device.MapBuffer(*caseBuffer), caseData.data(), caseData.size() * sizeof(float));
        desc.size = caseNum * kCaseOutputs * 4 * sizeof(float);
        desc.location = rhi::MemoryLocation::HOST_READBACK;
        REQUIRE(device.CreateBuffer(desc, resultBuffer) == rhi::Result::SUCCESS);

        rhi::Sampler* sampler = nullptr;
        REQUIRE(device.CreateSampler(rhi::SamplerDesc{}, sampler) == rhi::Result::SUCCESS);

        rhi::DescriptorBindingDesc bindings0[] = {{0, rhi::DescriptorType::SAMPLED_TEXTURE, 1, nullptr},
                                                  {1, rhi::DescriptorType::SAMPLED_TEXTURE, 1, nullptr},
                                                  {2, rhi::DescriptorType::BUFFER, 1, nullptr},
                                                  {3, rhi::DescriptorType::STORAGE_BUFFER, 1, nullptr}};
        rhi::DescriptorBindingDesc bindings1[] = {{0, rhi::DescriptorType::SAMPLER, 1, &sampler}};
        rhi::DescriptorSetDesc sets[] = {{bindings0, 4}, {bindings1, 1}};
        rhi::ComputePipelineDesc pipelineDesc = {};
        pipelineDesc.spirv = g_ReprojectionTest;
        pipelineDesc.spirvSize = sizeof(g_ReprojectionTest);
        pipelineDesc.sets = sets;
        pipelineDesc.setsNum = 2;
        pipelineDesc.pushConstantsSize = 4;
        pipelineDesc.name = "ReprojectionTest";
        rhi::Pipeline* pipeline = nullptr;
        REQUIRE(device.CreateComputePipeline(pipelineDesc, pipeline) == rhi::Result::SUCCESS);

        rhi::DescriptorPoolDesc poolDesc = {};
        poolDesc.setsMaxNum = 2;
        poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::SAMPLED_TEXTURE] = 2;
        poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::BUFFER] = 1;
        poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_BUFFER] = 1;
        poolDesc.descriptorsMaxNum[(size_t)rhi::DescriptorType::SAMPLER] = 1;
        rhi::DescriptorPool* pool = nullptr;
        REQUIRE(device.CreateDescriptorPool(poolDesc, pool) == rhi::Result::SUCCESS);
        rhi::DescriptorSet* set0 = nullptr;
        rhi::DescriptorSet* set1 = nullptr;
        REQUIRE(device.AllocateDescriptorSet(*pool, *pipeline, 0, set0) == rhi::Result::SUCCESS);
        REQUIRE(device.AllocateDescriptorSet(*pool, *pipeline, 1, set1) == rhi::Result::SUCCESS);
        rhi::DescriptorWrite writes[4] = {};
        writes[0].type = rhi::DescriptorType::SAMPLED_TEXTURE;
        writes[0].texture = historyTexture.texture;
        writes[1].binding = 1;
        writes[1].type = rhi::DescriptorType::SAMPLED_TEXTURE;
        writes[1].texture = viewZTexture.texture;
        writes[2].binding = 2;
        writes[2].type = rhi::DescriptorType::BUFFER;
        writes[2].buffer = caseBuffer;
        writes[3].binding = 3;
        writes[3].type = rhi::DescriptorType::STORAGE_BUFFER;
        writes[3].buffer = resultBuffer;
        device.UpdateDescriptorSet(*set0, writes, 4);

        VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
        REQUIRE(context->BeginCommands(commandBuffer) == VK_SUCCESS);
        rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
        device.CmdBindPipeline(cmd, *pipeline);
        device.CmdBindDescriptorSet(cmd, *pipeline, 0, *set0);
        device.CmdBindDescriptorSet(cmd, *pipeline, 1, *set1);
        device.CmdPushConstants(cmd, *pipeline, &caseNum, sizeof(caseNum));
        device.CmdDispatch(cmd, (caseNum + 63) / 64, 1, 1);
        // RAW: the host reads what the shader wrote.
        rhi::BufferBarrier toHost = {resultBuffer, rhi::ACCESS_SHADER_READ_WRITE, rhi::ACCESS_HOST_READ};
        device.CmdBarrier(cmd, {nullptr, 0, &toHost, 1, nullptr, 0});
        REQUIRE(context->SubmitAndWait(commandBuffer) == VK_SUCCESS);

        std::vector<float> actual(caseNum * kCaseOutputs * 4);
        std::memcpy(actual.data(), device.MapBuffer(*resultBuffer), actual.size() * sizeof(float));

        // CPU evaluation.
        auto historyAt = [&](int x, int y, int ch) {
            float v = history[(size_t(y) * kSize + x) * 4 + ch];
            return std::isfinite(v) ? v : 0.0f;
        };
        std::vector<float> expected(actual.size(), 0.0f);
        uint32_t catmullRomCases = 0, partialCases = 0, disoccludedCases = 0, parallaxCases = 0;
        uint32_t wholeCatmullRomCases = 0, mixedCatmullRomCases = 0; // All outer taps valid; some.
        uint32_t snappedCases = 0;
        for (uint32_t i = 0; i < caseNum; i++)
        {
            const Case& c = cases[i];
            float* e = &expected[size_t(i) * kCaseOutputs * 4];
            float tolerance = Tolerance(c.viewZ, c.expectedViewZ, c.NoV, c.threshold, c.projectY);
            bool isFinite = std::isfinite(c.uv[0]) && std::isfinite(c.uv[1]);
            float uvx = isFinite ? c.uv[0] : -1.0f, uvy = isFinite ? c.uv[1] : -1.0f;
            float px = uvx * kSize - 0.5f, py = uvy * kSize - 0.5f;
            // Within NRD_FOOTPRINT_SNAP (1/512) of a texel's centre: that texel.
            bool isSnapped = false;
            for (float* p : {&px, &py})
            {
                float r = std::floor(*p + 0.5f);
                if (std::fabs(*p - r) < 1.0f / 512.0f)
                {
                    isSnapped = isSnapped || *p != r;
                    *p = r;
                }
            }
            float ox = std::floor(px), oy = std::floor(py);
            float fx = px - ox, fy = py - oy;
            int originX = int(std::min(std::max(ox, -65536.0f), 65536.0f));
            int originY = int(std::min(std::max(oy, -65536.0f), 65536.0f));
            Vec4 bilinear = BilinearWeights(fx, fy);
            Vec4 weights;
            float footprintWeight = 0.0f;
            bool allValid = true;
            for (int k = 0; k < 4; k++)
            {
                int x = originX + (k & 1), y = originY + (k >> 1);
                bool valid = x >= 0 && x < kSize && y >= 0 && y < kSize &&
                             std::fabs(c.prevViewZ[k] - c.expectedViewZ) <= tolerance;
                weights[k] = valid ? bilinear[k] : 0.0f;
                footprintWeight += weights[k];
                allValid = allValid && valid;
            }
            std::copy(weights.begin(), weights.end(), e);
            e[4] = footprintWeight;
            e[5] = allValid ? 1.0f : 0.0f;
            e[6] = tolerance;
            e[7] = float(originX);
            for (int ch = 0; ch < 4; ch++)
            {
                float sum = 0.0f;
                for (int k = 0; k < 4; k++)
                {
                    if (weights[k] > 0.0f)
                        sum += historyAt(originX + (k & 1), originY + (k >> 1), ch) * weights[k];
                }
                e[8 + ch] = footprintWeight > 0.0f ? sum / footprintWeight : 0.0f;
            }
            // Catmull-Rom's outer taps (bit 4 j + t of the 4x4 footprint, corners and inner 2x2 left
            // out) whose previous viewZ is within twice the tolerance; the others read the inner tap
            // next to them.
            uint32_t outerTaps = 0;
            for (int j = 0; j < 4; j++)
                for (int t = 0; t < 4; t++)
                {
                    if (((t == 0 || t == 3) ? 1 : 0) + ((j == 0 || j == 3) ? 1 : 0) != 1)
                        continue;
                    int x = std::min(std::max(originX + t - 1, 0), kSize - 1);
                    int y = std::min(std::max(originY + j - 1, 0), kSize - 1);
                    if (std::fabs(prevViewZ[size_t(y) * kSize + x] - c.expectedViewZ) <= 2.0f * tolerance)
                        outerTaps |= 1u << (4 * j + t);
                }
            e[31] = float(outerTaps);
            if (allValid)
            {
                Vec4 wx = CatmullRomWeights(fx), wy = CatmullRomWeights(fy);
                for (int ch = 0; ch < 4; ch++)
                {
                    float sum = 0.0f, weightSum = 0.0f;
                    for (int j = 0; j < 4; j++)
                    {
                        for (int t = 0; t < 4; t++)
                        {
                            if ((t == 0 || t == 3) && (j == 0 || j == 3))
                                continue;
                            bool outer = t == 0 || t == 3 || j == 0 || j == 3;
                            bool replaced = outer && (outerTaps & (1u << (4 * j + t))) == 0;
                            int tx = replaced ? std::min(std::max(t, 1), 2) : t, ty = replaced ? std::min(std::max(j, 1), 2) : j;
                            int x = std::min(std::max(originX + tx - 1, 0), kSize - 1);
                            int y = std::min(std::max(originY + ty - 1, 0), kSize - 1);
                            sum += historyAt(x, y, ch) * wx[t] * wy[j];
                            weightSum += wx[t] * wy[j];
                        }
                    }
                    e[12 + ch] = sum / weightSum;
                }
            }
            float uvVirtual[2], uvSurface[2];
            VirtualUv(m, cameraPos, c, uvVirtual);
            float surface[3] = {c.X[0] + c.motion[0], c.X[1] + c.motion[1], c.X[2] + c.motion[2]};
            Project(m, surface, uvSurface);
            e[16] = uvVirtual[0];
            e[17] = uvVirtual[1];
            e[18] = DominantFactor(c.roughness);
            e[19] = std::hypot((uvVirtual[0] - uvSurface[0]) * kSize, (uvVirtual[1] - uvSurface[1]) * kSize);
            Vec4 crx = CatmullRomWeights(fx);
            std::copy(crx.begin(), crx.end(), e + 20);
            for (int k = 0; k < 4; k++)
            {
                int x = originX + (k & 1), y = originY + (k >> 1);
                bool inside = x >= 0 && x < kSize && y >= 0 && y < kSize;
                e[24 + k] = inside ? prevViewZ[size_t(y) * kSize + x] : -1.0f;
            }
            e[28] = std::floor(c.packedLength * 255.0f + 0.5f);
            e[29] = std::min(std::max(c.packedLength * 300.0f, 0.0f), 255.0f) / 255.0f;
            e[30] = float(originY);

            catmullRomCases += allValid ? 1 : 0;
            wholeCatmullRomCases += allValid && outerTaps == 0x6996u ? 1 : 0;
            mixedCatmullRomCases += allValid && outerTaps != 0x6996u && outerTaps != 0 ? 1 : 0;
            partialCases += !allValid && footprintWeight > 0.0f ? 1 : 0;
            disoccludedCases += footprintWeight == 0.0f ? 1 : 0;
            parallaxCases += e[19] > 0.1f ? 1 : 0;
            snappedCases += isSnapped ? 1 : 0;
        }
        std::printf("reprojection cases: %u Catmull-Rom (%u with every outer tap, %u with some), %u partial, %u disoccluded, "
                    "%u with parallax, %u snapped to a texel\n",
                    catmullRomCases, wholeCatmullRomCases, mixedCatmullRomCases, partialCases, disoccludedCases, parallaxCases,
                    snappedCases);
        // The random cases reach every branch.
        CHECK(catmullRomCases >= 20);
        CHECK(wholeCatmullRomCases >= 5);
        CHECK(mixedCatmullRomCases >= 5);
        CHECK(partialCases >= 20);
        CHECK(disoccludedCases >= 20);
        CHECK(parallaxCases >= 20);
        CHECK(snappedCases >= 20);
        CHECK(test::CountMismatches(actual, expected, 2e-5f, 2e-4f) == 0);

        device.DestroyDescriptorPool(pool);
        device.DestroyPipeline(pipeline);
        device.DestroySampler(sampler);
        device.DestroyBuffer(caseBuffer);
        device.DestroyBuffer(resultBuffer);
        context->DestroyTexture(historyTexture);
        context->DestroyTexture(viewZTexture);
    }
    CHECK(context->ValidationMessageCount() == 0);
}
