// The shadow denoisers (SIGMA_SHADOW, TILED_SHADOW) on every built-in scene of the scene lab, at
// several sizes, against issue 20's bar: the output's relMSE and FLIP no higher than the 1-spp
// input's ("do no harm"), and on scenes where something moves an input / output relMSE ratio at
// least half of what perfect temporal reuse reaches (`--bounds`' oracle, ReuseBounds.h).
//
// Not every scene meets it yet: the combinations in kShortfalls do not (measured on lavapipe when
// written, re-measured where the scene lab's fix of rotated boxes and quads changed the scenes; Shaders/TiledShadow/README.md and the README's SIGMA section give the causes). Those
// assert their measured relMSE ratio (input / output, 5% below) and FLIP ratio (output / input, 5%
// above) instead, so that they can only improve; move a line out of the table when it meets the bar.
//
// 64x64 and 128x128, in CI (label quality). 24 frames, the first 8 a warm-up; the truth takes 32
// samples per pixel (as `Samples/Scripts/shadow_table.py`). The frame cache makes reruns cheap.
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
const Shortfall kShortfalls[] = {
    {"camera_rotation", "TILED_SHADOW", 64, 0.43, 1.33}, // ratio 0.457 (oracle 1.24), FLIP 0.0062 -> 0.0078
    {"camera_translation", "TILED_SHADOW", 64, 0.37, 1.35}, // ratio 0.389 (oracle 1.65), FLIP 0.0057 -> 0.0074
    {"disocclusion", "TILED_SHADOW", 64, 0.87, 0.83}, // ratio 0.921 (oracle 5.70), FLIP 0.0051 -> 0.0038
    {"fast_orbit", "SIGMA_SHADOW", 64, 0.95, 1.05}, // ratio 1.000 (oracle 1.11), FLIP 0.0076 -> 0.0076
    {"fast_orbit", "TILED_SHADOW", 64, 0.29, 1.45}, // ratio 0.302 (oracle 1.11), FLIP 0.0076 -> 0.0104
    {"moving_light", "SIGMA_SHADOW", 64, 0.96, 1.85}, // ratio 1.008 (oracle 0.66), FLIP 0.0194 -> 0.0341
    {"moving_light", "TILED_SHADOW", 64, 0.24, 1.59}, // ratio 0.256 (oracle 0.66), FLIP 0.0194 -> 0.0293
    {"moving_occluder", "SIGMA_SHADOW", 64, 1.86, 1.31}, // ratio 1.961 (oracle 1.53), FLIP 0.0127 -> 0.0158
    {"moving_occluder", "TILED_SHADOW", 64, 0.95, 1.43}, // ratio 1.001 (oracle 1.98), FLIP 0.0138 -> 0.0182
    {"toggling_light", "SIGMA_SHADOW", 64, 1.92, 2.69}, // ratio 2.023 (oracle 4.62), FLIP 0.0106 -> 0.0272
    {"toggling_light", "TILED_SHADOW", 64, 0.33, 1.66}, // ratio 0.348 (oracle 4.62), FLIP 0.0106 -> 0.0167
    {"venetian_blinds", "SIGMA_SHADOW", 64, 0.24, 2.23}, // ratio 0.255 (oracle 0.97), FLIP 0.0176 -> 0.0374
    {"venetian_blinds", "TILED_SHADOW", 64, 0.08, 2.39}, // ratio 0.087 (oracle 0.97), FLIP 0.0176 -> 0.0401
    {"camera_rotation", "TILED_SHADOW", 128, 1.05, 1.09}, // ratio 1.101 (oracle 1.89), FLIP 0.0056 -> 0.0058
    {"camera_translation", "SIGMA_SHADOW", 128, 0.98, 1.04}, // ratio 1.034 (oracle 2.58), FLIP 0.0054 -> 0.0053
    {"camera_translation", "TILED_SHADOW", 128, 0.82, 1.06}, // ratio 0.863 (oracle 2.58), FLIP 0.0054 -> 0.0054
    {"fast_orbit", "SIGMA_SHADOW", 128, 0.98, 1.05}, // ratio 1.032 (oracle 2.09), FLIP 0.0067 -> 0.0067
    {"fast_orbit", "TILED_SHADOW", 128, 0.65, 1.19}, // ratio 0.684 (oracle 2.00), FLIP 0.0064 -> 0.0073
    {"moving_light", "SIGMA_SHADOW", 128, 1.23, 1.52}, // ratio 1.291 (oracle 0.65), FLIP 0.0173 -> 0.0250
    {"moving_light", "TILED_SHADOW", 128, 1.25, 1.17}, // ratio 1.316 (oracle 0.65), FLIP 0.0173 -> 0.0192
    {"moving_occluder", "SIGMA_SHADOW", 128, 1.59, 1.17}, // ratio 1.684 (oracle 1.77), FLIP 0.0122 -> 0.0135
    {"moving_occluder", "TILED_SHADOW", 128, 2.20, 1.12}, // ratio 2.322 (oracle 1.77), FLIP 0.0122 -> 0.0128
    {"toggling_light", "SIGMA_SHADOW", 128, 3.37, 2.09}, // ratio 3.547 (oracle 5.06), FLIP 0.0088 -> 0.0175
    {"toggling_light", "TILED_SHADOW", 128, 1.46, 1.26}, // ratio 1.532 (oracle 5.06), FLIP 0.0088 -> 0.0106
    {"venetian_blinds", "SIGMA_SHADOW", 128, 0.13, 2.24}, // ratio 0.132 (oracle 0.84), FLIP 0.0158 -> 0.0338
    {"venetian_blinds", "TILED_SHADOW", 128, 0.06, 2.52}, // ratio 0.062 (oracle 0.84), FLIP 0.0158 -> 0.0380
};
// clang-format on

