// The shadow denoisers (SIGMA_SHADOW, TILED_SHADOW) on every built-in scene of the scene lab, at
// several sizes, against issue 20's bar: the output's relMSE and FLIP no higher than the 1-spp
// input's ("do no harm"), and on scenes where something moves an input / output relMSE ratio at
// least half of what perfect temporal reuse reaches (`--bounds`' oracle, ReuseBounds.h).
//
// Every combination meets it. A combination that cannot (a new scene, a new method) goes into
// kShortfalls with its measured relMSE ratio (input / output, 10% below) and FLIP ratio (output /
// input, 10% above), which it then asserts instead, so that it can only improve; a line leaves the
// table when it meets the bar. Each line says where it was measured: lavapipe (CI's device) for 64x64
// and 128x128, lavapipe or the NVIDIA H100 / H200 for 256x256 (lavapipe gives the same relMSE ratios
// within 3.5%, hence the margin). The triangle-mesh scenes are included.
//
// 64x64 and 128x128 in CI (label quality, one test case per scene and size); 256x256 hidden
// (ctest entry nrd_shadow_quality_tests_256, label slow); the executable without arguments runs all three. 24 frames, the first 8 a
// warm-up; the truth takes 32 samples per pixel (as `Samples/Scripts/shadow_table.py`). The frame
// cache makes reruns cheap.
#include <catch2/catch.hpp>

