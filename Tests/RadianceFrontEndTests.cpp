// The radiance + hit distance helpers of Shaders/Include/NRD.glsl (REBLUR_FrontEnd_GetNormHitDist,
// REBLUR_FrontEnd_PackRadianceAndNormHitDist, REBLUR_BackEnd_UnpackRadianceAndNormHitDist,
// NRD_GetCorrectedHitDist) and the private de-normalization of Common.glsl, run in a compute shader
// on lavapipe and compared with a CPU evaluation of their documented behaviour, NaN / Inf included.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include "RHIVulkan.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

using namespace nrd;

namespace
{
#include "RadianceFrontEndTest.h"
} // namespace

namespace
{

constexpr float kFp16Max = 65504.0f;
constexpr uint32_t kCaseFloats = 16, kResultFloats = 12;

struct Case
{
    float hitDist = 0, viewZ = 1, roughness = 1;
    bool sanitize = true;
    HitDistanceParameters params;
    float texel[4] = {};
    float bounceIndex = 1, roughnessAlongPath = 0, importance = 1;
};

float Sanitize(float x, float replacement) { return std::isfinite(x) ? x : replacement; }
float Saturate(float x) { return std::min(std::max(x, 0.0f), 1.0f); }

// The documented normalization: (A + |viewZ| B) * lerp(1, C, saturate(exp2(D roughness^2))).
double Normalization(const Case& c)
{
    double z = std::fabs(double(Sanitize(c.viewZ, 0.0f)));
    double r = Saturate(Sanitize(c.roughness, 1.0f));
    double t = std::min(std::max(std::exp2(double(c.params.D) * r * r), 0.0), 1.0);
    return (double(c.params.A) + z * double(c.params.B)) * (1.0 + (double(c.params.C) - 1.0) * t);
}

double NormHitDist(const Case& c)
{
    double d = std::isnan(c.hitDist) ? 0.0 : std::max(double(c.hitDist), 0.0);
    return d >= kFp16Max ? 1.0 : std::min(std::max(d / Normalization(c), 0.0), 1.0);
}

double CorrectedHitDist(const Case& c)
{
    double d = std::isnan(c.hitDist) ? 0.0 : std::min(std::max(double(c.hitDist), 0.0), double(kFp16Max));
    double later = std::max(double(Sanitize(c.bounceIndex, 1.0f)) - 1.0, 0.0);
    double m = std::min(std::max(double(Sanitize(c.roughnessAlongPath, 0.0f)), 0.0), 64.0);
    m *= m;
    double k = 1.0 - std::exp(-m * later);
    double weight = double(Saturate(Sanitize(c.importance, 0.0f))) / (1.0 + later * later * m);
    return weight * d / (1.0 + d * k);
}

void Pack(const Case& c, float out[4])
{
    for (int k = 0; k < 4; k++)
    {
        float v = c.sanitize ? Sanitize(c.texel[k], 0.0f) : c.texel[k];
        out[k] = k < 3 ? std::min(std::max(v, 0.0f), kFp16Max) : Saturate(v);
    }
}

void Unpack(const Case& c, float out[4])
{
    for (int k = 0; k < 3; k++)
        out[k] = std::max(Sanitize(c.texel[k], 0.0f), 0.0f);
    out[3] = Saturate(Sanitize(c.texel[3], 0.0f));
}

// Runs the test shader over 'cases' and returns kResultFloats floats per case.
std::vector<float> RunOnDevice(lab::VulkanContext& context, const std::vector<Case>& cases)
{
    const uint32_t n = uint32_t(cases.size());
    std::vector<float> input(size_t(n) * kCaseFloats, 0.0f);
    for (uint32_t i = 0; i < n; i++)
    {
        const Case& c = cases[i];
        float* p = &input[size_t(i) * kCaseFloats];
        const float values[15] = {c.hitDist,  c.viewZ,    c.roughness, c.sanitize ? 1.0f : 0.0f, c.params.A,
                                  c.params.B, c.params.C, c.params.D,  c.texel[0],               c.texel[1],
                                  c.texel[2], c.texel[3], c.bounceIndex, c.roughnessAlongPath,   c.importance};
        std::memcpy(p, values, sizeof(values));
    }

    return test::RunBufferShader(context, g_RadianceFrontEndTest, sizeof(g_RadianceFrontEndTest), "RadianceFrontEndTest",
                                 input, size_t(n) * kResultFloats, n);
}

bool Close(double actual, double expected)
{
    if (!std::isfinite(actual) || !std::isfinite(expected))
        return false;
    return std::fabs(actual - expected) <= 1e-6 + 2e-5 * std::fabs(expected);
}

} // namespace

