// CONFIDENCE on the scene lab (64x64, few frames, truth at few samples: the frames the lab caches):
// exactly 1 on a still scene, below 0.5 around a switched light within 2 frames, and the bar of
// issue 16 for REBLUR and RELAX with and without confidence: on scenes whose lighting changes the
// trailing light at least halved (where there is one) and relMSE no higher; on scenes whose
// lighting does not change relMSE within 5%.
#include <catch2/catch.hpp>

#include "MethodRunner.h"
#include "NRDSettings.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace
{

nrdlab::RunOptions SmallRun(const std::string& scene, const std::string& method, uint32_t frames, uint32_t size = 64)
{
    nrdlab::RunOptions o;
    o.scene = scene;
    o.method = method;
    o.width = size;
    o.height = size;
    o.frames = frames;
    o.warmup = 8;
    o.truthSpp = size > 64 ? 64 : 32;
    o.keepImages = true;
    return o;
}

nrdlab::RunReport Run(const nrdlab::RunOptions& o)
{
    nrdlab::RunReport r;
    std::string error;
    INFO(error);
    REQUIRE(nrdlab::RunMethod(o, r, error));
    return r;
}

} // namespace

TEST_CASE("CONFIDENCE is exactly 1 everywhere on a still scene", "[quality][confidence]")
{
    // The lab's gradients of a still scene are exactly 0 (same surface, lights and light sample on
    // both frames; SceneLabTests checks them), so no pixel may lose confidence.
    for (const char* signal : {"diffuse_confidence", "specular_confidence"})
    {
        INFO(signal);
        nrdlab::RunOptions o = SmallRun("static", "CONFIDENCE", 4);
        o.signal = signal;
        o.warmup = 1;
        o.truthSpp = 4;
        nrdlab::RunReport r = Run(o);
        size_t belowOne = 0;
        for (float v : r.denoised.pixels)
            belowOne += v != 1.0f;
        CHECK(belowOne == 0);
    }
}

TEST_CASE("CONFIDENCE falls below 0.5 around a switched light within 2 frames", "[quality][confidence]")
{
    // light_switch with CONFIDENCE's default settings: the lamp turns off at frame 16. Around it
    // are the pixels whose truth lost at least a third of its luminance from frame 15 to 16 (the
    // lamp gave them a third of their light or more; the dim sun and the sky the rest); frame 16 or
    // 17 must have confidence below 0.5 on (nearly) all of them. The adapter's truth image is the
    // method's function of the truth's normalized change, inverted here with the default settings.
    const nrd::ConfidenceSettings defaults;
    const float changedBy = 1.0f / 3.0f;
    for (const char* signal : {"diffuse_confidence", "specular_confidence"})
    {
        INFO(signal);
        const bool diffuse = std::string(signal) == "diffuse_confidence";
        const float sensitivity = diffuse ? defaults.gradientSensitivity : defaults.specularGradientSensitivity;
        const float truthAtMost = 1.0f - (changedBy - defaults.gradientThreshold) * sensitivity;
        size_t changed = 0, caught = 0;
        std::vector<float> truth16, confidence16;
        for (uint32_t frames : {17u, 18u})
        {
            nrdlab::RunOptions o = SmallRun("light_switch", "CONFIDENCE", frames);
            o.signal = signal;
            nrdlab::RunReport r = Run(o);
            if (frames == 17)
            {
                truth16 = r.truth.pixels; // Frame 16.
                confidence16 = r.denoised.pixels;
                continue;
            }
            for (size_t i = 0; i < truth16.size(); i++)
                if (truth16[i] <= truthAtMost)
                {
                    changed++;
                    caught += std::min(confidence16[i], r.denoised.pixels[i]) < 0.5f; // Frame 16 or 17.
                }
        }
        INFO(caught << " of " << changed << " changed pixels below 0.5");
        REQUIRE(changed > 500);
        // Measured (lavapipe): diffuse 831 of 844 pixels (98.5%), specular 958 of 1098 (87.2%: the
        // lamp's highlights are a few pixels wide, below the 3x3 strata and the a-trous footprint, so
        // their edges get diluted gradients).
        CHECK(double(caught) >= (diffuse ? 0.95 : 0.85) * double(changed));
    }
}