#include "MethodRunner.h"
#include "Scene.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace
{

struct Shortfall
{
    const char* scene;
    const char* method;
    uint32_t size;
    double minRelmseRatio; // relMSE(input) / relMSE(output) at least this.
    double maxFlipRatio;   // FLIP(output) / FLIP(input) at most this.
};

// clang-format off
// (Empty: TILED_SHADOW on mesh_engine at 64x64, FLIP 1.0028x the input's, left it with TS_BORDER_VARIANCE.)
const std::vector<Shortfall> kShortfalls = {
};
// clang-format on

// Relative tolerance of "no higher than the input's" for the rounding of the metrics' sums.
constexpr double kRounding = 1e-4;

const Shortfall* FindShortfall(const std::string& scene, const char* method, uint32_t size)
{
    for (const Shortfall& s : kShortfalls)
        if (scene == s.scene && std::string(method) == s.method && size == s.size)
            return &s;
    return nullptr;
}

// The issue's settings: 24 frames, the first 8 a warm-up, the truth at 32 samples per pixel.
nrdlab::RunOptions IssueRunOptions(const std::string& scene, const char* method, uint32_t size)
{
    nrdlab::RunOptions o;
    o.scene = scene;
    o.method = method;
    o.width = o.height = size;
    o.frames = 24;
    o.warmup = 8;
    o.truthSpp = 32;
    o.keepImages = false;
    return o;
}

// Runs 'method' on 'scene' (a name or inline JSON) with the issue's settings and prints, under
// 'label', the relMSE ratio input / output and the FLIP ratio output / input it returns.
std::pair<double, double> RunRatios(const std::string& scene, const char* method, uint32_t size, const char* label)
{
    nrdlab::RunOptions o = IssueRunOptions(scene, method, size);
    nrdlab::RunReport r;
    std::string error;
    REQUIRE(nrdlab::RunMethod(o, r, error));
    double ratio = r.mean.relmseNoisy / std::max(r.mean.relmseDenoised, 1e-12);
    double flipRatio = r.mean.flipDenoised / r.mean.flipNoisy;
    std::printf("%s %s %ux%u: relMSE ratio %.4f, FLIP %.5f -> %.5f (%.4fx)\n", method, label, size, size, ratio,
                r.mean.flipNoisy, r.mean.flipDenoised, flipRatio);
    return {ratio, flipRatio};
}

void CheckDoNoHarm(const std::string& name, uint32_t size)
{
    nrdlab::Scene scene;
    std::string error;
    REQUIRE(nrdlab::LoadScene(name, scene, error));
    bool moving = nrdlab::IsSceneAnimated(scene); // Still scenes have no oracle bar.
    for (const char* method : {"SIGMA_SHADOW", "TILED_SHADOW"})
    {
        nrdlab::RunOptions o = IssueRunOptions(name, method, size);
        o.bounds = moving;
        nrdlab::RunReport r;
        INFO(name << " " << method << " " << size << "x" << size);
        REQUIRE(nrdlab::RunMethod(o, r, error));
        const nrdlab::FrameMetrics& m = r.mean;
        double ratio = m.relmseNoisy / std::max(m.relmseDenoised, 1e-12);
        double oracleRatio = moving ? m.relmseNoisy / std::max(m.boundOracle, 1e-12) : 0.0;
        const Shortfall* shortfall = FindShortfall(name, method, size);
        std::printf("%-13s %-18s %3u  relMSE ratio %6.3f (oracle %5.2f)  FLIP %.5f -> %.5f (%.5fx)%s\n", method, name.c_str(),
                    size, ratio, oracleRatio, m.flipNoisy, m.flipDenoised, m.flipDenoised / std::max(m.flipNoisy, 1e-12),
                    shortfall ? "  (known shortfall)" : "");
        if (shortfall)
        {
            CHECK(ratio >= shortfall->minRelmseRatio);
            CHECK(m.flipDenoised <= shortfall->maxFlipRatio * m.flipNoisy);
            continue;
        }
        // (Within float rounding: a method that passes its input through must pass.)
        CHECK(m.relmseDenoised <= m.relmseNoisy * (1.0 + kRounding));
        CHECK(m.flipDenoised <= m.flipNoisy * (1.0 + kRounding));
        if (moving)
        {
            REQUIRE(m.boundOracle > 0.0);
            CHECK(ratio >= 0.5 * oracleRatio);
        }
    }
}

// mesh_thin's spider turns over a still floor: its legs' shadows, under half a pixel soft, move without
// motion vectors. Given the light's size, SIGMA_SHADOW places each shadow's occluder and reads its
// motion (Shaders/Include/ShadowMotion.glsl): the output's FLIP stays within 1% of the input's
// (lavapipe: 1.0000x), where without it the history trails the legs (1.47x).
TEST_CASE("SIGMA_SHADOW follows shadows that a moving occluder carries once told the light's size", "[quality]")
{
    double flipRatio[2] = {}, relmseRatio[2] = {};
    for (int isGiven = 0; isGiven < 2; isGiven++)
    {
        nrdlab::RunOptions o = IssueRunOptions("mesh_thin", "SIGMA_SHADOW", 64);
        o.settingsJson = isGiven ? "{}" : "{\"sigma\": {\"isLightSizeGiven\": false}}";
        nrdlab::RunReport r;
        std::string error;
        REQUIRE(nrdlab::RunMethod(o, r, error));
        flipRatio[isGiven] = r.mean.flipDenoised / r.mean.flipNoisy;
        relmseRatio[isGiven] = r.mean.relmseNoisy / std::max(r.mean.relmseDenoised, 1e-12);
    }
    std::printf("SIGMA_SHADOW mesh_thin 64x64: FLIP %.4fx the input's with the light's size, %.4fx without; relMSE "
                "ratio %.3f / %.3f\n", flipRatio[1], flipRatio[0], relmseRatio[1], relmseRatio[0]);
    CHECK(flipRatio[1] <= 1.01);
    CHECK(flipRatio[0] >= 1.2);
    CHECK(relmseRatio[1] >= 0.95);
}

// Two bars 3-4 cm thick sweep 0.3-0.5 m above a floor under a 0.25-degree sun (written to break the
// occluder lookup of Shaders/Include/ShadowMotion.glsl: the bars are thinner than a pixel, their
// tips' shadows one pixel). TILED_SHADOW does no harm at either size (lavapipe: relMSE ratio 1.045 /
// FLIP 0.965x at 64x64, the input exactly at 128x128; before the 3x3 search and the young lit texels
// 0.238 / 1.336x and 0.332 / 1.314x); SIGMA_SHADOW at 64x64 (1.045 / 0.893x), and at 128x128 it stays
// within 0.1% of the input's FLIP (1.0009x: pinned, not yet the bar).
TEST_CASE("Shadow denoisers follow thin bars' shadows sweeping over a floor", "[quality]")
{
    const char* scene = R"({"name": "thin_bars_sweep", "frames": 48, "seed": 1,
        "sky": {"zenith": [0.25, 0.42, 0.8], "horizon": [0.75, 0.82, 0.95], "ground": [0.3, 0.28, 0.25]},
        "camera": {"position": [0.0, 2.4, 5.6], "target": [0.0, 0.5, 0.0], "fov": 45, "near": 0.05},
        "materials": {"floor": {"albedo": [0.7, 0.68, 0.65], "roughness": 0.8}, "white": {"albedo": 0.85, "roughness": 1.0}},
        "objects": [
            {"name": "floor", "type": "plane", "material": "floor"},
            {"name": "bar1", "type": "box", "size": [0.04, 0.04, 2.0], "position": [-2, 0.3, 0], "material": "white",
             "keyframes": [{"frame": 0, "position": [-2.0, 0.3, 0.0]}, {"frame": 47, "position": [2.0, 0.3, 0.0]}]},
            {"name": "bar2", "type": "box", "size": [2.0, 0.03, 0.03], "position": [0, 0.5, -1.5], "material": "white",
             "keyframes": [{"frame": 0, "position": [0.0, 0.5, -1.5], "rotation": [0, 0, 0]},
                           {"frame": 47, "position": [0.0, 0.5, 1.5], "rotation": [0, 90, 0]}]},
            {"name": "cube", "type": "box", "size": [0.6, 0.6, 0.6], "position": [1.2, 0.3, -0.8], "material": "white"}],
        "lights": [{"name": "sun", "type": "sun", "direction": [-0.4, 0.8, 0.3], "angularRadius": 0.25, "intensity": [3, 2.9, 2.7]}]})";
    for (const char* method : {"SIGMA_SHADOW", "TILED_SHADOW"})
    {
        for (uint32_t size : {64u, 128u})
        {
            auto [ratio, flipRatio] = RunRatios(scene, method, size, "thin bars");
            bool isPinned = std::string(method) == "SIGMA_SHADOW" && size == 128;
            CHECK(ratio >= 1.0 - kRounding);
            CHECK(flipRatio <= (isPinned ? 1.002 : 1.0 + kRounding));
        }
    }
}

