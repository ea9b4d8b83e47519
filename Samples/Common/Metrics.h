// Metrics.h - image quality and temporal metrics for the scene lab (CPU only).
//
// Conventions shared by every function in this header:
//  * Inputs are nrdlab::Image with 1..4 channels. Only the colour channels
//    take part: 1 channel = grey (replicated to grey RGB where a metric needs
//    colour, i.e. FLIP), 2 channels = (R, G) (B taken as 0 by FLIP), 3 = RGB,
//    and the 4th channel (alpha / packed data) is always ignored.
//  * Invalid input (see Image::isValid) or a mismatch in width, height or
//    channel count between the compared images returns kMetricError (-1).
//    Nothing asserts or throws.
//  * Psnr, Ssim, Flip and FlipMap take LINEAR (scene-referred) images and
//    tone-map both of them internally with ToneMap(image, 1) before
//    measuring. The *Ldr variants take display-referred images in [0, 1]
//    (values are only clamped to [0, 1], NaN -> 1) and skip the tone map.
//  * RelMSE and the temporal metrics work on the linear values directly.
#pragma once

#include "Image.h"

#include <cstddef>
#include <vector>

namespace nrdlab
{

// Returned by every metric for invalid or mismatched inputs.
constexpr double kMetricError = -1.0;

// Per-sample relMSE charged for a non-finite test (or reference) value.
constexpr double kRelMseNonFinitePenalty = 1000.0;

// PSNR returned for identical images (and the upper clamp for any PSNR).
constexpr double kPsnrCapDb = 100.0;

// Default FLIP observer: a 0.7 m wide 4K monitor seen from 0.7 m
// (3840 px / 0.7 m * 0.7 m * pi / 180 = 67.02 pixels per degree).
constexpr double kFlipDefaultPpd = 67.02;

// True when both images are valid and have the same width, height and channels.
bool SameShape(const Image& a, const Image& b);

// Mean of every channel of every pixel (0 for an empty image); compared between an output and its
// reference it shows energy bias.
double MeanValue(const Image& image);

// Relative MSE: mean over pixels and colour channels of (t - r)^2 / (r^2 + eps)
// on linear values. A sample whose test or reference value is NaN/Inf
// contributes kRelMseNonFinitePenalty instead of poisoning the mean with NaN.
// Returns -1 on mismatch or if eps is not a positive finite number.
double RelMSE(const Image& test, const Image& ref, double eps = 0.01);

// Means of 'block' x 'block' pixel blocks (the blocks at the right and bottom edges may be cut and
// average the pixels they have), every channel; an empty Image if the input is invalid or block is
// 0. RelMSE of two such images is the error of the low frequencies alone: the noise of a denoised
// image averages out in a block, a region left too bright or too dark (lag) does not.
Image BlockMeans(const Image& image, uint32_t block);

// Reinhard tone map of every channel: v = max(x, 0) * exposure, v / (1 + v),
// clamped to [0, 1]. NaN and +Inf map to 1 so bad pixels show up white.
// Returns an empty Image if the input is invalid.
Image ToneMap(const Image& linear, float exposure = 1.0f);

// PSNR in dB, 10 * log10(1 / MSE), with MSE over colour channels of the
// tone-mapped images (peak 1). Identical images give kPsnrCapDb, never Inf.
double Psnr(const Image& test, const Image& ref);
// Psnr on display-referred images in [0, 1] (no tone map).
double PsnrLdr(const Image& test, const Image& ref);

// Mean SSIM (Wang et al. 2004) on the tone-mapped images: 11x11 Gaussian
// window (sigma 1.5), C1 = (0.01 L)^2, C2 = (0.03 L)^2 with L = 1, computed per
// colour channel and averaged over channels and all pixels. Windows are
// evaluated at every pixel with clamp-to-edge borders, so any size works.
double Ssim(const Image& test, const Image& ref);
// Ssim on display-referred images in [0, 1] (no tone map).
double SsimLdr(const Image& test, const Image& ref);

// Per-pixel LDR FLIP (Andersson et al. 2020) of the tone-mapped images, viewed
// at ppd pixels per degree: single-channel width x height map, values in [0, 1]
// (0 = no perceived difference). The tone-mapped values are treated as linear
// RGB; all filters use clamp-to-edge borders. As in the reference code, the
// colour error is HyAB^0.7 of CSF-filtered, Hunt-adjusted L*a*b*, compressed
// with p_c 0.4 / p_t 0.95; the feature error is (max(|d edge|, |d point|) /
// sqrt(2))^0.5 and FLIP = colour ^ (1 - feature). Returns an empty Image on
// mismatch or if ppd is not a positive finite number.
Image FlipMap(const Image& test, const Image& ref, double ppd = kFlipDefaultPpd);
// Mean of FlipMap; -1 on invalid input.
double Flip(const Image& test, const Image& ref, double ppd = kFlipDefaultPpd);
// FlipMap / Flip on display-referred linear-RGB images in [0, 1] (no tone map).
Image FlipMapLdr(const Image& test, const Image& ref, double ppd = kFlipDefaultPpd);
double FlipLdr(const Image& test, const Image& ref, double ppd = kFlipDefaultPpd);

// Temporal instability between two consecutive frames: mean over pixels and
// colour channels of | |test - testPrev| - |ref - refPrev| | on linear values,
// i.e. frame-to-frame change that the reference does not have (flicker) or
// lacks (lag). Values are first made finite: NaN -> 0, then clamped to
// [-65504, 65504] (the half-float range, so Inf -> 65504). -1 unless all four
// images match in shape.
double TemporalInstability(const Image& testPrev, const Image& test, const Image& refPrev,
                           const Image& ref);

// TemporalInstability of every consecutive pair (frame i-1 -> i), so the result
// has frames.size() - 1 entries. Empty if the sequences differ in length, have
// fewer than 2 frames, or any frame pair is invalid/mismatched.
std::vector<double> TemporalInstabilityPerFrame(const std::vector<Image>& testFrames,
                                                const std::vector<Image>& refFrames);

// Mean of TemporalInstabilityPerFrame; -1 on invalid input.
double TemporalInstabilitySequence(const std::vector<Image>& testFrames,
                                   const std::vector<Image>& refFrames);

// Frames from eventFrame until the error is back within 2 * steadyError for
// good: (index of the last frame >= eventFrame with error > 2 * steadyError)
// + 1 - eventFrame. Non-finite errors count as out of band. Returns 0 if the
// error never left the band, errorPerFrame.size() - eventFrame if it is still
// out of band on the last frame ("did not recover"), and -1 if eventFrame is
// past the end or steadyError is negative or non-finite.
int LagFrames(const std::vector<double>& errorPerFrame, size_t eventFrame, double steadyError);

// Lag after the sudden changes of a sequence's reference. A sudden change is a frame f >=
// max(warmup, 1) whose referenceChangePerFrame[f] exceeds 4x the largest change of frames
// 1 .. warmup - 1 (at least 1e-4); consecutive such frames are one change. For each change,
// LagFrames against the mean error of the frames from the warm-up to the first change (the last
// frame's error if there are none), counted up to the next change. 'frames' is the longest, and
// 'eventFrame' its change; eventFrame -1 (frames 0) when nothing changes suddenly, or on mismatched
// sizes.
struct SuddenChangeLag
{
    int frames = 0;
    int eventFrame = -1;
};
SuddenChangeLag LagAfterSuddenChanges(const std::vector<double>& errorPerFrame,
                                      const std::vector<double>& referenceChangePerFrame, size_t warmup);

} // namespace nrdlab
