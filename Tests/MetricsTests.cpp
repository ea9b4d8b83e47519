// MetricsTests.cpp - pins the scene lab's metrics and image I/O (nrd_lab_common)
// on small images with hand-computed values. Catch2 v2; main is in TestMain.cpp.
#include <catch2/catch.hpp>

#include "Image.h"
#include "ImageIO.h"
#include "Metrics.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

using namespace nrdlab;

namespace
{

Image MakeImage(uint32_t w, uint32_t h, uint32_t c, std::vector<float> values)
{
    Image img(w, h, c);
    img.pixels = std::move(values);
    return img;
}

// Deterministic pseudo-random values in [lo, hi).
Image Pattern(uint32_t w, uint32_t h, uint32_t c, float lo, float hi, uint32_t seed)
{
    Image img(w, h, c);
    uint32_t s = seed * 2654435761u + 12345u;
    for (float& v : img.pixels)
    {
        s = s * 1664525u + 1013904223u;
        v = lo + (hi - lo) * float(s >> 8) / float(1u << 24);
    }
    return img;
}

// A black w x h LDR RGB image with a white size x size square at (x0, y0).
Image Square(uint32_t w, uint32_t h, uint32_t x0, uint32_t y0, uint32_t size)
{
    Image img(w, h, 3, 0.0f);
    for (uint32_t y = y0; y < y0 + size && y < h; ++y)
        for (uint32_t x = x0; x < x0 + size && x < w; ++x)
            for (uint32_t c = 0; c < 3; ++c)
                img.at(x, y, c) = 1.0f;
    return img;
}

// A fresh directory under the system temp dir, removed on destruction.
struct TempDir
{
    std::filesystem::path path;

    TempDir()
    {
        const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
        path = std::filesystem::temp_directory_path() /
               ("nrdlab_metrics_" + std::to_string(stamp) + "_" +
                std::to_string(reinterpret_cast<uintptr_t>(this)));
        std::filesystem::create_directories(path);
    }
    ~TempDir()
    {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
};

} // namespace

TEST_CASE("RelMSE of a 2x2 image matches the hand-computed value", "[metrics][relmse]")
{
    // ref = {1, 0, 2, 0.5}, test = {1.5, 0.1, 2, 0.25}, eps = 0.01:
    //   (0.5)^2  / (1    + 0.01) = 0.25   / 1.01 = 0.2475247525
    //   (0.1)^2  / (0    + 0.01) = 0.01   / 0.01 = 1
    //   0        / (4    + 0.01) = 0
    //   (0.25)^2 / (0.25 + 0.01) = 0.0625 / 0.26 = 0.2403846154
    //   mean = 1.4879093679 / 4 = 0.3719773420
    const Image ref = MakeImage(2, 2, 1, {1.0f, 0.0f, 2.0f, 0.5f});
    const Image test = MakeImage(2, 2, 1, {1.5f, 0.1f, 2.0f, 0.25f});
    CHECK(RelMSE(test, ref) == Approx(0.3719773420).epsilon(1e-6));
    CHECK(RelMSE(ref, ref) == 0.0);

    // The same values in all three channels of an RGB image give the same mean.
    Image refRgb(2, 2, 3), testRgb(2, 2, 3);
    for (size_t i = 0; i < 4; ++i)
        for (uint32_t c = 0; c < 3; ++c)
        {
            refRgb.pixels[i * 3 + c] = ref.pixels[i];
            testRgb.pixels[i * 3 + c] = test.pixels[i];
        }
    CHECK(RelMSE(testRgb, refRgb) == Approx(0.3719773420).epsilon(1e-6));
}

TEST_CASE("RelMSE eps keeps black reference pixels finite and scales their weight by 1/eps",
          "[metrics][relmse]")
{
    const Image ref = MakeImage(1, 1, 1, {0.0f});
    const Image test = MakeImage(1, 1, 1, {0.5f});
    // 0.25 / (0 + eps)
    CHECK(RelMSE(test, ref, 0.01) == Approx(25.0));
    CHECK(RelMSE(test, ref, 1.0) == Approx(0.25));
    // eps must be a positive finite number.
    CHECK(RelMSE(test, ref, 0.0) == kMetricError);
    CHECK(RelMSE(test, ref, -1.0) == kMetricError);
    CHECK(RelMSE(test, ref, std::numeric_limits<double>::quiet_NaN()) == kMetricError);
}

TEST_CASE("RelMSE counts non-finite test values as a fixed large error instead of NaN",
          "[metrics][relmse]")
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Image ref = MakeImage(2, 2, 1, {1.0f, 1.0f, 1.0f, 1.0f});
    const Image test = MakeImage(2, 2, 1, {nan, inf, 1.0f, 1.0f});
    // (penalty + penalty + 0 + 0) / 4
    const double v = RelMSE(test, ref);
    CHECK(std::isfinite(v));
    CHECK(v == Approx(kRelMseNonFinitePenalty / 2.0));
}