namespace
{

struct Pair
{
    nrdlab::RunReport without, with;
};

Pair RunBoth(const std::string& scene, const std::string& method, uint32_t frames, uint32_t size = 64)
{
    Pair p;
    nrdlab::RunOptions o = SmallRun(scene, method, frames, size);
    p.without = Run(o);
    o.confidence = true;
    p.with = Run(o);
    return p;
}

// Trailing light: frames after each sudden change of the truth (its image mean moves by more than
// 5% from one frame to the next, after the warm-up) until the output's mean is back within 1% of
// the truth's (specular: 2%, its image mean moves by 1-1.5% from frame to frame on short histories),
// relative to the output's bias over the 4 frames before the first change (the consumers' steady
// bias, specular's -2% included); the longest over the changes, each counted up to the next one. The lab's lag (RunReport::lagFrames) and low-pass lag count the frames until the
// error is back within twice its level before the change, which a restarted history's noise keeps
// above for 7 frames at 64x64 however fast the light follows (Shaders/Confidence/README.md).
int MeanLag(const nrdlab::RunReport& r)
{
    const double tolerance = r.method.find("SPECULAR") != std::string::npos ? 0.02 : 0.01;
    const std::vector<nrdlab::FrameMetrics>& f = r.perFrame;
    std::vector<size_t> changes;
    for (size_t t = std::max<size_t>(r.warmup, 1); t < f.size(); t++)
        if (std::abs(f[t].meanTruth / f[t - 1].meanTruth - 1.0) > 0.05)
            changes.push_back(t);
    if (changes.empty() || changes[0] < 4)
        return 0;
    auto bias = [&](size_t t) { return f[t].meanDenoised / f[t].meanTruth - 1.0; };
    double before = 0.0;
    for (size_t t = changes[0] - 4; t < changes[0]; t++)
        before += bias(t) / 4.0;
    int worst = 0;
    for (size_t i = 0; i < changes.size(); i++)
    {
        size_t end = i + 1 < changes.size() ? changes[i + 1] : f.size();
        for (size_t t = changes[i]; t < end; t++)
            if (std::abs(bias(t) - before) > tolerance)
                worst = std::max(worst, int(t - changes[i] + 1));
    }
    return worst;
}

struct Case
{
    const char* scene;
    const char* method;
    uint32_t frames;
    uint32_t size = 64;
};

// Issue 16's bar where the lighting changes, with CONFIDENCE's default settings: relMSE no higher
// with confidence than without and the trailing light (MeanLag) no longer; halved where 'halved' is
// set: light_switch for the four consumers (64x64, 40 frames: REBLUR_DIFFUSE 6 -> 0 frames, REBLUR_SPECULAR
// 16 -> 0, RELAX_SPECULAR 16 -> 2 (RELAX_SPECULAR_CONFIDENCE_CLAMP_KNEE's top darkens the frames after the
// lamp goes off a little), RELAX_DIFFUSE 2 -> 1) and toggling_light for all but RELAX_SPECULAR
// (4 -> 0 to 2 frames, REBLUR_DIFFUSE 2 below REBLUR_DIFFUSE_CONFIDENCE_NARROWING_KNEE's 0.7; RELAX_SPECULAR's frames kept are not moved to the new lighting where the
// light toggles every 4 frames: 4 -> 4, Shaders/Confidence/README.md).
// The ratio of one run (one noise seed) spreads by more than the excesses it decides: over seeds 1
// to 6 (lavapipe, 64x64, 40 frames) RELAX_DIFFUSE on moving_light reads 0.976x to 1.020x with /
// without confidence, REBLUR_DIFFUSE on toggling_light (4 frames kept) 0.961x to 1.050x (standard
// deviations 1.5% and 3.2%).
// In the slow table ([confidence_all]) a pair whose ratio at the scene's seed lies within kSeedSpread
// of 1 is decided by the relMSE summed over kSeeds (the runs with and without confidence share each
// seed): the mean excess, not one draw of it (Shaders/Confidence/README.md, "One seed against
// several"). The CI cases read the scene's seed only (their trailing light is what they assert).
// Pairs that miss issue 16's bar over kSeeds (lavapipe, 64x64, 40 frames): none. A pair that does
// is pinned here at its measured ratio plus a small margin so that a further loss fails; a line
// leaves when its pair meets the bar again (a line met by more than kDeviceSpread fails too). The
// last ones: REBLUR_SPECULAR on fast_occluder (1.00011x over seeds 1-6) until REBLUR specular ran
// its history fix for twice the confidence debt's frames (REBLUR_SPECULAR_DEBT_FIX_SCALE, 0.990x);
// RELAX_DIFFUSE on mesh_thin (1.00062x) until ConfidenceSettings's gradientThreshold went from 0.05
// to 0.03 (0.99894x; Shaders/Confidence/README.md, "The gradient threshold"); REBLUR_DIFFUSE on
// venetian_blinds at 128x128 ([confidence_128]) until its anti-lag narrowed only the correction,
// below REBLUR_DIFFUSE_CONFIDENCE_NARROWING_KNEE (1.030x -> 0.998x, Shaders/Confidence/README.md).
struct Shortfall
{
    const char* scene;
    const char* method;
    uint32_t size;
    double relmseRatio; // with / without confidence, at most
    bool trailingNotHalved;
};
const std::vector<Shortfall> kShortfalls = {};

// Seeds of the decision over several runs, and how far from 1 a ratio at the scene's seed is left to it.
constexpr uint32_t kSeeds[] = {1, 2, 3, 4, 5, 6};
constexpr double kSeedSpread = 0.05;

// "No higher" within the rounding of the GPU's arithmetic: the same run reads moving_occluder
// REBLUR_DIFFUSE at 0.9974x on lavapipe and 1.0000022x on the NVIDIA H200.
constexpr double kDeviceRounding = 1e-5;
// The same pair on lavapipe and on the NVIDIA H200 (RELAX_DIFFUSE at 64x64, 40 frames): moving_light
// 0.998x and 1.002x, fast_occluder 1.004x and 0.999x.
constexpr double kDeviceSpread = 0.005;

const Shortfall* FindShortfall(const Case& c)
{
    for (const Shortfall& s : kShortfalls)
        if (std::string(s.scene) == c.scene && std::string(s.method) == c.method && s.size == c.size)
            return &s;
    return nullptr;
}

// relMSE with / without confidence summed over kSeeds.
double SeedMeanRatio(const Case& c)
{
    double without = 0.0, with = 0.0;
    for (uint32_t seed : kSeeds)
    {
        nrdlab::RunOptions o = SmallRun(c.scene, c.method, c.frames, c.size);
        o.keepImages = false;
        o.seed = seed;
        without += Run(o).mean.relmseDenoised;
        o.confidence = true;
        with += Run(o).mean.relmseDenoised;
    }
    return with / without;
}

void CheckLightingChange(const Case& c, bool halved = false, bool overSeeds = false)
{
    Pair p = RunBoth(c.scene, c.method, c.frames, c.size);
    const int lagWithout = MeanLag(p.without), lagWith = MeanLag(p.with);
    INFO(c.scene << " " << c.method << " " << c.size << "x" << c.size << ": relMSE " << p.without.mean.relmseDenoised << " -> " << p.with.mean.relmseDenoised
                 << " (" << p.with.mean.relmseDenoised / p.without.mean.relmseDenoised << "x), trailing light " << lagWithout
                 << " -> " << lagWith << " frames, low-pass lag " << p.without.lagLowpassFrames << " -> "
                 << p.with.lagLowpassFrames);
    const Shortfall* shortfall = overSeeds ? FindShortfall(c) : nullptr; // The pins are over kSeeds.
    double ratio = p.with.mean.relmseDenoised / p.without.mean.relmseDenoised;
    const bool isOverSeeds = overSeeds && std::abs(ratio - 1.0) < kSeedSpread;
    if (isOverSeeds)
        ratio = SeedMeanRatio(c);
    INFO((isOverSeeds ? "over seeds 1 to 6: " : "at the scene's seed: ") << ratio << "x");
    CHECK(ratio <= (shortfall ? shortfall->relmseRatio : 1.0 + kDeviceRounding));
    CHECK(lagWith <= lagWithout);
    if (halved && !(shortfall && shortfall->trailingNotHalved))
        CHECK(2 * lagWith <= lagWithout);
    // A pinned pair that meets the bar again must leave the table; pairs within kDeviceSpread of the
    // bar may read either side of it on different devices.
    if (shortfall)
        CHECK_FALSE((ratio <= 1.0 - kDeviceSpread && (!halved || 2 * lagWith <= lagWithout)));
}

} // namespace