// The static scene seen by a camera sliding sideways under a 0.4-degree sun (written to break the
// history of pixels that a silhouette uncovers): the floor beside a sphere's trailing edge took its
// history from the texels of the sphere's cast shadow beside it, and TILED_SHADOW output those lit
// pixels at 0.05-0.4 (lavapipe, 128x128: relMSE ratio 1.082, FLIP 1.048x the input's; with
// TS_PARTIAL_FOOTPRINT 1.095 / 0.988x; at 64x64 1.300 / 0.898x). SIGMA_SHADOW: 1.227 / 0.986x (64x64: 1.387 / 0.981x).
TEST_CASE("Shadow denoisers keep the floor lit where a sliding camera uncovers it beside a hard shadow", "[quality]")
{
    const char* scene = R"({"name": "slide_hard_sun", "frames": 48, "seed": 1,
        "sky": {"zenith": [0.25, 0.42, 0.8], "horizon": [0.75, 0.82, 0.95], "ground": [0.3, 0.28, 0.25]},
        "camera": {"position": [-2.0, 2.4, 5.6], "target": [-2.0, 0.5, 0.0], "fov": 45, "near": 0.05,
                   "keyframes": [{"frame": 0, "position": [-2.0, 2.4, 5.6], "target": [-2.0, 0.5, 0.0]},
                                 {"frame": 47, "position": [2.0, 2.4, 5.6], "target": [2.0, 0.5, 0.0]}]},
        "materials": {"floor": {"albedo": [0.7, 0.68, 0.65], "roughness": 0.8}, "red": {"albedo": [0.8, 0.15, 0.1], "roughness": 0.15},
                      "blue": {"albedo": [0.15, 0.3, 0.8], "roughness": 0.5}, "white": {"albedo": 0.85, "roughness": 1.0}},
        "objects": [
            {"name": "floor", "type": "plane", "material": "floor"},
            {"name": "red sphere", "type": "sphere", "radius": 0.6, "position": [-1.3, 0.6, 0.0], "material": "red"},
            {"name": "gold sphere", "type": "sphere", "radius": 0.4, "position": [0.35, 0.4, 0.9], "material": "red"},
            {"name": "blue box", "type": "box", "size": [0.8, 1.0, 0.8], "position": [1.4, 0.5, -0.5], "rotation": [0, 30, 0], "material": "blue"},
            {"name": "pole", "type": "box", "size": [0.08, 1.8, 0.08], "position": [-0.3, 0.9, -0.2], "material": "white"},
            {"name": "floating slab", "type": "box", "size": [1.0, 0.06, 0.5], "position": [1.6, 1.5, 1.0], "rotation": [0, -20, 10], "material": "white"}],
        "lights": [{"name": "sun", "type": "sun", "direction": [0.45, 0.8, 0.35], "angularRadius": 0.4, "intensity": [3, 2.9, 2.7]}]})";
    for (const char* method : {"SIGMA_SHADOW", "TILED_SHADOW"})
    {
        auto [ratio, flipRatio] = RunRatios(scene, method, 128, "sliding camera, hard sun");
        CHECK(ratio >= 1.0 - kRounding);
        CHECK(flipRatio <= 1.0 + kRounding);
    }
}

// One test case per size and built-in scene ("shadow denoisers do no harm on <scene> at <n>x<n>"),
// so that ctest's slices of this executable spread the scenes over the cores.
struct DoNoHarmInvoker : Catch::ITestInvoker
{
    std::string scene;
    uint32_t size;
    DoNoHarmInvoker(std::string s, uint32_t n) : scene(std::move(s)), size(n) {}
    void invoke() const override { CheckDoNoHarm(scene, size); }
};

// 64x64 and 128x128 run in CI (tag [quality], the ctest slices select it); 256x256 ([size256]) runs as its own
// ctest entry with the label `slow`, which the README's test command leaves out (it costs about 4x
// the two smaller sizes together; `ctest -L slow` runs it).
bool RegisterDoNoHarm()
{
    for (uint32_t size : {64u, 128u, 256u})
        for (const std::string& name : nrdlab::GetBuiltinSceneNames())
        {
            std::string title = "shadow denoisers do no harm on " + name + " at " + std::to_string(size) + "x" +
                                std::to_string(size);
            Catch::AutoReg(new DoNoHarmInvoker(name, size), Catch::SourceLineInfo(__FILE__, __LINE__),
                           Catch::StringRef(), Catch::NameAndTags(title, size > 128 ? "[size256]" : "[quality]"));
        }
    return true;
}

const bool g_Registered = RegisterDoNoHarm();

} // namespace