TEST_CASE("Metrics return -1 when image sizes or channel counts do not match", "[metrics]")
{
    const Image a(4, 4, 3, 0.5f);
    const Image wider(5, 4, 3, 0.5f);
    const Image grey(4, 4, 1, 0.5f);
    const Image empty;
    Image broken(4, 4, 3, 0.5f);
    broken.pixels.pop_back();

    for (const Image* other : std::initializer_list<const Image*>{&wider, &grey, &empty, &broken})
    {
        CHECK(RelMSE(a, *other) == kMetricError);
        CHECK(Psnr(a, *other) == kMetricError);
        CHECK(Ssim(a, *other) == kMetricError);
        CHECK(Flip(a, *other) == kMetricError);
        CHECK(FlipMap(a, *other).pixels.empty());
        CHECK(TemporalInstability(a, a, a, *other) == kMetricError);
    }
    CHECK(Flip(a, a, 0.0) == kMetricError);
    CHECK(ToneMap(broken).pixels.empty());
}

TEST_CASE("ToneMap is Reinhard clamped to [0, 1] and paints NaN and Inf white", "[metrics][tonemap]")
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Image lin = MakeImage(6, 1, 1, {0.0f, 1.0f, 3.0f, -2.0f, nan, inf});
    const Image tm = ToneMap(lin);
    REQUIRE(tm.pixels.size() == 6);
    CHECK(tm.pixels[0] == 0.0f);
    CHECK(tm.pixels[1] == 0.5f);  // 1 / (1 + 1)
    CHECK(tm.pixels[2] == 0.75f); // 3 / (1 + 3)
    CHECK(tm.pixels[3] == 0.0f);  // negative radiance clamps to 0
    CHECK(tm.pixels[4] == 1.0f);
    CHECK(tm.pixels[5] == 1.0f);
    // exposure 2: 1 * 2 / (1 + 2)
    CHECK(ToneMap(lin, 2.0f).pixels[1] == Approx(2.0 / 3.0));
}

TEST_CASE("PSNR of a constant offset image equals 10 log10(1 / offset^2) on tone-mapped values",
          "[metrics][psnr]")
{
    // Linear 1 -> 0.5 and linear 3 -> 0.75 after Reinhard, so the tone-mapped
    // offset is 0.25, MSE = 0.0625 and PSNR = 10 log10(16) = 12.0411998 dB.
    const Image ref(8, 8, 3, 1.0f);
    const Image test(8, 8, 3, 3.0f);
    CHECK(Psnr(test, ref) == Approx(12.0411998266));
    // Display-referred variant: an offset of 0.1 gives 10 log10(100) = 20 dB.
    CHECK(PsnrLdr(Image(8, 8, 3, 0.6f), Image(8, 8, 3, 0.5f)) == Approx(20.0).epsilon(1e-5));
}

TEST_CASE("PSNR of identical images is the documented cap, not infinity", "[metrics][psnr]")
{
    const Image img = Pattern(8, 8, 3, 0.0f, 4.0f, 1);
    CHECK(Psnr(img, img) == kPsnrCapDb);
    CHECK(PsnrLdr(img, img) == kPsnrCapDb);
}