TEST_CASE("REBLUR and RELAX with CONFIDENCE: relMSE no higher and the light no longer trailing where lighting changes",
          "[quality][confidence]")
{
    // The four consumers on the light switch and the light toggled every 4 frames, RELAX_SPECULAR
    // under the moving lamp (1.07x without confidence before the consumers kept
    // NRD_CONFIDENCE_MIN_HISTORY frames). Every lighting scene and consumer: the [slow] case below.
    const Case halvedCases[] = {{"light_switch", "REBLUR_DIFFUSE", 32},   {"light_switch", "REBLUR_SPECULAR", 32},
                                {"light_switch", "RELAX_DIFFUSE", 32},    {"light_switch", "RELAX_SPECULAR", 32},
                                {"toggling_light", "REBLUR_DIFFUSE", 40}, {"toggling_light", "REBLUR_SPECULAR", 40},
                                {"toggling_light", "RELAX_DIFFUSE", 40}};
    for (const Case& c : halvedCases)
        CheckLightingChange(c, true);
    CheckLightingChange({"moving_light", "RELAX_SPECULAR", 24});
    // fast_occluder's speculars: the box's shadow sweeps the far floor; the local limit keeps the
    // a-trous filter from cutting the whole floor's histories (64x64: REBLUR_SPECULAR 1.011x ->
    // 0.999x, RELAX_SPECULAR 1.004x -> 0.992x with localGradientRadius 3), and REBLUR specular's
    // restarted histories keep the history fix for twice the debt's frames (REBLUR_SPECULAR_DEBT_FIX_SCALE).
    // REBLUR_SPECULAR is decided over seeds: 0.9994x at the scene's seed, 1.00011x over seeds 1-6 with
    // the debt's frames once, 0.990x twice.
    CheckLightingChange({"fast_occluder", "REBLUR_SPECULAR", 40}, false, true);
    CheckLightingChange({"fast_occluder", "RELAX_SPECULAR", 40});
}