const Shortfall* FindShortfall(const std::string& scene, const char* method, uint32_t size)
{
    for (const Shortfall& s : kShortfalls)
        if (scene == s.scene && std::string(method) == s.method && size == s.size)
            return &s;
    return nullptr;
}

// True when the camera, an object or a light changes over the frames (a track with keyframes).
bool IsMoving(const nrdlab::Scene& scene)
{
    bool moving = !scene.camera.position.keys.empty() || !scene.camera.target.keys.empty() ||
                  !scene.camera.up.keys.empty() || !scene.camera.fovDeg.keys.empty();
    for (const nrdlab::Object& o : scene.objects)
        moving = moving || !o.position.keys.empty() || !o.rotation.keys.empty();
    for (const nrdlab::Light& l : scene.lights)
        moving = moving || !l.direction.keys.empty() || !l.position.keys.empty() || !l.intensity.keys.empty() ||
                 !l.enabled.keys.empty();
    return moving;
}

void CheckDoNoHarm(const std::string& name, uint32_t size)
{
    nrdlab::Scene scene;
    std::string error;
    REQUIRE(nrdlab::LoadScene(name, scene, error));
    bool moving = IsMoving(scene);
    for (const char* method : {"SIGMA_SHADOW", "TILED_SHADOW"})
    {
        nrdlab::RunOptions o;
        o.scene = name;
        o.method = method;
        o.width = o.height = size;
        o.frames = 24;
        o.warmup = 8;
        o.truthSpp = 32;
        o.keepImages = false;
        o.bounds = moving;
        nrdlab::RunReport r;
        INFO(name << " " << method << " " << size << "x" << size);
        REQUIRE(nrdlab::RunMethod(o, r, error));
        const nrdlab::FrameMetrics& m = r.mean;
        double ratio = m.relmseNoisy / std::max(m.relmseDenoised, 1e-12);
        double oracleRatio = moving ? m.relmseNoisy / std::max(m.boundOracle, 1e-12) : 0.0;
        const Shortfall* shortfall = FindShortfall(name, method, size);
        std::printf("%-13s %-18s %3u  relMSE ratio %6.3f (oracle %5.2f)  FLIP %.4f -> %.4f%s\n", method, name.c_str(),
                    size, ratio, oracleRatio, m.flipNoisy, m.flipDenoised, shortfall ? "  (known shortfall)" : "");
        if (shortfall)
        {
            CHECK(ratio >= shortfall->minRelmseRatio);
            CHECK(m.flipDenoised <= shortfall->maxFlipRatio * m.flipNoisy);
            continue;
        }
        CHECK(m.relmseDenoised <= m.relmseNoisy);
        CHECK(m.flipDenoised <= m.flipNoisy);
        if (moving)
        {
            REQUIRE(m.boundOracle > 0.0);
            CHECK(ratio >= 0.5 * oracleRatio);
        }
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

bool RegisterDoNoHarm()
{
    for (uint32_t size : {64u, 128u})
        for (const std::string& name : nrdlab::GetBuiltinSceneNames())
        {
            // The triangle-mesh scenes are measured separately and fall short of this bar today
            // (Shaders/Sigma/README.md, Shaders/TiledShadow/README.md: "Triangle-mesh scenes").
            if (name.rfind("mesh_", 0) == 0)
                continue;
            std::string title = "shadow denoisers do no harm on " + name + " at " + std::to_string(size) + "x" +
                                std::to_string(size);
            Catch::AutoReg(new DoNoHarmInvoker(name, size), Catch::SourceLineInfo(__FILE__, __LINE__),
                           Catch::StringRef(), Catch::NameAndTags(title, "[quality]"));
        }
    return true;
}

const bool g_Registered = RegisterDoNoHarm();

} // namespace