TEST_CASE("SSIM of identical images is exactly 1", "[metrics][ssim]")
{
    const Image img = Pattern(16, 12, 3, 0.0f, 2.0f, 2);
    CHECK(Ssim(img, img) == 1.0);
    CHECK(SsimLdr(img, img) == 1.0);
}

TEST_CASE("SSIM of two constant images equals the luminance term (2 mu1 mu2 + C1) / (mu1^2 + mu2^2 + C1)",
          "[metrics][ssim]")
{
    // Constant images have zero variance and covariance, so every window gives
    // [(2 mu1 mu2 + C1)(0 + C2)] / [(mu1^2 + mu2^2 + C1)(0 + C2)].
    // Linear 1 -> mu1 = 0.5, linear 3 -> mu2 = 0.75, C1 = 0.01^2 = 1e-4:
    //   (0.75 + 1e-4) / (0.25 + 0.5625 + 1e-4) = 0.7501 / 0.8126 = 0.9230863894
    const Image a(12, 12, 3, 1.0f);
    const Image b(12, 12, 3, 3.0f);
    CHECK(Ssim(a, b) == Approx(0.9230863894).epsilon(1e-9));
    // Display-referred: mu 0.2 and 0.4 -> (0.16 + 1e-4) / (0.2 + 1e-4) = 0.8000999500
    CHECK(SsimLdr(Image(9, 7, 1, 0.2f), Image(9, 7, 1, 0.4f)) == Approx(0.8000999500).epsilon(1e-6));
}

TEST_CASE("SSIM is symmetric and drops when noise is added", "[metrics][ssim]")
{
    const Image ref = Pattern(24, 20, 3, 0.0f, 1.0f, 3);
    Image noisy = ref;
    const Image noise = Pattern(24, 20, 3, -0.5f, 0.5f, 4);
    for (size_t i = 0; i < noisy.pixels.size(); ++i)
        noisy.pixels[i] = std::max(0.0f, noisy.pixels[i] + noise.pixels[i]);
    const double s = Ssim(noisy, ref);
    CHECK(s < 0.95);
    CHECK(s > 0.0);
    CHECK(Ssim(ref, noisy) == Approx(s).epsilon(1e-12));
}

TEST_CASE("FLIP of identical images is 0", "[metrics][flip]")
{
    const Image img = Pattern(20, 16, 3, 0.0f, 3.0f, 5);
    CHECK(Flip(img, img) == 0.0);
    const Image map = FlipMap(img, img);
    REQUIRE(map.width == 20);
    REQUIRE(map.height == 16);
    REQUIRE(map.channels == 1);
    for (float v : map.pixels)
        CHECK(v == 0.0f);
}

TEST_CASE("FLIP of black versus white is the hand-derived 0.96738 at every pixel", "[metrics][flip]")
{
    // Uniform images: the CSF filters are normalised, so filtering changes
    // nothing, and a flat image has no edges or points, so the feature error
    // is 0 and FLIP = colour error (exponent 1 - 0).
    //   black L*a*b* = (0, 0, 0), white = (100, 0, 0); Hunt-adjusted the same.
    //   HyAB = |100 - 0| + 0 = 100;  100^0.7 = 25.1189
    //   cmax: green (0,1,0) -> Lab (87.736, -86.178, 83.181), Hunt (87.736, -75.610, 72.981)
    //         blue  (0,0,1) -> Lab (32.298,  79.194, -107.86), Hunt (32.298, 25.578, -34.836)
    //         HyAB = 55.438 + sqrt(101.188^2 + 107.818^2) = 55.438 + 147.864 = 203.302
    //         cmax = 203.302^0.7 = 41.2761
    //   knee = pc * cmax = 0.4 * 41.2761 = 16.5104 < 25.1189, so
    //   FLIP = pt + (25.1189 - 16.5104) / (41.2761 - 16.5104) * (1 - pt)
    //        = 0.95 + 0.34760 * 0.05 = 0.96738
    // This sits just above p_t = 0.95, i.e. in the compressed top of the range
    // that the paper reserves for differences beyond 40% of the green-blue one.
    const double expected = 0.9673797615;
    CHECK(FlipLdr(Image(16, 16, 3, 1.0f), Image(16, 16, 3, 0.0f)) == Approx(expected).epsilon(1e-5));
    // Linear 1e9 tone-maps to exactly 1.0f, so the linear entry point agrees.
    const Image map = FlipMap(Image(16, 16, 3, 0.0f), Image(16, 16, 3, 1e9f));
    REQUIRE(map.pixels.size() == 256);
    for (float v : map.pixels)
        CHECK(v == Approx(expected).epsilon(1e-5));

    // Uniform greys 0.5 vs 0.55: L* 76.0693 vs 79.0413 -> HyAB 2.97201,
    // ^0.7 = 2.14356 < knee -> 0.95 / 16.5104 * 2.14356 = 0.123339.
    CHECK(FlipLdr(Image(8, 8, 3, 0.55f), Image(8, 8, 3, 0.5f)) == Approx(0.1233388204).epsilon(1e-4));
}

