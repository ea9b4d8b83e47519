// ReuseBoundsTests.cpp - the scene lab's temporal-reuse bounds (ReuseBounds.h) on small sequences
// with hand-computed values. Catch2 v2; main is in TestMain.cpp.
#include <catch2/catch.hpp>

#include "ReuseBounds.h"

#include <cmath>

using namespace nrdlab;

namespace
{

// A W x 5 vertical step: 1 from pixel centre 'edge' on (pixel x has its centre at x + 0.5). Rows 1
// and 2 resample by Catmull-Rom, the others bilinearly (their 4x4 block leaves the image).
Image Step(uint32_t width, float edge)
{
    Image image(width, 5, 1);
    for (uint32_t y = 0; y < 5; y++)
        for (uint32_t x = 0; x < width; x++)
            image.at(x, y, 0) = float(x) + 0.5f >= edge ? 1.0f : 0.0f;
    return image;
}

// Uniform motion: uvPrev - uv for content that moved 'pixels' to the right since the last frame.
Image Motion(uint32_t width, uint32_t height, float pixels)
{
    Image motion(width, height, 2);
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++)
            motion.at(x, y, 0) = -pixels / float(width);
    return motion;
}

} // namespace

TEST_CASE("ReuseBounds: a still sequence keeps its truth and accumulates its samples", "[reuse_bounds]")
{
    // Truth 0.5 everywhere, samples alternating 0 and 1 (the first frame 0), no motion; blend
    // factors 0.25 (the reported oracle) and 0.5.
    ReuseBounds bounds(std::vector<float>{0.25f, 0.5f});
    Image truth(4, 3, 1, 0.5f), motion(4, 3, 2);
    float accumulated = 0.0f, accumulatedHalf = 0.0f;
    for (int f = 0; f < 6; f++)
    {
        const float sample = float(f % 2);
        Image noisy(4, 3, 1, sample);
        ReuseBoundsFrame b = bounds.Add(noisy, truth, motion);
        if (f > 0)
        {
            accumulated += 0.25f * (sample - accumulated);
            accumulatedHalf += 0.5f * (sample - accumulatedHalf);
        }
        const double expected = double(accumulated - 0.5f) * double(accumulated - 0.5f) / (0.25 + 0.01);
        const double expectedHalf = double(accumulatedHalf - 0.5f) * double(accumulatedHalf - 0.5f) / (0.25 + 0.01);
        CHECK(b.oracleRelmse == Approx(expected).epsilon(1e-5));
        REQUIRE(b.oracleRelmseByAlpha.size() == 2);
        CHECK(b.oracleRelmseByAlpha[0] == b.oracleRelmse);
        CHECK(b.oracleRelmseByAlpha[1] == Approx(expectedHalf).epsilon(1e-5));
        if (f == 0)
        {
            CHECK(b.reprojectedTruthRelmse == -1.0);
            CHECK(b.oracleInstability == -1.0);
        }
        else
        {
            CHECK(b.reprojectedTruthRelmse == 0.0);
            CHECK(b.oracleInstability > 0.0); // The running mean moves, the truth does not.
        }
    }
}

TEST_CASE("ReuseBounds: whole-pixel motion reprojects exactly", "[reuse_bounds]")
{
    // A pattern moving one pixel right per frame: the history lands on texel centres.
    const uint32_t w = 12, h = 5;
    auto pattern = [&](int shift)
    {
        Image image(w, h, 1);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                image.at(x, y, 0) = float(((int(x) - shift) * 7 + int(y) * 3) & 3) / 3.0f;
        return image;
    };
    ReuseBounds bounds;
    Image motion = Motion(w, h, 1.0f);
    for (int f = 0; f < 4; f++)
    {
        Image truth = pattern(f);
        ReuseBoundsFrame b = bounds.Add(truth, truth, motion);
        if (f > 0)
            CHECK(b.reprojectedTruthRelmse == Approx(0.0).margin(1e-12));
        CHECK(b.oracleRelmse == Approx(0.0).margin(1e-12)); // Noisy == truth: the running mean is exact.
    }
}

