// RELAX on the scene lab's built-in scenes through the method runner (the library of nrd-sample),
// against the quality bar of its issue at CI size: 128x128, 32 measured frames after an 8-frame
// warm-up, truth at 64 samples per pixel (lavapipe time; the frame cache makes reruns cheap).
// Still scenes: relMSE at most 1/10 of the noisy input's (diffuse) and 1/6 (specular); everywhere:
// FLIP below the input's, temporal instability at most half the input's, the mean within 3% of the
// truth's. Every figure is printed next to the bar. light_switch (64x64): the denoised mean follows
// the lamp within 3 frames of each switch. The lag figure of the bar (at most 3 frames at 128x128)
// is measured by nrd-sample on the GPU (Shaders/Relax/README.md): on lavapipe's 64-spp truth the
// error of the dark frames alone sits near twice the lit frames' and the figure is noise.
// Moving scenes (a camera, object or light track): relMSE no higher than the `--bounds` oracle (blend
// factor 0.25) and a third of the input's; disocclusion at 128x128 in CI.
// [size128] (ctest label slow): every built-in scene at 128x128, both signals, against the whole
// bar; combinations that miss it go to kShortfalls with their measured figures (5% margin) so that
// they can only improve.
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

struct Measured
{
    double relmseRatio = 0; // relMSE(noisy) / relMSE(denoised).
    double flipNoisy = 0, flipDenoised = 0;
    double instabilityNoisy = 0, instabilityDenoised = 0;
    double meanBias = 0; // |mean(denoised) / mean(truth) - 1| over the measured frames.
    int32_t lag = 0;
};

// The runs every RELAX quality case measures: 40 frames (32 measured after 8 of warm-up), truth 64 spp.
nrdlab::RunOptions QualityRunOptions(const std::string& scene, const std::string& method, const char* signal, uint32_t size)
{
    nrdlab::RunOptions o;
    o.scene = scene;
    o.method = method;
    o.signal = signal;
    o.width = o.height = size;
    o.frames = 40;
    o.warmup = 8;
    o.truthSpp = 64;
    o.keepImages = false;
    return o;
}

Measured Run(const char* scene, const char* signal, uint32_t size = 128, nrdlab::RunReport* report = nullptr)
{
    nrdlab::RunOptions o =
        QualityRunOptions(scene, std::string("RELAX_") + (std::string(signal) == "diffuse" ? "DIFFUSE" : "SPECULAR"), signal, size);
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
    m.meanBias = std::fabs(r.mean.meanDenoised / std::max(r.mean.meanTruth, 1e-12) - 1.0);
    m.lag = r.lagEventFrame >= 0 ? r.lagFrames : 0;
    if (report)
        *report = r;
    std::printf("%s %-14s %-8s relMSE noisy/denoised %5.1f  FLIP %.4f -> %.4f  instability %.5f -> %.5f  mean bias "
                "%.2f%%  lag %d\n",
                o.method.c_str(), scene, signal, m.relmseRatio, m.flipNoisy, m.flipDenoised, m.instabilityNoisy,
                m.instabilityDenoised, 100.0 * m.meanBias, m.lag);
    return m;
}

// 'maxBias' above the bar's 3% pins a measured shortfall (5% margin) so that it can only improve.
void CheckBar(const Measured& m, double ratio, double maxBias = 0.03)
{
    CHECK(m.relmseRatio >= ratio);
    CHECK(m.flipDenoised < m.flipNoisy);
    CHECK(m.instabilityDenoised <= 0.5 * m.instabilityNoisy);
    CHECK(m.meanBias <= maxBias);
}

} // namespace

TEST_CASE("RELAX meets the quality bar on a still scene", "[quality]")
{
    // Measured on lavapipe: diffuse relMSE 20.6x below the input's, mean bias 0.11%; specular 24.6x,
    // mean 1.3% below the truth's.
    CheckBar(Run("static", "diffuse"), 10.0);
    CheckBar(Run("static", "specular"), 6.0);
}

