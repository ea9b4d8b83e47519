// ImageIO.h - PNG / EXR reading and writing for the scene lab.
//
// Every function returns true on success. On failure it returns false, leaves
// outputs untouched and, if `error` is non-null, stores a human-readable
// reason there. Bad paths, unreadable files and invalid images never crash.
#pragma once

#include "Image.h"

#include <string>
#include <vector>

namespace nrdlab
{

// sRGB transfer function (IEC 61966-2-1) on one value; input clamped to [0, 1].
float LinearToSrgb(float linear);
float SrgbToLinear(float encoded);

struct PngOptions
{
    bool toneMap = true;   // apply ToneMap(image, exposure) (Reinhard) first
    float exposure = 1.0f; // exposure used by the tone map
    bool srgb = true;      // sRGB-encode before quantising (else store linearly)
};

// Writes an 8-bit PNG for viewing: values are tone-mapped (if options.toneMap,
// else clamped to [0, 1] with NaN -> 1), sRGB-encoded (if options.srgb) and
// rounded to 8 bits. 1 channel -> grey PNG; 2 channels -> RGB with B = 0;
// 3 and 4 channels -> RGB (the 4th channel is not written).
bool WritePng(const std::string& path, const Image& image, std::string* error = nullptr,
              const PngOptions& options = PngOptions());

// Reads any 8-bit image stb_image can decode (PNG, JPEG, BMP, TGA, ...).
// Result: 1 channel (grey), 3 (RGB) or 4 (RGBA; grey+alpha files are expanded
// to RGBA) with values v / 255 in [0, 1]. These are the stored, display-encoded
// values unless decodeSrgb is true, in which case the colour channels (not
// alpha) are converted to linear with SrgbToLinear.
bool ReadPng(const std::string& path, Image& out, std::string* error = nullptr,
             bool decodeSrgb = false);

// Writes a scanline OpenEXR file with every channel of the image, as 32-bit
// float (lossless) or 16-bit half (asHalf; values beyond +-65504 become Inf).
// Channel names: 1 -> "Y", 2 -> "R","G", 3 -> "R","G","B", 4 -> "R","G","B","A".
bool WriteExr(const std::string& path, const Image& image, std::string* error = nullptr,
              bool asHalf = false);

// Reads a single-part scanline OpenEXR file (half, float or uint channels) as
// float: R,G,B[,A] -> 3 or 4 channels, R,G -> 2, Y -> 1, a lone channel of any
// other name -> 1. Tiled, multi-part and deep files are reported as errors.
bool ReadExr(const std::string& path, Image& out, std::string* error = nullptr);

// Builds a horizontal strip: the images left to right, top-aligned, separated
// by `gap` pixels. Output has 3 channels (1-channel inputs become grey, the
// 4th channel is dropped); the gaps and the area below shorter images are
// filled with the linear value `fill`. Returns an empty Image if `images` is
// empty or any of them is invalid.
Image MakeSideBySide(const std::vector<Image>& images, uint32_t gap = 4, float fill = 1.0f);

// Writes MakeSideBySide(images, gap) to `path`: as EXR (float) if the path ends
// in ".exr" (any case), otherwise as PNG with `options`.
bool WriteSideBySide(const std::string& path, const std::vector<Image>& images,
                     std::string* error = nullptr, uint32_t gap = 4,
                     const PngOptions& options = PngOptions());

} // namespace nrdlab
