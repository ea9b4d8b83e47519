// Image.h - a tiny float image type for the scene lab (metrics, image I/O).
//
// Pixels are float32, interleaved, row-major, with linear (scene-referred)
// values unless a function documents otherwise. Channel semantics used by the
// lab: 1 = grey, 2 = (R, G), 3 = RGB, 4 = RGB + an extra channel (alpha or
// packed data) that metrics ignore.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace nrdlab
{

struct Image
{
    uint32_t width = 0, height = 0, channels = 0;
    std::vector<float> pixels; // width * height * channels values, interleaved

    Image() = default;

    Image(uint32_t w, uint32_t h, uint32_t c, float fill = 0.0f)
        : width(w), height(h), channels(c), pixels(size_t(w) * h * c, fill)
    {
    }

    // Index of channel c of pixel (x, y) in `pixels`. No bounds checks.
    size_t index(uint32_t x, uint32_t y, uint32_t c) const
    {
        return (size_t(y) * width + x) * channels + c;
    }

    float& at(uint32_t x, uint32_t y, uint32_t c) { return pixels[index(x, y, c)]; }
    float at(uint32_t x, uint32_t y, uint32_t c) const { return pixels[index(x, y, c)]; }

    size_t pixelCount() const { return size_t(width) * height; }

    // True when the image is non-empty, has 1..4 channels and a pixel buffer of
    // exactly width * height * channels floats.
    bool isValid() const
    {
        return width > 0 && height > 0 && channels >= 1 && channels <= 4 &&
               pixels.size() == size_t(width) * height * channels;
    }
};

} // namespace nrdlab