TEST_CASE("A perfect restart of every history when the lamp toggles reads toggling_light RELAX_SPECULAR's trailing light as 4",
          "[quality][confidence]")
{
    // The count's floor on toggling_light (its lamp toggles every 4 frames, the count stops at the
    // next toggle): every history restarted on the frames of the toggles (no confidence) still
    // reads 4 for RELAX_SPECULAR (a restarted history's mean is +1% of the truth's on its first two
    // frames, -4% to -5% on the next two, against its -2% before), as the confidence does
    // (Shaders/Confidence/README.md, Lag), so its halving is not asserted there.
    nrdlab::RunOptions o = SmallRun("toggling_light", "RELAX_SPECULAR", 40);
    o.settingsJson = R"({"common": {"restartFrames": [4, 8, 12, 16, 20, 24, 28, 32, 36]}})";
    nrdlab::RunReport restarted = Run(o);
    o.settingsJson.clear();
    o.confidence = true;
    nrdlab::RunReport withConfidence = Run(o);
    INFO("restarted: relMSE " << restarted.mean.relmseDenoised << ", with confidence " << withConfidence.mean.relmseDenoised);
    CHECK(MeanLag(restarted) == 4);
    CHECK(MeanLag(withConfidence) == 4);
    CHECK(withConfidence.mean.relmseDenoised < restarted.mean.relmseDenoised);
}

TEST_CASE("A perfect restart of every history when the lamp switches: the diffuse consumers' low-pass lag on light_switch",
          "[quality][confidence]")
{
    // The lab's low-pass lag (RunReport::lagLowpassFrames: frames until the 8x8 block means' error is
    // back within twice its level before the change) counts a new history's noise as lag. Every
    // history restarted on the frames the lamp switches (16, 24; no confidence) is the most an
    // invalidation can do: RELAX_DIFFUSE reads the same count as with confidence (8 at 64x64), so the
    // count's floor is no lag of the confidence; REBLUR_DIFFUSE's restart halves it (8 -> 4 at 32
    // frames, 10 -> 4 at 40) at a relMSE above the run without confidence (1.17x, 1.16x), where the
    // confidence gives 7 at a relMSE below it (0.89x, 0.91x; Shaders/Confidence/README.md, Lag).
    for (const char* method : {"REBLUR_DIFFUSE", "RELAX_DIFFUSE"})
    {
        Pair p = RunBoth("light_switch", method, 32);
        nrdlab::RunOptions o = SmallRun("light_switch", method, 32);
        o.settingsJson = R"({"common": {"restartFrames": [16, 24]}})";
        nrdlab::RunReport restarted = Run(o);
        INFO(method << ": relMSE without " << p.without.mean.relmseDenoised << ", with confidence " << p.with.mean.relmseDenoised
                    << ", restarted " << restarted.mean.relmseDenoised << "; low-pass lag " << p.without.lagLowpassFrames << ", "
                    << p.with.lagLowpassFrames << ", " << restarted.lagLowpassFrames << "; trailing light " << MeanLag(p.without)
                    << ", " << MeanLag(p.with) << ", " << MeanLag(restarted));
        CHECK(restarted.mean.relmseDenoised > p.without.mean.relmseDenoised);
        CHECK(p.with.mean.relmseDenoised < p.without.mean.relmseDenoised);
        CHECK(p.with.lagLowpassFrames <= p.without.lagLowpassFrames);
        if (std::string(method) == "RELAX_DIFFUSE")
            CHECK(restarted.lagLowpassFrames == p.with.lagLowpassFrames);
        else
            CHECK(2 * restarted.lagLowpassFrames <= p.without.lagLowpassFrames);
    }
}

