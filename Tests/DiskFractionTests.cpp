// _NRD_DiskFractionBeyondChord (Shaders/Include/Common.glsl), run in a compute shader on the default
// Vulkan device: the part of a light's disk above a surface's tangent plane, which the shadow
// denoisers use on the light's terminator (_NRD_ShadowMotion_HorizonVisibility). Compared with a
// count of directions inside the light's cone that lie above the plane (the definition, without the
// small-angle reduction to a chord), with its exact ends and symmetry, and with non-finite offsets.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include "RHIVulkan.h"

#include <cmath>
#include <limits>
#include <vector>

using namespace nrd;

namespace
{
#include "DiskFractionTest.h"
} // namespace

namespace
{

std::vector<float> RunOnDevice(lab::VulkanContext& context, const std::vector<float>& offsets)
{
    return test::RunBufferShader(context, g_DiskFractionTest, sizeof(g_DiskFractionTest), "DiskFractionTest", offsets,
                                 offsets.size(), uint32_t(offsets.size()));
}

// Fraction of the directions within 'radius' (radians) of the light's direction that lie above the
// plane whose normal makes the angle 'angle' (radians) with it: a polar grid over the cone, each cell
// weighted by its solid angle.
double ConeFractionAbovePlane(double radius, double angle)
{
    const int rings = 400, sectors = 800;
    const double pi = 3.14159265358979323846;
    // Light along +z; the normal in the x-z plane.
    double nx = std::sin(angle), nz = std::cos(angle);
    double above = 0.0, total = 0.0;
    for (int r = 0; r < rings; r++)
    {
        double theta = radius * (double(r) + 0.5) / double(rings);
        double solidAngle = std::sin(theta); // Per unit of theta and phi.
        for (int s = 0; s < sectors; s++)
        {
            double phi = 2.0 * pi * (double(s) + 0.5) / double(sectors);
            double dx = std::sin(theta) * std::cos(phi), dz = std::cos(theta);
            total += solidAngle;
            above += dx * nx + dz * nz > 0.0 ? solidAngle : 0.0;
        }
    }
    return above / total;
}

} // namespace

TEST_CASE("The fraction of a light's disk above a tangent plane matches the directions counted in its cone", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const double pi = 3.14159265358979323846;
    struct Light
    {
        double radiusDegrees, tolerance;
    };
    // The chord reduction (x = cos / sin of the radius) is exact for a small disk: 0.00003 and 0.00006
    // off the count for the sun and a 1.5-degree light, 0.0004 for a 5-degree one, 0.0016 for 10.
    const Light lights[] = {{0.27, 0.001}, {1.5, 0.001}, {5.0, 0.002}, {10.0, 0.004}};
    std::vector<float> offsets;
    std::vector<double> expected, tolerance;
    for (const Light& light : lights)
    {
        double radius = light.radiusDegrees * pi / 180.0;
        for (int k = -12; k <= 12; k++)
        {
            // Angles from the normal to the light's direction that put it across the plane: 90 degrees
            // +- up to 1.2 light radii.
            double angle = 0.5 * pi + radius * double(k) / 10.0;
            offsets.push_back(float(std::cos(angle) / std::sin(radius)));
            expected.push_back(ConeFractionAbovePlane(radius, angle));
            tolerance.push_back(light.tolerance);
        }
    }
    std::vector<float> r = RunOnDevice(*context, offsets);
    uint32_t mismatches = 0;
    for (size_t i = 0; i < offsets.size(); i++)
    {
        if (!(std::fabs(double(r[i]) - expected[i]) <= tolerance[i]) && ++mismatches <= 5)
            WARN("offset " << offsets[i] << ": " << r[i] << ", counted " << expected[i]);
    }
    CHECK(mismatches == 0);
    CHECK(context->ValidationMessageCount() == 0);
}

TEST_CASE("The disk fraction is 0, a half and 1 at the ends and the centre, symmetric, and finite for any offset", "[vulkan]")
{
    auto context = test::CreateValidatedContext();
    REQUIRE(context);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<float> offsets = {-1.0f, 0.0f, 1.0f, -2.0f, 7.0f, -inf, inf, nan};
    for (int k = 1; k < 20; k++)
        offsets.insert(offsets.end(), {float(k) / 20.0f, -float(k) / 20.0f});
    std::vector<float> r = RunOnDevice(*context, offsets);
    CHECK(r[0] == 0.0f);
    CHECK(std::fabs(r[1] - 0.5f) <= 1e-6f);
    CHECK(r[2] == 1.0f);
    CHECK(r[3] == 0.0f);
    CHECK(r[4] == 1.0f);
    CHECK(r[5] == 0.0f);
    CHECK(r[6] == 1.0f);
    CHECK(std::fabs(r[7] - 0.5f) <= 1e-6f); // NaN: the plane through the light's centre.
    float previous = 0.5f;
    for (int k = 1; k < 20; k++)
    {
        float up = r[8 + 2 * (k - 1)], down = r[9 + 2 * (k - 1)];
        INFO("offset +-" << float(k) / 20.0f);
        CHECK(std::fabs(up + down - 1.0f) <= 2e-6f);
        CHECK(up > previous); // Increasing.
        previous = up;
    }
    CHECK(context->ValidationMessageCount() == 0);
}
