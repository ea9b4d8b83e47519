// _NRD_Fp16Converge (Shaders/Include/Common.glsl), run in a compute shader on the default Vulkan
// device: a blend of an fp16 history towards a target by less than one fp16 step (which a store
// could round back onto the history) moves it one fp16 step towards the target, and any other
// blend is returned as it is; a history blended towards a constant fp16 target frame after frame
// then reaches it exactly, where storing the blend as it is can leave it short (the case of SIGMA's
// temporal stabilization: a lit pixel's history of 1 - 2^-11 under a weight of 5/6 stays there).
// _NRD_NearestFp16 (the shadow denoisers' outputs) rounds to the nearest fp16 value.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include "RHIVulkan.h"

#include <cmath>
#include <cstring>
#include <vector>

using namespace nrd;

namespace
{
#include "Fp16ConvergeTest.h"
} // namespace

namespace
{

constexpr uint32_t kCaseFloats = 4, kResultFloats = 5;

struct Case
{
    float x, history, target, weight;
};

// The fp16 neighbours of an fp16 value 'h' in (2^-14, 2): h -/+ one step of its binade (the step
// below a power of two is that of the binade below).
float StepUp(float h)
{
    int e = 0;
    std::frexp(h, &e); // h = m 2^e, m in [0.5, 1): the binade [2^(e-1), 2^e) has steps 2^(e-11).
    return h + std::ldexp(1.0f, e - 11);
}
float StepDown(float h)
{
    int e = 0;
    float m = std::frexp(h, &e);
    return h - std::ldexp(1.0f, m == 0.5f ? e - 12 : e - 11);
}

std::vector<float> RunOnDevice(lab::VulkanContext& context, const std::vector<Case>& cases)
{
    std::vector<float> input;
    for (const Case& c : cases)
        input.insert(input.end(), {c.x, c.history, c.target, c.weight});
    return test::RunBufferShader(context, g_Fp16ConvergeTest, sizeof(g_Fp16ConvergeTest), "Fp16ConvergeTest", input,
                                 cases.size() * kResultFloats, uint32_t(cases.size()));
}

} // namespace

TEST_CASE("_NRD_Fp16Converge moves a history that an fp16 store could keep one step towards the target", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const float one = 1.0f, belowOne = StepDown(1.0f), half = 0.5f, quarter = 0.25f, third = 0.333251953125f; // fp16 values
    std::vector<Case> cases;
    std::vector<float> expected;
    auto add = [&](float x, float history, float target, float result)
    {
        cases.push_back({x, history, target, 5.0f / 6.0f});
        expected.push_back(result);
    };
    for (float h : {belowOne, half, quarter, third, 0.75f})
    {
        float up = StepUp(h), down = StepDown(h);
        // A step of a fifth of an fp16 step (rounds back onto the history whatever the rounding mode):
        // one step towards the target instead.
        add(h + 0.2f * (up - h), h, one, up);
        add(h - 0.2f * (h - down), h, 0.0f, down);
        // Three quarters of a step: one step on (a store rounding towards zero would keep the history).
        add(h + 0.75f * (up - h), h, one, up);
        add(h - 0.75f * (h - down), h, 0.0f, down);
        // A whole step, and no step: as it is (fp16 holds it).
        add(up, h, one, up);
        add(down, h, 0.0f, down);
        add(h, h, h, h);
    }
    std::vector<float> r = RunOnDevice(*context, cases);
    for (size_t i = 0; i < cases.size(); i++)
    {
        INFO("x " << cases[i].x << " history " << cases[i].history << " target " << cases[i].target);
        CHECK(r[i * kResultFloats] == expected[i]);
    }
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("An fp16 history blended towards a constant target reaches it exactly with _NRD_Fp16Converge", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    // Histories blended by 5/6 (SIGMA's history of 5 frames) and 31/32 towards targets that fp16 holds.
    std::vector<Case> cases;
    for (float weight : {5.0f / 6.0f, 31.0f / 32.0f})
        for (float start : {0.0f, 0.5f, 1.0f, 0.998046875f})
            for (float target : {1.0f, 0.0f, 0.5f, 0.333251953125f, 0.0009765625f})
                cases.push_back({0.0f, start, target, weight});
    std::vector<float> r = RunOnDevice(*context, cases);
    uint32_t shortWithout = 0;
    for (size_t i = 0; i < cases.size(); i++)
    {
        const Case& c = cases[i];
        INFO("start " << c.history << " target " << c.target << " weight " << c.weight << ": " << r[i * kResultFloats + 1]
                      << " after 1024 frames (frame " << r[i * kResultFloats + 3] << "), " << r[i * kResultFloats + 2]
                      << " stored as blended");
        CHECK(r[i * kResultFloats + 1] == c.target);
        shortWithout += r[i * kResultFloats + 2] != c.target;
    }
    // Stored as blended, some histories stop short of the target (the test above would fail without the helper).
    INFO("histories short of their target without _NRD_Fp16Converge: " << shortWithout << " of " << cases.size());
    CHECK(shortWithout > 0);
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("_NRD_NearestFp16 gives the fp16 value nearest to its argument", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    std::vector<Case> cases;
    std::vector<float> expected;
    auto add = [&](float x, float nearest)
    {
        cases.push_back({x, 0.0f, 0.0f, 0.0f});
        expected.push_back(nearest);
    };
    // Between fp16 neighbours, in several binades (1 - 2^-11 and 1 straddle a power of two): a fifth,
    // two fifths, three fifths and nine tenths of the way up, and the ends themselves; negated too.
    for (float h : {StepDown(1.0f), 0.5f, 0.25f, 0.333251953125f, 0.75f, StepDown(0.5f), 1.5f})
    {
        float up = StepUp(h);
        for (float sign : {1.0f, -1.0f})
        {
            add(sign * (h + 0.2f * (up - h)), sign * h);
            add(sign * (h + 0.4f * (up - h)), sign * h);
            add(sign * (h + 0.6f * (up - h)), sign * up);
            add(sign * (h + 0.9f * (up - h)), sign * up);
            add(sign * h, sign * h);
            add(sign * up, sign * up);
        }
    }
    // A filter's lit pixel a few fp32 ulps under 1, and 0 and tiny values (fp16's smallest subnormal
    // is 2^-24).
    add(0.99997f, 1.0f);
    add(1.0f - 1e-7f, 1.0f);
    add(0.0f, 0.0f);
    add(1e-9f, 0.0f);
    add(std::ldexp(1.0f, -24) * 0.9f, std::ldexp(1.0f, -24));
    std::vector<float> r = RunOnDevice(*context, cases);
    for (size_t i = 0; i < cases.size(); i++)
    {
        INFO("x " << cases[i].x);
        CHECK(r[i * kResultFloats + 4] == expected[i]);
    }
    CHECK(context->ValidationMessageCount() == 0);
}