TEST_CASE("RELAX follows a light switched off and on within 3 frames", "[quality]")
{
    // light_switch: the lamp turns off at frame 16 (the mean radiance drops by 19%) and on at 24.
    // From the third frame after each switch the denoised mean is within 2% of the truth's (before
    // the mean clamps: still 14% above it 3 frames after the lamp went off, 7% below 3 frames after
    // it came back).
    nrdlab::RunReport r;
    Measured m = Run("light_switch", "diffuse", 64, &r);
    CHECK(m.relmseRatio >= 3.0);
    CHECK(m.meanBias <= 0.03);
    REQUIRE(r.perFrame.size() == 40);
    for (size_t f : {19, 20, 21, 22, 23, 27, 28, 29, 30, 31})
    {
        const nrdlab::FrameMetrics& fm = r.perFrame[f];
        INFO("frame " << f << ": mean " << fm.meanDenoised << ", truth " << fm.meanTruth);
        CHECK(std::fabs(fm.meanDenoised / fm.meanTruth - 1.0) <= 0.02);
    }
}

namespace
{

// A combination that misses the bar, pinned at its measured figures (lavapipe, 128x128, 5% margin):
// relMSE at most 'maxRelmseOfBar' times the bar's, the mean within 'maxBias' of the truth's.
struct Shortfall
{
    const char* scene;
    const char* signal;
    double maxRelmseOfBar;
    double maxBias;
};

// None since the diffuse change test (venetian_blinds diffuse: 0.96 of a third of the input's relMSE on
// lavapipe; 1.418 before).
const std::vector<Shortfall> kShortfalls = {};

const Shortfall* FindShortfall(const std::string& scene, const std::string& signal)
{
    for (const Shortfall& s : kShortfalls)
        if (scene == s.scene && signal == s.signal)
            return &s;
    return nullptr;
}

// The whole bar of issue 14 at 'size': still scenes relMSE 1/10 (diffuse) or 1/6 (specular) of the
// input's, moving ones at most the oracle's and a third of the input's; everywhere FLIP below the
// input's, temporal instability at most half the input's, the mean within 3% of the truth's.
void CheckSceneBar(const std::string& name, const char* signal, uint32_t size)
{
    nrdlab::Scene scene;
    std::string error;
    REQUIRE(nrdlab::LoadScene(name, scene, error));
    const bool isMoving = nrdlab::IsSceneAnimated(scene);
    const bool isDiffuse = std::string(signal) == "diffuse";

    nrdlab::RunOptions o = QualityRunOptions(name, "RELAX_DIFFUSE_SPECULAR", signal, size);
    o.bounds = isMoving;
    nrdlab::RunReport r;
    INFO(name << " " << signal << " " << size << "x" << size << ": " << error);
    REQUIRE(nrdlab::RunMethod(o, r, error));

    const nrdlab::FrameMetrics& m = r.mean;
    const double bar = isMoving ? std::min(m.boundOracle, m.relmseNoisy / 3.0)
                                : m.relmseNoisy / (isDiffuse ? 10.0 : 6.0);
    const double bias = m.meanDenoised / std::max(m.meanTruth, 1e-12) - 1.0;
    const Shortfall* shortfall = FindShortfall(name, signal);
    std::printf("RELAX %-18s %-8s %3ux%-3u %s relMSE %.5f -> %.5f (bar %.5f, %.3f of it)  FLIP %.4f -> %.4f  "
                "instability %.4f -> %.4f  bias %+.2f%%%s\n",
                name.c_str(), signal, size, size, isMoving ? "moving" : "still ", m.relmseNoisy, m.relmseDenoised, bar,
                m.relmseDenoised / bar, m.flipNoisy, m.flipDenoised, m.temporalInstabilityNoisy,
                m.temporalInstabilityDenoised, bias * 100.0, shortfall ? "  (known shortfall)" : "");
    if (isMoving)
        REQUIRE(m.boundOracle > 0.0);
    CHECK(m.relmseDenoised <= bar * (shortfall ? shortfall->maxRelmseOfBar : 1.0));
    CHECK(m.flipDenoised < m.flipNoisy);
    CHECK(m.temporalInstabilityDenoised <= 0.5 * m.temporalInstabilityNoisy);
    CHECK(std::fabs(bias) <= (shortfall ? std::max(shortfall->maxBias, 0.03) : 0.03));
}

} // namespace

TEST_CASE("RELAX meets the moving-scene bar on disocclusion", "[quality]")
{
    // Measured on lavapipe: relMSE 0.0099, 0.53 of the oracle's (0.0206, 1.11 of it, with the history
    // fix's former 14-pixel stride and bilinear resampling of the histories).
    CheckSceneBar("disocclusion", "diffuse", 128);
}

TEST_CASE("RELAX against the quality bar on every built-in scene at 128x128", "[size128]")
{
    for (const std::string& scene : nrdlab::GetBuiltinSceneNames())
        for (const char* signal : {"diffuse", "specular"})
            CheckSceneBar(scene, signal, 128);
}
