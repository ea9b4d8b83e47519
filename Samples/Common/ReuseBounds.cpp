// ReuseBounds.cpp - see ReuseBounds.h.
#include "ReuseBounds.h"

#include "Metrics.h"

#include <algorithm>
#include <cmath>

namespace nrdlab
{
namespace
{

// Catmull-Rom weights of the texels at -1, 0, 1, 2 around fraction t.
void CatmullRom(float t, float w[4])
{
    w[0] = t * (-0.5f + t * (1.0f - 0.5f * t));
    w[1] = 1.0f + t * t * (-2.5f + 1.5f * t);
    w[2] = t * (0.5f + t * (2.0f - 1.5f * t));
    w[3] = t * t * (-0.5f + 0.5f * t);
}

// Whether previous texel (tx, ty) of 'idPrev' holds the surface of a pixel with id 'id' and, with
// 3-channel ids, previous-frame depth 'viewZPrev': the texel's own viewZ (channel 1) must lie within
// 1% of it plus twice the texel's depth slope (the smaller one-sided difference along each axis,
// so that a neighbouring edge does not widen the tolerance): one object can hide parts of itself.
bool SameSurface(const Image& idPrev, int tx, int ty, float id, float viewZPrev)
{
    if (idPrev.at(uint32_t(tx), uint32_t(ty), 0) != id)
        return false;
    if (idPrev.channels < 3)
        return true;
    const int w = int(idPrev.width), h = int(idPrev.height);
    auto z = [&](int x, int y) { return idPrev.at(uint32_t(x), uint32_t(y), 1); };
    const float zt = z(tx, ty);
    auto slope = [&](int dx, int dy) {
        float s = INFINITY;
        if (tx - dx >= 0 && ty - dy >= 0)
            s = std::fabs(zt - z(tx - dx, ty - dy));
        if (tx + dx < w && ty + dy < h)
            s = std::min(s, std::fabs(z(tx + dx, ty + dy) - zt));
        return std::isfinite(s) ? s : 0.0f;
    };
    const float tolerance = 0.01f * std::fabs(viewZPrev) + 2.0f * std::max(slope(1, 0), slope(0, 1));
    return std::fabs(zt - viewZPrev) <= tolerance; // False for NaN.
}

// 'image' at the previous-frame position of pixel (x, y), or false where that position lies
// outside the texel centres of the image (or the motion is not finite), or where no texel around it
// holds the pixel's surface: 'idPrev' (may be null: every texel matches) against 'id' and
// 'viewZPrev' (see SameSurface).
bool Resample(const Image& image, const Image& motion, uint32_t x, uint32_t y, const Image* idPrev, float id,
              float viewZPrev, float* out)
{
    const float u = (float(x) + 0.5f) / float(image.width) + motion.at(x, y, 0);
    const float v = (float(y) + 0.5f) / float(image.height) + motion.at(x, y, 1);
    const float px = u * float(image.width) - 0.5f, py = v * float(image.height) - 0.5f;
    if (!(px >= 0.0f && px <= float(image.width - 1) && py >= 0.0f && py <= float(image.height - 1))) // False for NaN.
        return false;
    const int w = int(image.width), h = int(image.height);
    const int ox = std::min(int(px), std::max(w - 2, 0)), oy = std::min(int(py), std::max(h - 2, 0));
    const float fx = px - float(ox), fy = py - float(oy);
    auto matches = [&](int tx, int ty) { return !idPrev || SameSurface(*idPrev, tx, ty, id, viewZPrev); };
    bool isCubic = ox >= 1 && oy >= 1 && ox + 2 < w && oy + 2 < h;
    for (int j = -1; j <= 2 && isCubic; j++)
        for (int i = -1; i <= 2 && isCubic; i++)
            isCubic = matches(ox + i, oy + j);
    if (isCubic)
    {
        float wx[4], wy[4];
        CatmullRom(fx, wx);
        CatmullRom(fy, wy);
        for (uint32_t c = 0; c < image.channels; c++)
        {
            float sum = 0.0f, lo = image.at(uint32_t(ox), uint32_t(oy), c), hi = lo;
            for (int j = 0; j < 4; j++)
            {
                for (int i = 0; i < 4; i++)
                {
                    const float s = image.at(uint32_t(ox + i - 1), uint32_t(oy + j - 1), c);
                    sum += wx[i] * wy[j] * s;
                    lo = std::min(lo, s);
                    hi = std::max(hi, s);
                }
            }
            out[c] = std::min(std::max(sum, lo), hi); // No ringing beyond the footprint's range.
        }
        return true;
    }
    // Bilinear over the texels of the pixel's surface.
    const int x1 = std::min(ox + 1, w - 1), y1 = std::min(oy + 1, h - 1);
    const int tx[4] = {ox, x1, ox, x1}, ty[4] = {oy, oy, y1, y1};
    const float tw[4] = {(1.0f - fx) * (1.0f - fy), fx * (1.0f - fy), (1.0f - fx) * fy, fx * fy};
    float weight[4], total = 0.0f;
    for (int k = 0; k < 4; k++)
    {
        weight[k] = matches(tx[k], ty[k]) ? tw[k] : 0.0f;
        total += weight[k];
    }
    if (!(total > 0.0f))
        return false;
    for (uint32_t c = 0; c < image.channels; c++)
    {
        float sum = 0.0f;
        for (int k = 0; k < 4; k++)
            sum += weight[k] * image.at(uint32_t(tx[k]), uint32_t(ty[k]), c);
        out[c] = sum / total;
    }
    return true;
}

} // namespace

ReuseBounds::ReuseBounds(float alpha, float exactEpsilon) : ReuseBounds(std::vector<float>{alpha}, exactEpsilon)
{
}

ReuseBounds::ReuseBounds(const std::vector<float>& alphas, float exactEpsilon)
    : m_ExactEpsilon(std::isfinite(exactEpsilon) ? std::max(exactEpsilon, 0.0f) : 0.0f)
{
    for (float alpha : alphas)
        m_Alphas.push_back(std::isfinite(alpha) ? std::min(std::max(alpha, 0.0f), 1.0f) : 1.0f);
    if (m_Alphas.empty())
        m_Alphas.push_back(0.25f);
}

ReuseBoundsFrame ReuseBounds::Add(const Image& noisy, const Image& truth, const Image& motion, const Image* surfaceId)
{
    ReuseBoundsFrame result;
    if (!SameShape(noisy, truth) || !motion.isValid() || motion.channels < 2 || motion.width != truth.width ||
        motion.height != truth.height ||
        (surfaceId && (!surfaceId->isValid() || surfaceId->width != truth.width || surfaceId->height != truth.height)))
    {
        m_TruthPrev = m_OraclePrev = m_SurfaceIdPrev = Image();
        m_AccumulatedPrev.clear();
        return result;
    }
    // Ids on both frames, or on neither.
    const bool hasHistory = SameShape(m_TruthPrev, truth) && (surfaceId != nullptr) == m_SurfaceIdPrev.isValid() &&
                            (!surfaceId || surfaceId->channels == m_SurfaceIdPrev.channels);
    const Image* idPrev = surfaceId ? &m_SurfaceIdPrev : nullptr;
    const size_t oracles = m_Alphas.size();
    Image reprojected = truth;
    std::vector<Image> accumulated(oracles, noisy);
    float value[4];
    for (uint32_t y = 0; y < truth.height; y++)
    {
        for (uint32_t x = 0; x < truth.width; x++)
        {
            const float id = surfaceId ? surfaceId->at(x, y, 0) : 0.0f;
            const float viewZPrev = surfaceId && surfaceId->channels >= 3 ? surfaceId->at(x, y, 2) : 0.0f;
            if (hasHistory && Resample(m_TruthPrev, motion, x, y, idPrev, id, viewZPrev, value))
            {
                for (uint32_t c = 0; c < truth.channels; c++)
                    reprojected.at(x, y, c) = value[c];
            }
            for (size_t k = 0; k < oracles && hasHistory; k++)
            {
                if (Resample(m_AccumulatedPrev[k], motion, x, y, idPrev, id, viewZPrev, value))
                {
                    for (uint32_t c = 0; c < truth.channels; c++)
                        accumulated[k].at(x, y, c) = value[c] + m_Alphas[k] * (noisy.at(x, y, c) - value[c]);
                }
            }
        }
    }
    // The oracle: the truth where it is exactly 0 or 1, the running mean elsewhere.
    Image oracle;
    for (size_t k = 0; k < oracles; k++)
    {
        Image o = accumulated[k];
        for (size_t i = 0; i < o.pixels.size(); i++)
        {
            const float t = truth.pixels[i];
            if (std::fabs(t) <= m_ExactEpsilon || std::fabs(t - 1.0f) <= m_ExactEpsilon)
                o.pixels[i] = t;
        }
        result.oracleRelmseByAlpha.push_back(RelMSE(o, truth));
        if (k == 0)
            oracle = std::move(o);
    }
    result.oracleRelmse = result.oracleRelmseByAlpha[0];
    if (hasHistory)
    {
        result.reprojectedTruthRelmse = RelMSE(reprojected, truth);
        result.oracleInstability = TemporalInstability(m_OraclePrev, oracle, m_TruthPrev, truth);
    }
    m_TruthPrev = truth;
    m_AccumulatedPrev = std::move(accumulated);
    m_OraclePrev = std::move(oracle);
    m_SurfaceIdPrev = surfaceId ? *surfaceId : Image();
    return result;
}

} // namespace nrdlab