TEST_CASE("REBLUR and RELAX with CONFIDENCE: relMSE within 5% where lighting does not change", "[quality][confidence]")
{
    // Confidence is exactly 1 on these scenes, so the output is the same with and without it.
    const std::pair<const char*, const char*> runs[] = {{"static", "REBLUR_DIFFUSE"},
                                                        {"camera_translation", "REBLUR_DIFFUSE"},
                                                        {"static", "RELAX_DIFFUSE"},
                                                        {"camera_translation", "RELAX_SPECULAR"}};
    for (const auto& run : runs)
    {
        Pair p = RunBoth(run.first, run.second, 16);
        INFO(run.first << " " << run.second << ": relMSE " << p.without.mean.relmseDenoised << " -> "
                       << p.with.mean.relmseDenoised);
        CHECK(p.with.mean.relmseDenoised <= 1.05 * p.without.mean.relmseDenoised);
    }
}

TEST_CASE("REBLUR and RELAX with CONFIDENCE on every lighting scene and consumer", "[confidence_all]")
{
    // Label slow (Tests/CMakeLists.txt): the whole table of Shaders/Confidence/README.md at 64x64.
    const char* const consumers[] = {"REBLUR_DIFFUSE", "RELAX_DIFFUSE", "REBLUR_SPECULAR", "RELAX_SPECULAR"};
    for (const char* scene : {"light_switch", "toggling_light", "moving_light", "fast_occluder", "moving_occluder",
                              "venetian_blinds", "mesh_character", "mesh_thin"})
        for (const char* method : consumers)
        {
            const std::string sc = scene, m = method;
            CheckLightingChange({scene, method, 40}, sc == "light_switch" || (sc == "toggling_light" && m != "RELAX_SPECULAR"), true);
        }
    for (const char* scene : {"static", "camera_translation", "mesh_engine"})
        for (const char* method : consumers)
        {
            Pair p = RunBoth(scene, method, 24);
            INFO(scene << " " << method << ": relMSE " << p.without.mean.relmseDenoised << " -> " << p.with.mean.relmseDenoised);
            CHECK(p.with.mean.relmseDenoised <= 1.05 * p.without.mean.relmseDenoised);
        }
}

TEST_CASE("REBLUR and RELAX with CONFIDENCE at 128x128 where lighting changes", "[confidence_128]")
{
    // Label slow: the four consumers on the light switch and the toggled light and fast_occluder's
    // speculars at 128x128 (truth 64 spp), the trailing light halved as at 64x64
    // (Shaders/Confidence/README.md's H100 tables).
    const char* const consumers[] = {"REBLUR_DIFFUSE", "RELAX_DIFFUSE", "REBLUR_SPECULAR", "RELAX_SPECULAR"};
    for (const char* scene : {"light_switch", "toggling_light"})
        for (const char* method : consumers)
            CheckLightingChange({scene, method, 40, 128},
                                std::string(scene) == "light_switch" || std::string(method) != "RELAX_SPECULAR");
    // fast_occluder's speculars at 128x128: REBLUR_SPECULAR 1.004x before its restarted histories kept
    // the history fix for the debt's frames (README, "fast_occluder: the cost of the restarts").
    CheckLightingChange({"fast_occluder", "RELAX_SPECULAR", 40, 128});
    CheckLightingChange({"fast_occluder", "REBLUR_SPECULAR", 40, 128});
    // REBLUR_DIFFUSE on the blinds' moving stripes, decided over kSeeds (Shaders/Confidence/README.md,
    // "One seed against several").
    CheckLightingChange({"venetian_blinds", "REBLUR_DIFFUSE", 40, 128}, false, true);
}

TEST_CASE("REBLUR and RELAX speculars with CONFIDENCE at 256x256 under moving stripes and a fast occluder", "[confidence_256]")
{
    // Label slow: at 256x256 a sun glint one pixel high crosses the blinds' floor; RELAX_SPECULAR's
    // frames kept by the confidence held it where it had left (venetian_blinds 1.306x, fast_occluder
    // 1.030x with / without confidence) until RELAX_SPECULAR_CONFIDENCE_CLAMP_KNEE
    // (Shaders/Confidence/README.md, "The specular consumers at 256x256").
    for (const char* scene : {"venetian_blinds", "fast_occluder"})
        for (const char* method : {"RELAX_SPECULAR", "REBLUR_SPECULAR"})
            CheckLightingChange({scene, method, 40, 256});
}