TEST_CASE("FLIP grows monotonically with the size of a colour difference", "[metrics][flip]")
{
    const Image ref(12, 12, 3, 0.5f);
    double previous = 0.0;
    for (float d : {0.02f, 0.05f, 0.1f, 0.2f, 0.4f})
    {
        const double f = FlipLdr(Image(12, 12, 3, 0.5f + d), ref);
        CHECK(f > previous);
        previous = f;
    }
    CHECK(previous < 1.0);
}

TEST_CASE("FLIP of a small shift is smaller than FLIP of a large shift", "[metrics][flip]")
{
    const Image ref = Square(32, 32, 12, 12, 6);
    const double small = FlipLdr(Square(32, 32, 13, 12, 6), ref);
    const double large = FlipLdr(Square(32, 32, 16, 12, 6), ref);
    CHECK(small > 0.0);
    CHECK(small < large);
    // Symmetric in its arguments (HyAB and feature differences are).
    CHECK(FlipLdr(ref, Square(32, 32, 16, 12, 6)) == Approx(large).epsilon(1e-6));
}

TEST_CASE("FLIP replicates single-channel images to grey and ignores the 4th channel",
          "[metrics][flip]")
{
    const Image grey = Pattern(10, 10, 1, 0.0f, 1.0f, 6);
    const Image greyRef = Pattern(10, 10, 1, 0.0f, 1.0f, 7);
    Image rgb(10, 10, 3), rgbRef(10, 10, 3), rgba(10, 10, 4), rgbaRef(10, 10, 4);
    for (size_t i = 0; i < 100; ++i)
    {
        for (uint32_t c = 0; c < 3; ++c)
        {
            rgb.pixels[i * 3 + c] = rgba.pixels[i * 4 + c] = grey.pixels[i];
            rgbRef.pixels[i * 3 + c] = rgbaRef.pixels[i * 4 + c] = greyRef.pixels[i];
        }
        rgba.pixels[i * 4 + 3] = 100.0f * float(i); // alpha differs wildly
        rgbaRef.pixels[i * 4 + 3] = -5.0f;
    }
    const double f = Flip(grey, greyRef);
    CHECK(f > 0.0);
    CHECK(Flip(rgb, rgbRef) == Approx(f).epsilon(1e-6));
    CHECK(Flip(rgba, rgbaRef) == Approx(f).epsilon(1e-6));
    CHECK(Ssim(rgba, rgbaRef) == Approx(Ssim(grey, greyRef)).epsilon(1e-9));
}

TEST_CASE("Temporal instability of a static test and a static reference is 0", "[metrics][temporal]")
{
    const Image test = Pattern(6, 5, 3, 0.0f, 2.0f, 8);
    const Image ref = Pattern(6, 5, 3, 0.0f, 2.0f, 9);
    CHECK(TemporalInstability(test, test, ref, ref) == 0.0);
}

