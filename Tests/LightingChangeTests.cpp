// Shaders/Include/LightingChange.glsl (the lighting change record shared by the radiance
// denoisers), run in a compute shader on lavapipe: every update of every record, the moving test,
// and the UNORM8 packing beside a 5-bit value, compared with a CPU evaluation of the documented
// rules; and the documented timing (what starts "moving", how long it lasts), followed on the
// device's own transition table.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include "RHIVulkan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace nrd;

namespace
{
#include "LightingChangeTest.h"
} // namespace

namespace
{

constexpr uint32_t kCaseFloats = 4, kResultFloats = 8;
constexpr uint32_t kRecordMax = 7, kRise = 3, kMoving = 4, kValueLevels = 31;

struct Case
{
    uint32_t record = 0;
    bool isChanged = false;
    float value = 0, channel = 0;
};

std::vector<float> RunOnDevice(lab::VulkanContext& context, const std::vector<Case>& cases)
{
    const uint32_t n = uint32_t(cases.size());
    std::vector<float> input;
    for (const Case& c : cases)
        input.insert(input.end(), {float(c.record), c.isChanged ? 1.0f : 0.0f, c.value, c.channel});
    return test::RunBufferShader(context, g_LightingChangeTest, sizeof(g_LightingChangeTest), "LightingChangeTest", input,
                                 size_t(n) * kResultFloats, n);
}

// The documented rules.
uint32_t Update(uint32_t record, bool isChanged)
{
    return isChanged ? std::min(record + kRise, kRecordMax) : (record > 0 ? record - 1 : 0);
}

uint32_t ChannelLevel(float channel) // UNORM8 level of a channel value (non-finite: 0).
{
    float c = std::isfinite(channel) ? std::min(std::max(channel, 0.0f), 1.0f) : 0.0f;
    return uint32_t(c * 255.0f + 0.5f);
}

uint32_t PackLevel(uint32_t record, float value)
{
    float v = std::isfinite(value) ? std::min(std::max(value, 0.0f), 1.0f) : 0.0f;
    return (std::min(record, kRecordMax) << 5) | uint32_t(v * float(kValueLevels) + 0.5f);
}

} // namespace

TEST_CASE("The lighting change record, its moving test and its UNORM8 packing equal their CPU evaluation", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const float values[] = {0.0f, 0.1f, 1.0f / 3.0f, 0.5f, 0.99f, 1.0f, -1.0f, 2.0f, nan, inf};
    std::vector<Case> cases;
    for (uint32_t record = 0; record <= kRecordMax; record++)
        for (int changed = 0; changed < 2; changed++)
            for (float value : values)
            {
                Case c;
                c.record = record;
                c.isChanged = changed != 0;
                c.value = value;
                cases.push_back(c);
            }
    // Channels to unpack: every UNORM8 level, out of range and non-finite.
    std::vector<float> channels;
    for (uint32_t level = 0; level < 256; level++)
        channels.push_back(float(level) / 255.0f);
    channels.insert(channels.end(), {nan, inf, -inf, -0.5f, 1.5f});
    for (size_t i = 0; i < channels.size(); i++)
    {
        if (i >= cases.size())
            cases.push_back(Case());
        cases[i].channel = channels[i];
    }

    std::vector<float> r = RunOnDevice(*context, cases);
    uint32_t mismatches = 0;
    for (size_t i = 0; i < cases.size(); i++)
    {
        const Case& c = cases[i];
        const float* out = &r[i * kResultFloats];
        uint32_t updated = Update(c.record, c.isChanged);
        uint32_t packed = PackLevel(c.record, c.value);
        uint32_t level = ChannelLevel(c.channel);
        bool ok = out[0] == float(updated) && out[1] == (updated >= kMoving ? 1.0f : 0.0f) &&
                  out[2] == (c.record >= kMoving ? 1.0f : 0.0f);
        // The packed channel is an exact UNORM8 level (storage keeps it), which unpacks to the
        // record and the value rounded to 1 / 31.
        ok = ok && out[3] == float(packed) / 255.0f && ChannelLevel(out[3]) == packed;
        ok = ok && out[4] == float(std::min(c.record, kRecordMax)) &&
             std::fabs(out[5] - float(packed & kValueLevels) / float(kValueLevels)) <= 1e-6f;
        if (std::isfinite(c.value))
            ok = ok && std::fabs(out[5] - std::min(std::max(c.value, 0.0f), 1.0f)) <= 0.5f / float(kValueLevels) + 1e-6f;
        ok = ok && out[6] == float(level >> 5) &&
             std::fabs(out[7] - float(level & kValueLevels) / float(kValueLevels)) <= 1e-6f;
        if (!ok && ++mismatches <= 5)
            WARN("case " << i << ": record " << c.record << " changed " << c.isChanged << " value " << c.value
                         << " channel " << c.channel << " -> " << out[0] << " " << out[1] << " " << out[2] << " "
                         << out[3] << " " << out[4] << " " << out[5] << " " << out[6] << " " << out[7]);
    }
    CHECK(mismatches == 0);
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("The lighting change record moves after two changes at most three frames apart, not after one", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    // The device's transition table: next[record][changed].
    std::vector<Case> cases;
    for (uint32_t record = 0; record <= kRecordMax; record++)
        for (int changed = 0; changed < 2; changed++)
        {
            Case c;
            c.record = record;
            c.isChanged = changed != 0;
            cases.push_back(c);
        }
    std::vector<float> r = RunOnDevice(*context, cases);
    auto next = [&](uint32_t record, bool changed) { return uint32_t(r[(record * 2 + (changed ? 1 : 0)) * kResultFloats]); };
    auto moving = [&](uint32_t record) { return r[record * 2 * kResultFloats + 2] != 0.0f; };

    // One change alone, then none: never moving.
    uint32_t record = next(0, true);
    CHECK_FALSE(moving(record));
    for (int frame = 0; frame < 8; frame++)
    {
        record = next(record, false);
        CHECK_FALSE(moving(record));
    }
    // A second change 1, 2 or 3 frames after the first starts it; 4 or more frames after, not.
    for (int gap = 1; gap <= 6; gap++)
    {
        INFO("gap " << gap);
        record = next(0, true);
        for (int frame = 1; frame < gap; frame++)
            record = next(record, false);
        record = next(record, true);
        CHECK(moving(record) == (gap <= 3));
    }
    // Changes every fourth frame keep it moving on those frames.
    record = next(next(0, true), true);
    for (int period = 0; period < 4; period++)
    {
        for (int frame = 1; frame < 4; frame++)
            record = next(record, false);
        record = next(record, true);
        CHECK(moving(record));
    }
    // From the cap, it lasts 3 frames after the last change found.
    record = kRecordMax;
    for (int frame = 1; frame <= 4; frame++)
    {
        record = next(record, false);
        CHECK(moving(record) == (frame <= 3));
    }
    CHECK(context->ValidationMessageCount() == 0);
}