TEST_CASE("ReuseBounds: a hard edge at half-pixel motion defeats the reprojected truth, not the oracle",
          "[reuse_bounds]")
{
    // A step moving half a pixel right per frame over 8 pixels: lit from x = 4 on frames 0 and 1,
    // from x = 5 on frame 2. Pixel 4 resamples halfway between texels 3 and 4 (0 and 1): 0.5, by
    // Catmull-Rom as bilinearly. On frame 1 its truth is 1 (relative error 0.25 / 1.01), on frame 2
    // it is 0 (0.25 / 0.01 = 25); every other pixel lands on equal texels, or its Catmull-Rom
    // overshoot is clamped to them. One pixel of 8 in every row.
    ReuseBounds bounds;
    Image motion = Motion(8, 5, 0.5f);
    Image truth0 = Step(8, 4.0f), truth1 = Step(8, 4.5f), truth2 = Step(8, 5.0f);
    REQUIRE(truth1.at(4, 2, 0) == 1.0f);
    REQUIRE(truth2.at(4, 2, 0) == 0.0f);
    bounds.Add(truth0, truth0, motion);
    ReuseBoundsFrame b1 = bounds.Add(truth1, truth1, motion);
    ReuseBoundsFrame b2 = bounds.Add(truth2, truth2, motion);
    CHECK(b1.reprojectedTruthRelmse == Approx(0.25 / 1.01 / 8.0).epsilon(1e-5));
    CHECK(b2.reprojectedTruthRelmse == Approx(25.0 / 8.0).epsilon(1e-5));
    // The truth is 0 or 1 everywhere: the oracle outputs it.
    CHECK(b1.oracleRelmse == 0.0);
    CHECK(b2.oracleRelmse == 0.0);
    CHECK(b2.oracleInstability == 0.0);
}

TEST_CASE("ReuseBounds: surface ids keep a revealed background from reusing the foreground", "[reuse_bounds]")
{
    // 8x5: a foreground (id 1, truth and samples 0.75) covers x < 4 on frame 0 and moves two pixels
    // left, to x < 2 on frame 1, over a still background (id 0, 0.25). Pixels 2 and 3 are revealed:
    // their (zero) motion lands on the foreground's texels. Every position is a texel centre.
    const uint32_t w = 8, h = 5;
    auto frame = [&](uint32_t edge, float fg, float bg)
    {
        Image image(w, h, 1);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                image.at(x, y, 0) = x < edge ? fg : bg;
        return image;
    };
    Image truth0 = frame(4, 0.75f, 0.25f), truth1 = frame(2, 0.75f, 0.25f);
    Image id0 = frame(4, 1.0f, 0.0f), id1 = frame(2, 1.0f, 0.0f);
    Image motion0(w, h, 2), motion1(w, h, 2);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < 2; x++)
            motion1.at(x, y, 0) = 2.0f / float(w); // uvPrev - uv: the foreground was 2 pixels to the right.

    // Without ids the revealed pixels take the foreground: reprojected truth 0.75 against 0.25
    // (0.25 / 0.0725 each), oracle 0.75 + 0.25 (0.25 - 0.75) = 0.625 (0.140625 / 0.0725 each); 2 of
    // 8 pixels of every row.
    ReuseBounds plain;
    plain.Add(truth0, truth0, motion0);
    ReuseBoundsFrame b = plain.Add(truth1, truth1, motion1);
    CHECK(b.reprojectedTruthRelmse == Approx(0.25 / 0.0725 * 2.0 / 8.0).epsilon(1e-5));
    CHECK(b.oracleRelmse == Approx(0.140625 / 0.0725 * 2.0 / 8.0).epsilon(1e-5));

    // With ids they have no history: the current truth, and the oracle restarts from the sample;
    // the foreground reprojects onto its own texels (bilinearly: its 4x4 blocks hold background).
    ReuseBounds withIds;
    withIds.Add(truth0, truth0, motion0, &id0);
    ReuseBoundsFrame c = withIds.Add(truth1, truth1, motion1, &id1);
    CHECK(c.reprojectedTruthRelmse == Approx(0.0).margin(1e-12));
    CHECK(c.oracleRelmse == Approx(0.0).margin(1e-12));
    CHECK(c.oracleInstability == Approx(0.0).margin(1e-12));

    // Ids of another size are rejected and restart the sequence.
    Image wrongSize(4, 5, 1);
    CHECK(withIds.Add(truth1, truth1, motion1, &wrongSize).oracleRelmse == -1.0);
    CHECK(withIds.Add(truth1, truth1, motion1, &id1).reprojectedTruthRelmse == -1.0);
}