TEST_CASE("Temporal instability of a flickering pixel equals its amplitude times the flickering fraction",
          "[metrics][temporal]")
{
    // 2x2 RGB, reference static at 1; the test pixel (0,0) jumps by a = 0.5 in
    // all channels: | |0.5| - |0| | on 3 of 12 samples -> 0.5 * 3 / 12 = 0.125.
    const Image ref(2, 2, 3, 1.0f);
    const Image prev(2, 2, 3, 1.0f);
    Image cur = prev;
    for (uint32_t c = 0; c < 3; ++c)
        cur.at(0, 0, c) = 1.5f;
    CHECK(TemporalInstability(prev, cur, ref, ref) == Approx(0.125));
    // A change the reference has too (e.g. a light switching on) is not instability.
    CHECK(TemporalInstability(prev, cur, prev, cur) == 0.0);
    // NaN reads as 0: 1 -> NaN is a jump of 1 on 3 of 12 samples.
    Image bad = prev;
    for (uint32_t c = 0; c < 3; ++c)
        bad.at(1, 1, c) = std::numeric_limits<float>::quiet_NaN();
    CHECK(TemporalInstability(prev, bad, ref, ref) == Approx(0.25));
}

TEST_CASE("Sequence temporal instability averages consecutive frame pairs", "[metrics][temporal]")
{
    // 1x1 grey. Reference ramps 0,1,2,3; test follows it but with +a on odd
    // frames (a = 0.25): per pair | |1 +- a| - 1 | = a, so every entry is a.
    const float a = 0.25f;
    std::vector<Image> ref, test;
    for (int i = 0; i < 4; ++i)
    {
        ref.push_back(Image(1, 1, 1, float(i)));
        test.push_back(Image(1, 1, 1, float(i) + (i % 2 ? a : 0.0f)));
    }
    const std::vector<double> perFrame = TemporalInstabilityPerFrame(test, ref);
    REQUIRE(perFrame.size() == 3);
    for (double v : perFrame)
        CHECK(v == Approx(a));
    CHECK(TemporalInstabilitySequence(test, ref) == Approx(a));
    CHECK(TemporalInstabilitySequence(ref, ref) == 0.0);
    CHECK(TemporalInstabilitySequence({test[0]}, {ref[0]}) == kMetricError);
    CHECK(TemporalInstabilityPerFrame(test, {ref[0], ref[1]}).empty());
}

TEST_CASE("LagFrames finds the known recovery frame of a synthetic error curve", "[metrics][lag]")
{
    // Steady error 0.1 (band 0.2), event at frame 10, decay 1.0 0.6 0.3 | 0.19 ...
    // Frame 13 is the first one back in band for good: lag = 13 - 10 = 3.
    std::vector<double> e(10, 0.1);
    for (double v : {1.0, 0.6, 0.3, 0.19, 0.12, 0.1, 0.1, 0.1})
        e.push_back(v);
    CHECK(LagFrames(e, 10, 0.1) == 3);

    // A one-frame dip inside the transient does not count as recovery.
    std::vector<double> dip(10, 0.1);
    for (double v : {1.0, 0.15, 0.5, 0.1, 0.1})
        dip.push_back(v);
    CHECK(LagFrames(dip, 10, 0.1) == 3);

    // Error that only rises one frame after the event still counts from the event.
    std::vector<double> late(10, 0.1);
    for (double v : {0.1, 0.8, 0.1, 0.1})
        late.push_back(v);
    CHECK(LagFrames(late, 10, 0.1) == 2);
}

TEST_CASE("LagFrames returns 0 when the error never leaves and the frames left when it never recovers",
          "[metrics][lag]")
{
    const std::vector<double> flat(20, 0.1);
    CHECK(LagFrames(flat, 10, 0.1) == 0);

    std::vector<double> stuck(10, 0.1);
    for (int i = 0; i < 6; ++i)
        stuck.push_back(0.5);
    CHECK(LagFrames(stuck, 10, 0.1) == 6); // size - eventFrame: did not recover

    std::vector<double> withNan = flat;
    withNan.back() = std::numeric_limits<double>::quiet_NaN();
    CHECK(LagFrames(withNan, 10, 0.1) == 10);

    CHECK(LagFrames(flat, 20, 0.1) == -1);
    CHECK(LagFrames(flat, 10, -1.0) == -1);
}

