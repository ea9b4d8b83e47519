// Metrics.cpp - see Metrics.h for the contract of every public function.
#include "Metrics.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace nrdlab
{
namespace
{

constexpr double kPi = 3.14159265358979323846;

uint32_t ColourChannels(const Image& image)
{
    return std::min<uint32_t>(image.channels, 3u);
}

// Display-referred sanitising used by the *Ldr metrics: NaN -> 1, clamp [0, 1].
float SanitizeLdr(float v)
{
    if (std::isnan(v))
        return 1.0f;
    return std::min(std::max(v, 0.0f), 1.0f);
}

float ToneMapValue(float x, float exposure)
{
    if (std::isnan(x))
        return 1.0f;
    const float v = std::max(x, 0.0f) * exposure;
    if (std::isnan(v)) // e.g. Inf * 0 exposure
        return 1.0f;
    if (std::isinf(v)) // +Inf -> white, -Inf (negative exposure) -> black
        return v > 0.0f ? 1.0f : 0.0f;
    return SanitizeLdr(v / (1.0f + v));
}

float DisplayValue(float x, bool toneMap)
{
    return toneMap ? ToneMapValue(x, 1.0f) : SanitizeLdr(x);
}

// Colour channels of an image as display-referred planes (one per colour channel).
std::vector<std::vector<double>> DisplayPlanes(const Image& image, bool toneMap)
{
    const uint32_t cc = ColourChannels(image);
    const size_t n = image.pixelCount();
    std::vector<std::vector<double>> planes(cc, std::vector<double>(n));
    for (size_t i = 0; i < n; ++i)
        for (uint32_t c = 0; c < cc; ++c)
            planes[c][i] = DisplayValue(image.pixels[i * image.channels + c], toneMap);
    return planes;
}

// ---------------------------------------------------------------------------
// Separable correlation with clamp-to-edge borders. Kernels have odd length
// 2r + 1 and tap k applies to offset k - r. Accumulation is in double.

template <typename T>
void CorrelateRows(const std::vector<T>& src, std::vector<T>& dst, int w, int h,
                   const std::vector<double>& kernel)
{
    const int r = int(kernel.size() / 2);
    dst.resize(src.size());
    for (int y = 0; y < h; ++y)
    {
        const T* row = src.data() + size_t(y) * size_t(w);
        T* out = dst.data() + size_t(y) * size_t(w);
        for (int x = 0; x < w; ++x)
        {
            double sum = 0.0;
            for (int k = -r; k <= r; ++k)
            {
                const int xs = std::min(std::max(x + k, 0), w - 1);
                sum += kernel[size_t(k + r)] * double(row[xs]);
            }
            out[x] = T(sum);
        }
    }
}

template <typename T>
void CorrelateCols(const std::vector<T>& src, std::vector<T>& dst, int w, int h,
                   const std::vector<double>& kernel)
{
    const int r = int(kernel.size() / 2);
    dst.resize(src.size());
    for (int y = 0; y < h; ++y)
    {
        T* out = dst.data() + size_t(y) * size_t(w);
        for (int x = 0; x < w; ++x)
        {
            double sum = 0.0;
            for (int k = -r; k <= r; ++k)
            {
                const int ys = std::min(std::max(y + k, 0), h - 1);
                sum += kernel[size_t(k + r)] * double(src[size_t(ys) * size_t(w) + size_t(x)]);
            }
            out[x] = T(sum);
        }
    }
}

template <typename T>
void CorrelateSeparable(const std::vector<T>& src, std::vector<T>& dst, std::vector<T>& tmp, int w,
                        int h, const std::vector<double>& kx, const std::vector<double>& ky)
{
    CorrelateRows(src, tmp, w, h, kx);
    CorrelateCols(tmp, dst, w, h, ky);
}

// ---------------------------------------------------------------------------
// SSIM

double SsimPlanes(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b,
                  int w, int h)
{
    if (a == b)
        return 1.0; // exact by definition; avoids any floating-point residue

    constexpr double kC1 = 0.01 * 0.01; // (K1 L)^2, L = 1
    constexpr double kC2 = 0.03 * 0.03; // (K2 L)^2
    constexpr int kRadius = 5;          // 11 taps
    constexpr double kSigma = 1.5;

    std::vector<double> g(2 * kRadius + 1);
    double gsum = 0.0;
    for (int i = -kRadius; i <= kRadius; ++i)
    {
        g[size_t(i + kRadius)] = std::exp(-double(i * i) / (2.0 * kSigma * kSigma));
        gsum += g[size_t(i + kRadius)];
    }
    for (double& v : g)
        v /= gsum;

    const size_t n = size_t(w) * size_t(h);
    std::vector<double> prod(n), tmp, muA, muB, aa, bb, ab;
    double total = 0.0;
    for (size_t c = 0; c < a.size(); ++c)
    {
        CorrelateSeparable(a[c], muA, tmp, w, h, g, g);
        CorrelateSeparable(b[c], muB, tmp, w, h, g, g);
        for (size_t i = 0; i < n; ++i)
            prod[i] = a[c][i] * a[c][i];
        CorrelateSeparable(prod, aa, tmp, w, h, g, g);
        for (size_t i = 0; i < n; ++i)
            prod[i] = b[c][i] * b[c][i];
        CorrelateSeparable(prod, bb, tmp, w, h, g, g);
        for (size_t i = 0; i < n; ++i)
            prod[i] = a[c][i] * b[c][i];
        CorrelateSeparable(prod, ab, tmp, w, h, g, g);

        for (size_t i = 0; i < n; ++i)
        {
            const double ma = muA[i], mb = muB[i];
            const double va = aa[i] - ma * ma;
            const double vb = bb[i] - mb * mb;
            const double cov = ab[i] - ma * mb;
            const double num = (2.0 * ma * mb + kC1) * (2.0 * cov + kC2);
            const double den = (ma * ma + mb * mb + kC1) * (va + vb + kC2);
            total += num / den;
        }
    }
    return total / double(n * a.size());
}

double SsimImpl(const Image& test, const Image& ref, bool toneMap)
{
    if (!SameShape(test, ref))
        return kMetricError;
    return SsimPlanes(DisplayPlanes(test, toneMap), DisplayPlanes(ref, toneMap), int(test.width),
                      int(test.height));
}

double PsnrImpl(const Image& test, const Image& ref, bool toneMap)
{
    if (!SameShape(test, ref))
        return kMetricError;
    const uint32_t cc = ColourChannels(test);
    double sum = 0.0;
    for (size_t i = 0; i < test.pixelCount(); ++i)
    {
        for (uint32_t c = 0; c < cc; ++c)
        {
            const double d = double(DisplayValue(test.pixels[i * test.channels + c], toneMap)) -
                             double(DisplayValue(ref.pixels[i * ref.channels + c], toneMap));
            sum += d * d;
        }
    }
    const double mse = sum / double(test.pixelCount() * cc);
    if (mse <= 0.0)
        return kPsnrCapDb;
    return std::min(kPsnrCapDb, 10.0 * std::log10(1.0 / mse));
}

// ---------------------------------------------------------------------------
// FLIP (LDR), after Andersson et al. 2020.

// Linear sRGB (D65) -> CIE XYZ, written as exact ratios of the sRGB primaries.
// Written row by row (GLM's constructor takes columns, hence the transpose).
const glm::dmat3 kRgbToXyz =
    glm::transpose(glm::dmat3(10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0,
                              2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0,
                              1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0));
const glm::dmat3 kXyzToRgb = glm::inverse(kRgbToXyz);
// Reference white (D65): XYZ of linear RGB (1, 1, 1); its Y is 1.
const glm::dvec3 kWhite = kRgbToXyz * glm::dvec3(1.0);

// Linear RGB -> YCxCz (opponent space of the FLIP paper).
glm::dvec3 RgbToYcxcz(const glm::dvec3& rgb)
{
    const glm::dvec3 n = kRgbToXyz * rgb / kWhite;
    return glm::dvec3(116.0 * n.y - 16.0, 500.0 * (n.x - n.y), 200.0 * (n.y - n.z));
}

glm::dvec3 YcxczToRgb(const glm::dvec3& ycc)
{
    const double yn = (ycc.x + 16.0) / 116.0;
    const double xn = yn + ycc.y / 500.0;
    const double zn = yn - ycc.z / 200.0;
    return kXyzToRgb * (glm::dvec3(xn, yn, zn) * kWhite);
}

// Linear RGB -> CIE L*a*b* (D65) -> Hunt-adjusted (a, b scaled by 0.01 L).
glm::dvec3 RgbToHuntLab(const glm::dvec3& rgb)
{
    const glm::dvec3 xyz = kRgbToXyz * rgb;
    constexpr double kDelta = 6.0 / 29.0;
    glm::dvec3 f;
    for (int i = 0; i < 3; ++i)
    {
        const double t = xyz[i] / kWhite[i];
        f[i] = t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
    }
    const double L = 116.0 * f.y - 16.0;
    const double a = 500.0 * (f.x - f.y);
    const double b = 200.0 * (f.y - f.z);
    return glm::dvec3(L, 0.01 * L * a, 0.01 * L * b);
}

double HyAB(const glm::dvec3& p, const glm::dvec3& q)
{
    return std::abs(p.x - q.x) + glm::length(glm::dvec2(p.y - q.y, p.z - q.z));
}

constexpr double kFlipQc = 0.7;
constexpr double kFlipQf = 0.5;
constexpr double kFlipPc = 0.4;
constexpr double kFlipPt = 0.95;

// Largest expected colour error: HyAB^qc between Hunt-adjusted green and blue.
double FlipCmax()
{
    static const double cmax =
        std::pow(HyAB(RgbToHuntLab(glm::dvec3(0.0, 1.0, 0.0)), RgbToHuntLab(glm::dvec3(0.0, 0.0, 1.0))), kFlipQc);
    return cmax;
}

// Published piecewise compression of HyAB^qc into [0, 1]: [0, pc*cmax] maps
// linearly to [0, pt], [pc*cmax, cmax] maps linearly to [pt, 1].
double FlipRedistribute(double e)
{
    const double cmax = FlipCmax();
    const double knee = kFlipPc * cmax;
    if (e < knee)
        return kFlipPt / knee * e;
    return kFlipPt + (e - knee) / (cmax - knee) * (1.0 - kFlipPt);
}

// Contrast sensitivity filter of one opponent channel: a sum of up to two
// separable Gaussians, each a weight and one 1D tap vector (used for x and y).
struct CsfTerm
{
    double weight;
    std::vector<double> taps;
};

std::vector<CsfTerm> MakeCsfFilter(double ppd, double a1, double b1, double a2, double b2)
{
    // Radius from the widest Gaussian of all three channels (b = 0.04), as published.
    constexpr double kMaxB = 0.04;
    const int r = int(std::ceil(3.0 * std::sqrt(kMaxB / (2.0 * kPi * kPi)) * ppd));
    const double dx = 1.0 / ppd; // degrees per pixel

    std::vector<CsfTerm> terms;
    double total = 0.0;
    const double as[2] = {a1, a2}, bs[2] = {b1, b2};
    for (int t = 0; t < 2; ++t)
    {
        if (as[t] == 0.0)
            continue;
        CsfTerm term{as[t] * std::sqrt(kPi / bs[t]), std::vector<double>(size_t(2 * r + 1))};
        double s = 0.0;
        for (int i = -r; i <= r; ++i)
        {
            const double x = double(i) * dx;
            term.taps[size_t(i + r)] = std::exp(-kPi * kPi * x * x / bs[t]);
            s += term.taps[size_t(i + r)];
        }
        total += term.weight * s * s; // sum of the 2D kernel of this term
        terms.push_back(std::move(term));
    }
    for (CsfTerm& term : terms)
        term.weight /= total; // whole 2D kernel sums to 1
    return terms;
}

// Normalise a 1D feature kernel so its positive taps sum to 1 and its negative
// taps to -1 (the 2D kernel normalisation factorises onto the 1D kernel).
void NormalizeSigned(std::vector<double>& k)
{
    double pos = 0.0, neg = 0.0;
    for (double v : k)
        (v > 0.0 ? pos : neg) += v;
    for (double& v : k)
    {
        if (v > 0.0 && pos > 0.0)
            v /= pos;
        else if (v < 0.0 && neg < 0.0)
            v /= -neg;
    }
}

struct FeatureKernels
{
    std::vector<double> gauss; // normalised to sum 1 (across-direction factor)
    std::vector<double> edge;  // first derivative of a Gaussian
    std::vector<double> point; // second derivative of a Gaussian
};

FeatureKernels MakeFeatureKernels(double ppd)
{
    constexpr double kW = 0.082; // peak-to-trough width of the edge filter, degrees
    const double sd = 0.5 * kW * ppd;
    const int r = int(std::ceil(3.0 * sd));
    FeatureKernels k;
    k.gauss.resize(size_t(2 * r + 1));
    k.edge.resize(k.gauss.size());
    k.point.resize(k.gauss.size());
    double gsum = 0.0;
    for (int i = -r; i <= r; ++i)
    {
        const double x = double(i);
        const double g = std::exp(-x * x / (2.0 * sd * sd));
        k.gauss[size_t(i + r)] = g;
        k.edge[size_t(i + r)] = -x * g;
        k.point[size_t(i + r)] = (x * x / (sd * sd) - 1.0) * g;
        gsum += g;
    }
    for (double& v : k.gauss)
        v /= gsum;
    NormalizeSigned(k.edge);
    NormalizeSigned(k.point);
    return k;
}

using Plane = std::vector<float>;

// Display-referred RGB planes: 1 channel -> grey, 2 channels -> (R, G, 0).
void FlipRgbPlanes(const Image& image, bool toneMap, Plane rgb[3])
{
    const size_t n = image.pixelCount();
    for (int c = 0; c < 3; ++c)
        rgb[c].assign(n, 0.0f);
    for (size_t i = 0; i < n; ++i)
    {
        const float* p = image.pixels.data() + i * image.channels;
        if (image.channels == 1)
        {
            const float v = DisplayValue(p[0], toneMap);
            rgb[0][i] = rgb[1][i] = rgb[2][i] = v;
        }
        else
        {
            for (uint32_t c = 0; c < ColourChannels(image); ++c)
                rgb[c][i] = DisplayValue(p[c], toneMap);
        }
    }
}

struct FlipPrepared
{
    Plane lab[3]; // Hunt-adjusted L*a*b* of the CSF-filtered image
    Plane edge;   // edge detector magnitude on normalised luminance
    Plane point;  // point detector magnitude on normalised luminance
};

FlipPrepared FlipPrepare(const Plane rgb[3], int w, int h, const std::vector<CsfTerm> csf[3],
                         const FeatureKernels& fk)
{
    const size_t n = size_t(w) * size_t(h);
    Plane ycc[3], yNorm(n);
    for (int c = 0; c < 3; ++c)
        ycc[c].resize(n);
    for (size_t i = 0; i < n; ++i)
    {
        const glm::dvec3 o = RgbToYcxcz(glm::dvec3(rgb[0][i], rgb[1][i], rgb[2][i]));
        for (int c = 0; c < 3; ++c)
            ycc[c][i] = float(o[c]);
        yNorm[i] = float((o.x + 16.0) / 116.0);
    }

    // Colour pipeline: CSF filtering per opponent channel.
    Plane filtered[3], tmp, term;
    for (int c = 0; c < 3; ++c)
    {
        filtered[c].assign(n, 0.0f);
        for (const CsfTerm& t : csf[c])
        {
            CorrelateSeparable(ycc[c], term, tmp, w, h, t.taps, t.taps);
            for (size_t i = 0; i < n; ++i)
                filtered[c][i] += float(t.weight * double(term[i]));
        }
    }

    FlipPrepared out;
    for (int c = 0; c < 3; ++c)
        out.lab[c].resize(n);
    for (size_t i = 0; i < n; ++i)
    {
        const glm::dvec3 lin = YcxczToRgb(glm::dvec3(filtered[0][i], filtered[1][i], filtered[2][i]));
        const glm::dvec3 lab = RgbToHuntLab(glm::clamp(lin, 0.0, 1.0)); // clamped to the RGB cube
        for (int c = 0; c < 3; ++c)
            out.lab[c][i] = float(lab[c]);
    }

    // Feature pipeline on the unfiltered normalised luminance.
    Plane smoothY, smoothX, gx, gy;
    CorrelateCols(yNorm, smoothY, w, h, fk.gauss); // smoothed across y, for x derivatives
    CorrelateRows(yNorm, smoothX, w, h, fk.gauss); // smoothed across x, for y derivatives
    out.edge.resize(n);
    out.point.resize(n);
    CorrelateRows(smoothY, gx, w, h, fk.edge);
    CorrelateCols(smoothX, gy, w, h, fk.edge);
    for (size_t i = 0; i < n; ++i)
        out.edge[i] = float(std::hypot(double(gx[i]), double(gy[i])));
    CorrelateRows(smoothY, gx, w, h, fk.point);
    CorrelateCols(smoothX, gy, w, h, fk.point);
    for (size_t i = 0; i < n; ++i)
        out.point[i] = float(std::hypot(double(gx[i]), double(gy[i])));
    return out;
}

Image FlipMapImpl(const Image& test, const Image& ref, double ppd, bool toneMap)
{
    if (!SameShape(test, ref) || !std::isfinite(ppd) || ppd <= 0.0)
        return Image();
    const int w = int(test.width), h = int(test.height);

    const std::vector<CsfTerm> csf[3] = {
        MakeCsfFilter(ppd, 1.0, 0.0047, 0.0, 1e-5),  // achromatic
        MakeCsfFilter(ppd, 1.0, 0.0053, 0.0, 1e-5),  // red-green
        MakeCsfFilter(ppd, 34.1, 0.04, 13.5, 0.025), // blue-yellow
    };
    const FeatureKernels fk = MakeFeatureKernels(ppd);

    Plane rgbTest[3], rgbRef[3];
    FlipRgbPlanes(test, toneMap, rgbTest);
    FlipRgbPlanes(ref, toneMap, rgbRef);
    const FlipPrepared t = FlipPrepare(rgbTest, w, h, csf, fk);
    const FlipPrepared r = FlipPrepare(rgbRef, w, h, csf, fk);

    Image map(test.width, test.height, 1);
    for (size_t i = 0; i < map.pixels.size(); ++i)
    {
        const double hyab =
            HyAB(glm::dvec3(t.lab[0][i], t.lab[1][i], t.lab[2][i]), glm::dvec3(r.lab[0][i], r.lab[1][i], r.lab[2][i]));
        const double colour = FlipRedistribute(std::pow(hyab, kFlipQc));
        const double df = std::max(std::abs(double(t.edge[i]) - double(r.edge[i])),
                                   std::abs(double(t.point[i]) - double(r.point[i])));
        const double feature = std::pow(df / std::sqrt(2.0), kFlipQf);
        map.pixels[i] = float(std::pow(colour, 1.0 - feature));
    }
    return map;
}

double MeanOfMap(const Image& map)
{
    if (!map.isValid())
        return kMetricError;
    double sum = 0.0;
    for (float v : map.pixels)
        sum += double(v);
    return sum / double(map.pixels.size());
}

// ---------------------------------------------------------------------------

double FiniteClamp(float v)
{
    constexpr double kHalfMax = 65504.0;
    if (std::isnan(v))
        return 0.0;
    return std::min(std::max(double(v), -kHalfMax), kHalfMax);
}

} // namespace

double MeanValue(const Image& image)
{
    double sum = 0.0;
    for (float v : image.pixels)
        sum += double(v);
    return image.pixels.empty() ? 0.0 : sum / double(image.pixels.size());
}

bool SameShape(const Image& a, const Image& b)
{
    return a.isValid() && b.isValid() && a.width == b.width && a.height == b.height &&
           a.channels == b.channels;
}

double RelMSE(const Image& test, const Image& ref, double eps)
{
    if (!SameShape(test, ref) || !std::isfinite(eps) || eps <= 0.0)
        return kMetricError;
    const uint32_t cc = ColourChannels(test);
    double sum = 0.0;
    for (size_t i = 0; i < test.pixelCount(); ++i)
    {
        for (uint32_t c = 0; c < cc; ++c)
        {
            const double t = test.pixels[i * test.channels + c];
            const double r = ref.pixels[i * ref.channels + c];
            if (!std::isfinite(t) || !std::isfinite(r))
            {
                sum += kRelMseNonFinitePenalty;
                continue;
            }
            const double e = (t - r) * (t - r) / (r * r + eps);
            sum += std::isfinite(e) ? e : kRelMseNonFinitePenalty; // overflow of huge values
        }
    }
    return sum / double(test.pixelCount() * cc);
}

Image BlockMeans(const Image& image, uint32_t block)
{
    if (!image.isValid() || block == 0)
        return Image();
    Image out((image.width + block - 1) / block, (image.height + block - 1) / block, image.channels);
    for (uint32_t by = 0; by < out.height; ++by)
        for (uint32_t bx = 0; bx < out.width; ++bx)
        {
            const uint32_t x1 = std::min(bx * block + block, image.width);
            const uint32_t y1 = std::min(by * block + block, image.height);
            const double count = double(x1 - bx * block) * double(y1 - by * block);
            for (uint32_t c = 0; c < image.channels; ++c)
            {
                double sum = 0.0;
                for (uint32_t y = by * block; y < y1; ++y)
                    for (uint32_t x = bx * block; x < x1; ++x)
                        sum += image.at(x, y, c);
                out.at(bx, by, c) = float(sum / count);
            }
        }
    return out;
}

Image ToneMap(const Image& linear, float exposure)
{
    if (!linear.isValid())
        return Image();
    Image out = linear;
    for (float& v : out.pixels)
        v = ToneMapValue(v, exposure);
    return out;
}

double Psnr(const Image& test, const Image& ref) { return PsnrImpl(test, ref, true); }
double PsnrLdr(const Image& test, const Image& ref) { return PsnrImpl(test, ref, false); }

double Ssim(const Image& test, const Image& ref) { return SsimImpl(test, ref, true); }
double SsimLdr(const Image& test, const Image& ref) { return SsimImpl(test, ref, false); }

Image FlipMap(const Image& test, const Image& ref, double ppd)
{
    return FlipMapImpl(test, ref, ppd, true);
}

double Flip(const Image& test, const Image& ref, double ppd)
{
    return MeanOfMap(FlipMapImpl(test, ref, ppd, true));
}

Image FlipMapLdr(const Image& test, const Image& ref, double ppd)
{
    return FlipMapImpl(test, ref, ppd, false);
}

double FlipLdr(const Image& test, const Image& ref, double ppd)
{
    return MeanOfMap(FlipMapImpl(test, ref, ppd, false));
}

double TemporalInstability(const Image& testPrev, const Image& test, const Image& refPrev,
                           const Image& ref)
{
    if (!SameShape(testPrev, test) || !SameShape(test, refPrev) || !SameShape(refPrev, ref))
        return kMetricError;
    const uint32_t cc = ColourChannels(test);
    double sum = 0.0;
    for (size_t i = 0; i < test.pixelCount(); ++i)
    {
        for (uint32_t c = 0; c < cc; ++c)
        {
            const size_t k = i * test.channels + c;
            const double dt = std::abs(FiniteClamp(test.pixels[k]) - FiniteClamp(testPrev.pixels[k]));
            const double dr = std::abs(FiniteClamp(ref.pixels[k]) - FiniteClamp(refPrev.pixels[k]));
            sum += std::abs(dt - dr);
        }
    }
    return sum / double(test.pixelCount() * cc);
}

std::vector<double> TemporalInstabilityPerFrame(const std::vector<Image>& testFrames,
                                                const std::vector<Image>& refFrames)
{
    std::vector<double> out;
    if (testFrames.size() != refFrames.size() || testFrames.size() < 2)
        return out;
    for (size_t i = 1; i < testFrames.size(); ++i)
    {
        const double v =
            TemporalInstability(testFrames[i - 1], testFrames[i], refFrames[i - 1], refFrames[i]);
        if (v < 0.0)
            return std::vector<double>();
        out.push_back(v);
    }
    return out;
}

double TemporalInstabilitySequence(const std::vector<Image>& testFrames,
                                   const std::vector<Image>& refFrames)
{
    const std::vector<double> perFrame = TemporalInstabilityPerFrame(testFrames, refFrames);
    if (perFrame.empty())
        return kMetricError;
    double sum = 0.0;
    for (double v : perFrame)
        sum += v;
    return sum / double(perFrame.size());
}

int LagFrames(const std::vector<double>& errorPerFrame, size_t eventFrame, double steadyError)
{
    if (eventFrame >= errorPerFrame.size() || !std::isfinite(steadyError) || steadyError < 0.0)
        return -1;
    const double band = 2.0 * steadyError;
    size_t recovered = eventFrame; // first frame from which the error stays in band
    for (size_t i = eventFrame; i < errorPerFrame.size(); ++i)
    {
        if (!(errorPerFrame[i] <= band)) // NaN counts as out of band
            recovered = i + 1;
    }
    return int(recovered - eventFrame);
}

SuddenChangeLag LagAfterSuddenChanges(const std::vector<double>& errorPerFrame,
                                      const std::vector<double>& referenceChangePerFrame, size_t warmup)
{
    SuddenChangeLag result;
    const size_t n = errorPerFrame.size();
    if (referenceChangePerFrame.size() != n)
        return result;
    double calm = 1e-4;
    for (size_t f = 1; f < warmup && f < n; f++)
        calm = std::max(calm, referenceChangePerFrame[f]);
    auto isSudden = [&](size_t f) { return referenceChangePerFrame[f] > 4.0 * calm; };
    std::vector<size_t> events;
    for (size_t f = std::max<size_t>(warmup, 1); f < n; f++)
        if (isSudden(f) && !(f > std::max<size_t>(warmup, 1) && isSudden(f - 1)))
            events.push_back(f);
    if (events.empty())
        return result;

    double steady = 0.0;
    size_t steadyNum = 0;
    for (size_t f = warmup; f < events.front(); f++)
    {
        steady += errorPerFrame[f];
        steadyNum++;
    }
    steady = steadyNum ? steady / double(steadyNum) : errorPerFrame.back();
    for (size_t e = 0; e < events.size(); e++)
    {
        size_t end = e + 1 < events.size() ? events[e + 1] : n;
        std::vector<double> window(errorPerFrame.begin(), errorPerFrame.begin() + ptrdiff_t(end));
        int lag = LagFrames(window, events[e], steady);
        if (result.eventFrame < 0 || lag > result.frames)
        {
            result.frames = lag;
            result.eventFrame = int(events[e]);
        }
    }
    return result;
}

} // namespace nrdlab
