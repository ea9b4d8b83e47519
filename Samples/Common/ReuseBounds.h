// ReuseBounds.h - how far temporal reuse can go on a sequence, measured from its truth (CPU only).
//
// A denoiser that reprojects its history can do no better than the history allows. Two references
// bracket what the scene itself permits, with the same exact motion vectors a denoiser gets:
//  * reprojected truth: the previous frame's noise-free truth, resampled at this frame's
//    reprojected positions (Catmull-Rom over the 4x4 texels, clamped to their range; bilinear
//    where the 4x4 block leaves the image, the current truth where the position lies outside the
//    texel centres). Where the
//    signal holds features narrower than a pixel (hard shadow edges, one-pixel shadows) under
//    sub-pixel motion, this is worse than a 1-spp input that is exact there.
//  * oracle: a running mean (blend factor 'alpha') of the noisy input, resampled the same way,
//    that is replaced by the truth wherever the truth is exactly 0 or 1 (within 'exactEpsilon'):
//    what a temporal method reaches if it always knew which pixels its input already gets right.
//    Meaningful for visibility signals in [0, 1] (shadows). The blend factor that suits a scene
//    best depends on its motion: several can be measured at once (the reprojected truth is
//    computed once for all of them).
// Disocclusion: given a surface id per pixel (the scene lab's object index), previous texels with
// another id than the pixel's are not reused: Catmull-Rom needs all 16 texels of the pixel's
// surface, else the bilinear weights of the matching texels are renormalized; with none, the pixel
// has no history (as outside the image). An object id alone is an exact test only for convex
// objects; a triangle mesh hides parts of itself. With 3-channel ids (object id, this frame's viewZ,
// and the viewZ the pixel's surface point had in the previous frame's camera) a previous texel must
// also hold that depth: within 1% plus twice its own depth slope (the smaller one-sided difference
// per axis). Without ids every texel counts as the same surface.
#pragma once

#include "Image.h"

#include <vector>

namespace nrdlab
{

struct ReuseBoundsFrame
{
    double reprojectedTruthRelmse = -1.0; // -1 on the first frame (or after a size change).
    double oracleRelmse = -1.0;      // With the first blend factor.
    double oracleInstability = -1.0; // TemporalInstability of that oracle against the truth; -1 on the first frame.
    std::vector<double> oracleRelmseByAlpha; // One per blend factor (empty after invalid input).
};

class ReuseBounds
{
public:
    explicit ReuseBounds(float alpha = 0.25f, float exactEpsilon = 0.02f);
    // Oracles with each of 'alphas' (at least one: an empty list measures 0.25).
    explicit ReuseBounds(const std::vector<float>& alphas, float exactEpsilon = 0.02f);

    // One frame: the noisy input and the truth (same shape, 1..4 channels), the motion
    // (>= 2 channels: uvPrev - uv, v down, the size of the image) and optionally a surface id
    // (the size of the image; 1 channel: object id; 3 channels: object id, viewZ, previous-frame
    // viewZ of the pixel's surface point, see above). Ids of another channel count than the last
    // frame's restart the history. Mismatched or invalid
    // input returns all -1 and restarts the sequence.
    ReuseBoundsFrame Add(const Image& noisy, const Image& truth, const Image& motion, const Image* surfaceId = nullptr);

private:
    std::vector<float> m_Alphas;
    float m_ExactEpsilon;
    std::vector<Image> m_AccumulatedPrev; // One per blend factor.
    Image m_TruthPrev, m_OraclePrev, m_SurfaceIdPrev;
};

} // namespace nrdlab