TEST_CASE("LagAfterSuddenChanges counts each change up to the next one and keeps the longest",
          "[metrics][lag]")
{
    // 24 frames, warm-up 4 (reference changes 0.01 there). The reference jumps at frames 10 and 11
    // (one change) and at 16 (a light back on). Steady error 0.1 over frames 4..9 (band 0.2).
    std::vector<double> change(24, 0.01), error(24, 0.1);
    change[10] = change[11] = 0.5;
    change[16] = 0.5;
    // First change: out of band on 10 and 11, back on 12: lag 2. The error of the frames between
    // the changes stays in band, so the second change's recovery is not charged to the first.
    error[10] = 1.0;
    error[11] = 0.3;
    // Second change: out of band on 16, 17, 18 (a dip on 17 does not count): lag 3.
    error[16] = 0.9;
    error[17] = 0.15;
    error[18] = 0.25;
    SuddenChangeLag lag = LagAfterSuddenChanges(error, change, 4);
    CHECK(lag.frames == 3);
    CHECK(lag.eventFrame == 16);

    // The same curve with the first change slower (out of band until the second one): its window
    // ends at frame 16, so its lag is 6 (16 - 10), the longest.
    std::vector<double> slow = error;
    for (size_t f = 12; f < 16; f++)
        slow[f] = 0.5;
    lag = LagAfterSuddenChanges(slow, change, 4);
    CHECK(lag.frames == 6);
    CHECK(lag.eventFrame == 10);

    // Nothing sudden (every change within 4x of the warm-up's largest): no event.
    std::vector<double> calm(24, 0.01);
    calm[2] = 0.2;
    calm[12] = 0.5;
    lag = LagAfterSuddenChanges(error, calm, 4);
    CHECK(lag.eventFrame == -1);
    CHECK(lag.frames == 0);

    // Mismatched sizes: no event.
    CHECK(LagAfterSuddenChanges(error, std::vector<double>(23, 0.01), 4).eventFrame == -1);
}

TEST_CASE("EXR round trip is exact for float and within half precision for half", "[io][exr]")
{
    TempDir dir;
    std::string err;

    // 17x9 (ZIP-compressed path) RGBA with negative, tiny, huge and non-finite values.
    Image rgba = Pattern(17, 9, 4, -4.0f, 100.0f, 10);
    rgba.pixels[0] = 1e-30f;
    rgba.pixels[1] = 3.0e38f;
    rgba.pixels[2] = std::numeric_limits<float>::infinity();
    rgba.pixels[3] = std::numeric_limits<float>::quiet_NaN();
    REQUIRE(WriteExr(dir.file("rgba.exr"), rgba, &err));
    Image back;
    REQUIRE(ReadExr(dir.file("rgba.exr"), back, &err));
    REQUIRE(back.width == 17);
    REQUIRE(back.height == 9);
    REQUIRE(back.channels == 4);
    CHECK(std::memcmp(back.pixels.data(), rgba.pixels.data(), rgba.pixels.size() * sizeof(float)) == 0);

    // Small (uncompressed path) single-channel and two-channel images.
    for (uint32_t channels : {1u, 2u, 3u})
    {
        const Image small = Pattern(3, 2, channels, -1.0f, 1.0f, 11 + channels);
        const std::string path = dir.file("small" + std::to_string(channels) + ".exr");
        REQUIRE(WriteExr(path, small, &err));
        Image smallBack;
        REQUIRE(ReadExr(path, smallBack, &err));
        REQUIRE(smallBack.channels == channels);
        CHECK(smallBack.pixels == small.pixels);
    }

    // Half: relative error at most 2^-11 for normal values.
    const Image hdr = Pattern(20, 18, 3, 0.01f, 1000.0f, 14);
    REQUIRE(WriteExr(dir.file("half.exr"), hdr, &err, true));
    Image halfBack;
    REQUIRE(ReadExr(dir.file("half.exr"), halfBack, &err));
    REQUIRE(halfBack.pixels.size() == hdr.pixels.size());
    for (size_t i = 0; i < hdr.pixels.size(); ++i)
        CHECK(std::abs(halfBack.pixels[i] - hdr.pixels[i]) <= hdr.pixels[i] * (1.0f / 2048.0f));
}

