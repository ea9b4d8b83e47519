// REFLECTION on the scene lab against issue 15's bar. The lab traces exactly the rays of the
// method's ray list (SceneLab::TraceSpecularRays); the output is compared with the full-rate
// specular truth, and with the full-rate 1-spp input (one ray per non-sky pixel, which the method
// never sees):
// - still scenes: relMSE at most 1/4 of the input's;
// - moving scenes (a camera, object or light track): relMSE no higher than the `--bounds` oracle
//   (blend factor 0.25, the one nrd-sample reports);
// - everywhere: FLIP below the input's, the mean within 7% of the truth's (energy), some rays;
// - roughness_sweep: at most 60% of the full-rate rays.
// [quality] (CI): six scenes at 64x64, 16 frames of which 8 are a warm-up, truth 32 spp.
// [size128] (ctest label slow): every built-in scene at 128x128, 40 frames of which 8 are a
// warm-up (32 measured, as the issue asks), truth 64 spp. Shaders/Reflection/README.md has the
// figures. Combinations that do not meet the bar go to kShortfalls with their measured figures
// (5% margin) so that they can only improve.
#include <catch2/catch.hpp>

#include "MethodRunner.h"
#include "Scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace
{

struct Shortfall
{
    const char* scene;
    uint32_t size;
    double maxRelmseRatio; // relMSE(output) / bar relMSE at most this.
};

// Empty: every scene measured meets the bar.
const std::vector<Shortfall> kShortfalls = {};

const Shortfall* FindShortfall(const std::string& scene, uint32_t size)
{
    for (const Shortfall& s : kShortfalls)
        if (scene == s.scene && size == s.size)
            return &s;
    return nullptr;
}

void CheckBar(const std::string& name, uint32_t size, uint32_t frames, uint32_t truthSpp)
{
    nrdlab::Scene scene;
    std::string error;
    REQUIRE(nrdlab::LoadScene(name, scene, error));
    const bool isMoving = nrdlab::IsSceneAnimated(scene);

    nrdlab::RunOptions o;
    o.scene = name;
    o.method = "REFLECTION";
    o.width = o.height = size;
    o.frames = frames;
    o.warmup = 8;
    o.truthSpp = truthSpp;
    o.bounds = isMoving;
    o.keepImages = false;
    nrdlab::RunReport r;
    INFO(name << " " << size << "x" << size << ": " << error);
    REQUIRE(nrdlab::RunMethod(o, r, error));

    const nrdlab::FrameMetrics& m = r.mean;
    const double bar = isMoving ? m.boundOracle : 0.25 * m.relmseNoisy;
    const double bias = m.meanDenoised / m.meanTruth - 1.0;
    const Shortfall* shortfall = FindShortfall(name, size);
    std::printf("REFLECTION %-18s %3ux%-3u %s relMSE %.5f -> %.5f (bar %.5f, %.3f of it)  FLIP %.4f -> %.4f  "
                "bias %+.2f%%  rays %.3f%s\n",
                name.c_str(), size, size, isMoving ? "moving" : "still ", m.relmseNoisy, m.relmseDenoised, bar,
                m.relmseDenoised / bar, m.flipNoisy, m.flipDenoised, bias * 100.0, r.rayRatio,
                shortfall ? "  (known shortfall)" : "");
    CHECK(std::isfinite(m.relmseDenoised));
    if (isMoving)
        REQUIRE(m.boundOracle > 0.0);
    CHECK(m.relmseDenoised <= bar * (shortfall ? shortfall->maxRelmseRatio : 1.0));
    CHECK(m.flipDenoised < m.flipNoisy);
    CHECK(std::abs(bias) <= 0.07);
    CHECK(r.raysTraced > 0.0);
    CHECK(r.rayRatio <= 1.0);
    if (name == "roughness_sweep")
        CHECK(r.rayRatio <= 0.6);
}

} // namespace

TEST_CASE("REFLECTION meets the quality bar on still and moving scenes at 64x64 with at most 60% of the rays",
          "[quality]")
{
    for (const char* scene :
         {"roughness_sweep", "grazing_floor", "static", "camera_translation", "mesh_thin", "light_switch"})
        CheckBar(scene, 64, 16, 32);
}

TEST_CASE("REFLECTION meets the quality bar on every built-in scene at 128x128", "[size128]")
{
    for (const std::string& scene : nrdlab::GetBuiltinSceneNames())
        CheckBar(scene, 128, 40, 64);
}