TEST_CASE("ReuseBounds: depth in the surface ids keeps an object from reusing a part of itself it hid",
          "[reuse_bounds]")
{
    // As above, but foreground and background are parts of one mesh (id 1 everywhere): the front
    // part at viewZ 1 moves two pixels left and reveals the back part (viewZ 2). The id alone lets
    // the revealed pixels reuse the front part; the previous-frame depth does not.
    const uint32_t w = 8, h = 5;
    auto frame = [&](uint32_t edge, float fg, float bg)
    {
        Image image(w, h, 1);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                image.at(x, y, 0) = x < edge ? fg : bg;
        return image;
    };
    Image truth0 = frame(4, 0.75f, 0.25f), truth1 = frame(2, 0.75f, 0.25f);
    auto ids = [&](uint32_t edge)
    {
        Image image(w, h, 3);
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
            {
                image.at(x, y, 0) = 1.0f;
                image.at(x, y, 1) = x < edge ? 1.0f : 2.0f; // viewZ
                image.at(x, y, 2) = image.at(x, y, 1);      // nothing moves in depth
            }
        return image;
    };
    Image id0 = ids(4), id1 = ids(2);
    Image motion0(w, h, 2), motion1(w, h, 2);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < 2; x++)
            motion1.at(x, y, 0) = 2.0f / float(w);

    Image objectOnly0(w, h, 1, 1.0f), objectOnly1(w, h, 1, 1.0f);
    ReuseBounds byObject;
    byObject.Add(truth0, truth0, motion0, &objectOnly0);
    CHECK(byObject.Add(truth1, truth1, motion1, &objectOnly1).reprojectedTruthRelmse ==
          Approx(0.25 / 0.0725 * 2.0 / 8.0).epsilon(1e-5));

    ReuseBounds byDepth;
    byDepth.Add(truth0, truth0, motion0, &id0);
    ReuseBoundsFrame c = byDepth.Add(truth1, truth1, motion1, &id1);
    CHECK(c.reprojectedTruthRelmse == Approx(0.0).margin(1e-12));
    CHECK(c.oracleRelmse == Approx(0.0).margin(1e-12));

    // A switch between 1- and 3-channel ids restarts the history.
    CHECK(byDepth.Add(truth1, truth1, motion1, &objectOnly1).reprojectedTruthRelmse == -1.0);
}

TEST_CASE("ReuseBounds: mismatched input restarts the sequence", "[reuse_bounds]")
{
    ReuseBounds bounds;
    Image truth(4, 4, 1, 0.5f), motion(4, 4, 2);
    bounds.Add(truth, truth, motion);
    ReuseBoundsFrame bad = bounds.Add(Image(3, 4, 1), truth, motion);
    CHECK(bad.reprojectedTruthRelmse == -1.0);
    CHECK(bad.oracleRelmse == -1.0);
    ReuseBoundsFrame noMotion = bounds.Add(truth, truth, Image(4, 4, 1));
    CHECK(noMotion.oracleRelmse == -1.0);
    // After a restart the next frame is a first frame again.
    ReuseBoundsFrame next = bounds.Add(truth, truth, motion);
    CHECK(next.reprojectedTruthRelmse == -1.0);
    CHECK(next.oracleRelmse == 0.0);
}