TEST_CASE("PNG round trip is within 1/255 of the sRGB-encoded tone map", "[io][png]")
{
    TempDir dir;
    std::string err;
    const Image lin = Pattern(7, 5, 3, 0.0f, 8.0f, 15);
    REQUIRE(WritePng(dir.file("rgb.png"), lin, &err));

    Image encoded;
    REQUIRE(ReadPng(dir.file("rgb.png"), encoded, &err));
    REQUIRE(encoded.width == 7);
    REQUIRE(encoded.height == 5);
    REQUIRE(encoded.channels == 3);
    const Image tm = ToneMap(lin);
    for (size_t i = 0; i < lin.pixels.size(); ++i)
        CHECK(std::abs(encoded.pixels[i] - LinearToSrgb(tm.pixels[i])) <= 1.0f / 255.0f);

    // Decoded back to linear it matches the tone map itself (sRGB decode
    // stretches one code value by at most ~2.3x near white).
    Image decoded;
    REQUIRE(ReadPng(dir.file("rgb.png"), decoded, &err, true));
    for (size_t i = 0; i < lin.pixels.size(); ++i)
        CHECK(std::abs(decoded.pixels[i] - tm.pixels[i]) <= 2.5f / 255.0f);

    // Grey images stay single-channel; the alpha of RGBA images is not written.
    REQUIRE(WritePng(dir.file("grey.png"), Image(4, 3, 1, 1.0f), &err));
    Image grey;
    REQUIRE(ReadPng(dir.file("grey.png"), grey, &err));
    CHECK(grey.channels == 1);
    CHECK(grey.pixels[0] == Approx(std::round(LinearToSrgb(0.5f) * 255.0f) / 255.0f));
    REQUIRE(WritePng(dir.file("rgba.png"), Image(4, 3, 4, 1.0f), &err));
    Image rgb;
    REQUIRE(ReadPng(dir.file("rgba.png"), rgb, &err));
    CHECK(rgb.channels == 3);
}

TEST_CASE("Image readers and writers report errors on bad paths and bad images instead of crashing",
          "[io]")
{
    TempDir dir;
    const Image img(4, 4, 3, 0.5f);
    std::string err;

    CHECK_FALSE(WritePng("/nonexistent-nrdlab-dir/x.png", img, &err));
    CHECK_FALSE(err.empty());
    err.clear();
    CHECK_FALSE(WriteExr("/nonexistent-nrdlab-dir/x.exr", img, &err));
    CHECK_FALSE(err.empty());
    CHECK_FALSE(WritePng(dir.path.string(), img, &err)); // a directory
    CHECK_FALSE(WriteExr("", img, &err));
    CHECK_FALSE(WritePng(dir.file("empty.png"), Image(), &err));
    CHECK_FALSE(WriteExr(dir.file("empty.exr"), Image(), nullptr));

    Image out(2, 2, 1, 7.0f);
    CHECK_FALSE(ReadPng("/nonexistent-nrdlab-dir/x.png", out, &err));
    CHECK_FALSE(ReadExr("/nonexistent-nrdlab-dir/x.exr", out, &err));
    {
        std::ofstream garbage(dir.file("garbage.exr"), std::ios::binary);
        garbage << "not an exr file at all";
    }
    CHECK_FALSE(ReadExr(dir.file("garbage.exr"), out, &err));
    CHECK_FALSE(ReadPng(dir.file("garbage.exr"), out, &err));
    REQUIRE(WritePng(dir.file("ok.png"), img, &err));
    CHECK_FALSE(ReadExr(dir.file("ok.png"), out, &err));
    // Failed reads leave the output untouched.
    CHECK(out.width == 2);
    CHECK(out.pixels[0] == 7.0f);
}