TEST_CASE("The normalized hit distance follows the published formula", "[vulkan]")
{
    // Hand-computed values of (A + |viewZ| B) * lerp(1, C, saturate(exp2(D r^2))) with the defaults.
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    std::vector<Case> cases(4);
    cases[0].hitDist = 40.0f; // f = (3 + 0.1 * 10) * 20 = 80 at roughness 0.
    cases[0].viewZ = 10.0f;
    cases[0].roughness = 0.0f;
    cases[1].hitDist = 2.0f; // f = 4 * (1 + 19 * 2^-25) at roughness 1.
    cases[1].viewZ = -10.0f; // |viewZ|.
    cases[1].roughness = 1.0f;
    cases[2].hitDist = 1e9f; // Beyond the range: 1.
    cases[3].hitDist = std::numeric_limits<float>::infinity(); // Miss: 1.
    std::vector<float> r = RunOnDevice(*context, cases);
    CHECK(r[0 * kResultFloats] == Approx(0.5).epsilon(1e-6));
    CHECK(r[1 * kResultFloats] == Approx(2.0 / (4.0 * (1.0 + 19.0 * std::exp2(-25.0)))).epsilon(1e-6));
    CHECK(r[2 * kResultFloats] == 1.0f);
    CHECK(r[3 * kResultFloats] == 1.0f);
    CHECK(r[0 * kResultFloats + 1] == Approx(40.0).epsilon(1e-6)); // De-normalized back.
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("Radiance and hit distance helpers equal their CPU evaluation, NaN and Inf included", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();

    HitDistanceParameters custom;
    custom.A = 1.5f;
    custom.B = 0.0f;
    custom.C = 4.0f;
    custom.D = -8.0f;
    const float hitDists[] = {0.0f, 0.25f, 3.0f, 17.0f, 250.0f, 1e5f, kFp16Max, inf, -inf, nan, -2.0f};
    const float viewZs[] = {0.01f, 5.0f, -40.0f, 3000.0f, inf, nan};
    const float roughnesses[] = {0.0f, 0.2f, 0.5f, 1.0f, 2.0f, nan};
    // Texels to pack and unpack: ordinary, out of range, non-finite (non-finite ones only with sanitize).
    const float texels[][4] = {{0.5f, 1.0f, 2.0f, 0.3f},   {-1.0f, 1e30f, 0.0f, 1.5f}, {1e-40f, 70000.0f, 3.0f, -0.2f},
                               {nan, 1.0f, inf, nan},      {-inf, nan, 2.0f, inf},     {0.0f, 0.0f, 0.0f, 1.0f}};
    const float bounces[] = {1.0f, 2.0f, 3.0f, nan};
    const float pathRoughness[] = {0.0f, 0.5f, 2.0f, inf};
    const float importances[] = {1.0f, 0.3f, 2.0f, nan};

    std::vector<Case> cases;
    uint32_t k = 0;
    for (float hitDist : hitDists)
        for (float viewZ : viewZs)
            for (float roughness : roughnesses)
                for (int p = 0; p < 2; p++)
                {
                    Case c;
                    c.hitDist = hitDist;
                    c.viewZ = viewZ;
                    c.roughness = roughness;
                    if (p)
                        c.params = custom;
                    const float* texel = texels[k % 6];
                    bool finite = std::all_of(texel, texel + 4, [](float v) { return std::isfinite(v); });
                    c.sanitize = !finite || (k / 6) % 2 == 0;
                    std::memcpy(c.texel, texel, sizeof(c.texel));
                    c.bounceIndex = bounces[k % 4];
                    c.roughnessAlongPath = pathRoughness[(k / 4) % 4];
                    c.importance = importances[(k / 16) % 4];
                    cases.push_back(c);
                    k++;
                }

    std::vector<float> r = RunOnDevice(*context, cases);
    uint32_t mismatches = 0;
    for (size_t i = 0; i < cases.size(); i++)
    {
        const Case& c = cases[i];
        const float* out = &r[i * kResultFloats];
        double norm = NormHitDist(c);
        float packed[4], unpacked[4];
        Pack(c, packed);
        Unpack(c, unpacked);
        bool ok = Close(out[0], norm) && out[0] >= 0.0f && out[0] <= 1.0f;
        ok = ok && Close(out[1], double(out[0]) * Normalization(c)); // De-normalization inverts it.
        ok = ok && Close(out[2], CorrectedHitDist(c));
        for (int ch = 0; ch < 4; ch++)
            ok = ok && Close(out[4 + ch], packed[ch]) && Close(out[8 + ch], unpacked[ch]);
        if (!ok && ++mismatches <= 5)
            WARN("case " << i << ": hitDist " << c.hitDist << " viewZ " << c.viewZ << " roughness " << c.roughness
                         << " -> norm " << out[0] << " (expected " << norm << "), hitDist " << out[1] << ", corrected "
                         << out[2] << " (expected " << CorrectedHitDist(c) << "), packed " << out[4] << " " << out[5]
                         << " " << out[6] << " " << out[7] << " (expected " << packed[0] << " " << packed[1] << " "
                         << packed[2] << " " << packed[3] << ")");
    }
    CHECK(mismatches == 0);
    CHECK(context->ValidationMessageCount() == 0);
}