TEST_CASE("Side-by-side strip places the images left to right with gaps in between", "[io][strip]")
{
    TempDir dir;
    std::string err;
    const Image a(4, 3, 3, 0.0f);
    const Image b(5, 4, 1, 3.0f);
    const Image c(6, 2, 4, 0.0f);
    const Image strip = MakeSideBySide({a, b, c}, 2, 1.0f);
    REQUIRE(strip.width == 4 + 5 + 6 + 2 * 2);
    REQUIRE(strip.height == 4);
    REQUIRE(strip.channels == 3);
    CHECK(strip.at(0, 0, 0) == 0.0f);  // a
    CHECK(strip.at(4, 0, 0) == 1.0f);  // gap
    CHECK(strip.at(6, 3, 2) == 3.0f);  // b, grey replicated
    CHECK(strip.at(0, 3, 0) == 1.0f);  // below a (shorter) is fill
    CHECK(strip.at(13, 1, 1) == 0.0f); // c

    REQUIRE(WriteSideBySide(dir.file("strip.png"), {a, b, c}, &err, 2));
    Image png;
    REQUIRE(ReadPng(dir.file("strip.png"), png, &err));
    CHECK(png.width == 19);
    CHECK(png.height == 4);
    REQUIRE(WriteSideBySide(dir.file("strip.EXR"), {a, b, c}, &err, 2));
    Image exr;
    REQUIRE(ReadExr(dir.file("strip.EXR"), exr, &err));
    CHECK(exr.pixels == strip.pixels);

    CHECK_FALSE(WriteSideBySide(dir.file("none.png"), {}, &err));
    CHECK_FALSE(err.empty());
}

TEST_CASE("MeanValue averages every channel of every pixel", "[metrics]")
{
    nrdlab::Image image(2, 1, 3);
    image.pixels = {1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 9.0f};
    CHECK(nrdlab::MeanValue(image) == Approx(4.0));
    CHECK(nrdlab::MeanValue(nrdlab::Image()) == 0.0);
}

TEST_CASE("BlockMeans averages each block, the cut blocks at the edges over the pixels they have", "[metrics]")
{
    // 5x3, one channel: values x + 10 y; blocks of 2: columns {0,1}, {2,3}, {4}; rows {0,1}, {2}.
    nrdlab::Image image(5, 3, 1);
    for (uint32_t y = 0; y < 3; y++)
        for (uint32_t x = 0; x < 5; x++)
            image.at(x, y, 0) = float(x + 10 * y);
    nrdlab::Image means = nrdlab::BlockMeans(image, 2);
    REQUIRE(means.width == 3);
    REQUIRE(means.height == 2);
    REQUIRE(means.channels == 1);
    CHECK(means.at(0, 0, 0) == Approx(5.5));  // 0, 1, 10, 11
    CHECK(means.at(2, 0, 0) == Approx(9.0));  // 4, 14
    CHECK(means.at(1, 1, 0) == Approx(22.5)); // 22, 23
    CHECK(means.at(2, 1, 0) == Approx(24.0)); // 24
    CHECK_FALSE(nrdlab::BlockMeans(image, 0).isValid());
    CHECK_FALSE(nrdlab::BlockMeans(nrdlab::Image(), 8).isValid());
}

TEST_CASE("RelMSE of block means leaves out zero-mean noise and keeps a region that is too bright", "[metrics]")
{
    // Noise of +-0.5 alternating pixel by pixel around 1: relMSE 0.25 / 1.01 per pixel, 0 over
    // 2x2 blocks. The same image 20% too bright in its left half keeps that error in the blocks.
    nrdlab::Image truth(8, 8, 1, 1.0f), noisy(8, 8, 1), lagging(8, 8, 1);
    for (uint32_t y = 0; y < 8; y++)
        for (uint32_t x = 0; x < 8; x++)
        {
            noisy.at(x, y, 0) = (x + y) % 2 ? 1.5f : 0.5f;
            lagging.at(x, y, 0) = noisy.at(x, y, 0) * (x < 4 ? 1.2f : 1.0f);
        }
    CHECK(nrdlab::RelMSE(noisy, truth) == Approx(0.25 / 1.01));
    CHECK(nrdlab::RelMSE(nrdlab::BlockMeans(noisy, 2), nrdlab::BlockMeans(truth, 2)) == Approx(0.0).margin(1e-12));
    CHECK(nrdlab::RelMSE(nrdlab::BlockMeans(lagging, 2), nrdlab::BlockMeans(truth, 2)) == Approx(0.5 * 0.04 / 1.01));
}
