// ImageIO.cpp - see ImageIO.h. PNG through stb (libstb), EXR through tinyexr
// (libtinyexr); both are optional at build time (NRDLAB_HAS_STB /
// NRDLAB_HAS_TINYEXR) and the functions report an error when one is missing.
#include "ImageIO.h"

#include "Metrics.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstring>

#if NRDLAB_HAS_STB
#include <stb_image.h>
#include <stb_image_write.h>
#endif

#if NRDLAB_HAS_TINYEXR
#include <tinyexr.h>
#endif

namespace nrdlab
{
namespace
{

void SetError(std::string* error, const std::string& message)
{
    if (error)
        *error = message;
}

bool CheckWritable(const Image& image, std::string* error)
{
    if (!image.isValid())
    {
        SetError(error, "invalid image (needs width, height > 0, 1..4 channels and "
                        "width*height*channels pixels)");
        return false;
    }
    if (image.width > uint32_t(INT_MAX) / 4u || image.height > uint32_t(INT_MAX) / 4u ||
        size_t(image.width) * image.height > size_t(INT_MAX) / 4u)
    {
        SetError(error, "image too large");
        return false;
    }
    return true;
}

#if NRDLAB_HAS_TINYEXR
std::string ExrError(const char* what, int code, const char* err)
{
    std::string message = std::string(what) + " (tinyexr code " + std::to_string(code) + ")";
    if (err)
    {
        message += ": ";
        message += err;
        FreeEXRErrorMessage(err);
    }
    return message;
}
#endif

} // namespace

float LinearToSrgb(float linear)
{
    const float v = std::isnan(linear) ? 1.0f : std::min(std::max(linear, 0.0f), 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float SrgbToLinear(float encoded)
{
    const float v = std::isnan(encoded) ? 1.0f : std::min(std::max(encoded, 0.0f), 1.0f);
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

bool WritePng(const std::string& path, const Image& image, std::string* error,
              const PngOptions& options)
{
    if (!CheckWritable(image, error))
        return false;
#if NRDLAB_HAS_STB
    const int comp = image.channels == 1 ? 1 : 3;
    const Image display = options.toneMap ? ToneMap(image, options.exposure) : image;
    std::vector<unsigned char> bytes(image.pixelCount() * size_t(comp), 0);
    for (size_t i = 0; i < image.pixelCount(); ++i)
    {
        for (int c = 0; c < comp && uint32_t(c) < image.channels; ++c)
        {
            float v = display.pixels[i * image.channels + size_t(c)];
            v = std::isnan(v) ? 1.0f : std::min(std::max(v, 0.0f), 1.0f);
            if (options.srgb)
                v = LinearToSrgb(v);
            bytes[i * size_t(comp) + size_t(c)] = static_cast<unsigned char>(std::lround(v * 255.0f));
        }
    }
    const int ok = stbi_write_png(path.c_str(), int(image.width), int(image.height), comp,
                                  bytes.data(), int(image.width) * comp);
    if (!ok)
    {
        SetError(error, "cannot write PNG '" + path + "'");
        return false;
    }
    return true;
#else
    (void)path;
    (void)options;
    SetError(error, "nrd_lab_common was built without stb: PNG writing unavailable");
    return false;
#endif
}

bool ReadPng(const std::string& path, Image& out, std::string* error, bool decodeSrgb)
{
#if NRDLAB_HAS_STB
    int w = 0, h = 0, fileComp = 0;
    if (!stbi_info(path.c_str(), &w, &h, &fileComp))
    {
        const char* reason = stbi_failure_reason();
        SetError(error, "cannot read image '" + path + "'" + (reason ? std::string(": ") + reason : ""));
        return false;
    }
    const int want = fileComp == 2 ? 4 : fileComp; // grey+alpha -> RGBA
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &fileComp, want);
    if (!data || w <= 0 || h <= 0)
    {
        const char* reason = stbi_failure_reason();
        SetError(error, "cannot decode image '" + path + "'" + (reason ? std::string(": ") + reason : ""));
        if (data)
            stbi_image_free(data);
        return false;
    }
    Image img{uint32_t(w), uint32_t(h), uint32_t(want)};
    for (size_t i = 0; i < img.pixelCount(); ++i)
    {
        for (int c = 0; c < want; ++c)
        {
            float v = float(data[i * size_t(want) + size_t(c)]) / 255.0f;
            if (decodeSrgb && c < 3)
                v = SrgbToLinear(v);
            img.pixels[i * size_t(want) + size_t(c)] = v;
        }
    }
    stbi_image_free(data);
    out = std::move(img);
    return true;
#else
    (void)path;
    (void)out;
    (void)decodeSrgb;
    SetError(error, "nrd_lab_common was built without stb: PNG reading unavailable");
    return false;
#endif
}

bool WriteExr(const std::string& path, const Image& image, std::string* error, bool asHalf)
{
    if (!CheckWritable(image, error))
        return false;
#if NRDLAB_HAS_TINYEXR
    // EXR readers expect channels sorted by name; src is the image channel.
    struct Channel
    {
        const char* name;
        uint32_t src;
    };
    static const Channel kLayouts[4][4] = {
        {{"Y", 0}},
        {{"G", 1}, {"R", 0}},
        {{"B", 2}, {"G", 1}, {"R", 0}},
        {{"A", 3}, {"B", 2}, {"G", 1}, {"R", 0}},
    };
    const uint32_t nc = image.channels;
    const Channel* layout = kLayouts[nc - 1];
    const size_t n = image.pixelCount();

    std::vector<std::vector<float>> planes(nc, std::vector<float>(n));
    std::vector<unsigned char*> planePtrs(nc);
    std::vector<EXRChannelInfo> infos(nc);
    std::vector<int> pixelTypes(nc, TINYEXR_PIXELTYPE_FLOAT);
    std::vector<int> storedTypes(nc, asHalf ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT);
    for (uint32_t k = 0; k < nc; ++k)
    {
        for (size_t i = 0; i < n; ++i)
            planes[k][i] = image.pixels[i * nc + layout[k].src];
        planePtrs[k] = reinterpret_cast<unsigned char*>(planes[k].data());
        std::memset(&infos[k], 0, sizeof(EXRChannelInfo));
        std::strncpy(infos[k].name, layout[k].name, sizeof(infos[k].name) - 1);
        infos[k].pixel_type = storedTypes[k];
        infos[k].x_sampling = 1;
        infos[k].y_sampling = 1;
    }

    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = int(nc);
    header.channels = infos.data();
    header.pixel_types = pixelTypes.data();
    header.requested_pixel_types = storedTypes.data();
    header.compression_type = (image.width < 16 && image.height < 16) ? TINYEXR_COMPRESSIONTYPE_NONE
                                                                      : TINYEXR_COMPRESSIONTYPE_ZIP;

    EXRImage exr;
    InitEXRImage(&exr);
    exr.num_channels = int(nc);
    exr.images = planePtrs.data();
    exr.width = int(image.width);
    exr.height = int(image.height);

    const char* err = nullptr;
    const int ret = SaveEXRImageToFile(&exr, &header, path.c_str(), &err);
    // header/exr point at our vectors: nothing to free besides the message.
    if (ret != TINYEXR_SUCCESS)
    {
        SetError(error, ExrError(("cannot write EXR '" + path + "'").c_str(), ret, err));
        return false;
    }
    return true;
#else
    (void)path;
    (void)asHalf;
    SetError(error, "nrd_lab_common was built without tinyexr: EXR writing unavailable");
    return false;
#endif
}

bool ReadExr(const std::string& path, Image& out, std::string* error)
{
#if NRDLAB_HAS_TINYEXR
    EXRVersion version;
    int ret = ParseEXRVersionFromFile(&version, path.c_str());
    if (ret != TINYEXR_SUCCESS)
    {
        SetError(error, ExrError(("cannot read EXR '" + path + "'").c_str(), ret, nullptr));
        return false;
    }
    if (version.multipart || version.non_image || version.tiled)
    {
        SetError(error, "EXR '" + path + "' is multi-part, deep or tiled: not supported");
        return false;
    }

    EXRHeader header;
    InitEXRHeader(&header);
    const char* err = nullptr;
    ret = ParseEXRHeaderFromFile(&header, &version, path.c_str(), &err);
    if (ret != TINYEXR_SUCCESS)
    {
        SetError(error, ExrError(("cannot parse EXR header of '" + path + "'").c_str(), ret, err));
        FreeEXRHeader(&header);
        return false;
    }
    if (header.tiled)
    {
        SetError(error, "EXR '" + path + "' is tiled: not supported");
        FreeEXRHeader(&header);
        return false;
    }
    for (int i = 0; i < header.num_channels; ++i)
        if (header.pixel_types[i] == TINYEXR_PIXELTYPE_HALF)
            header.requested_pixel_types[i] = TINYEXR_PIXELTYPE_FLOAT;

    EXRImage exr;
    InitEXRImage(&exr);
    ret = LoadEXRImageFromFile(&exr, &header, path.c_str(), &err);
    if (ret != TINYEXR_SUCCESS)
    {
        SetError(error, ExrError(("cannot load EXR '" + path + "'").c_str(), ret, err));
        FreeEXRHeader(&header);
        return false;
    }

    int idx[5] = {-1, -1, -1, -1, -1}; // R, G, B, A, Y
    const char* names[5] = {"R", "G", "B", "A", "Y"};
    for (int i = 0; i < header.num_channels; ++i)
        for (int k = 0; k < 5; ++k)
            if (std::strcmp(header.channels[i].name, names[k]) == 0)
                idx[k] = i;

    std::vector<int> sources;
    if (idx[0] >= 0 && idx[1] >= 0 && idx[2] >= 0)
    {
        sources = {idx[0], idx[1], idx[2]};
        if (idx[3] >= 0)
            sources.push_back(idx[3]);
    }
    else if (idx[0] >= 0 && idx[1] >= 0)
        sources = {idx[0], idx[1]};
    else if (idx[4] >= 0)
        sources = {idx[4]};
    else if (header.num_channels == 1)
        sources = {0};

    bool ok = !sources.empty() && exr.images != nullptr && exr.width > 0 && exr.height > 0;
    if (!ok)
        SetError(error, "EXR '" + path + "' has no recognised channel layout (R,G,B[,A] / R,G / Y)");
    else
    {
        const uint32_t nc = uint32_t(sources.size());
        Image img{uint32_t(exr.width), uint32_t(exr.height), nc};
        for (uint32_t k = 0; k < nc; ++k)
        {
            const int s = sources[k];
            const bool isUint = header.requested_pixel_types[s] == TINYEXR_PIXELTYPE_UINT;
            const float* fsrc = reinterpret_cast<const float*>(exr.images[s]);
            const unsigned int* usrc = reinterpret_cast<const unsigned int*>(exr.images[s]);
            for (size_t i = 0; i < img.pixelCount(); ++i)
                img.pixels[i * nc + k] = isUint ? float(usrc[i]) : fsrc[i];
        }
        out = std::move(img);
    }
    FreeEXRImage(&exr);
    FreeEXRHeader(&header);
    return ok;
#else
    (void)path;
    (void)out;
    SetError(error, "nrd_lab_common was built without tinyexr: EXR reading unavailable");
    return false;
#endif
}

Image MakeSideBySide(const std::vector<Image>& images, uint32_t gap, float fill)
{
    if (images.empty())
        return Image();
    uint64_t width = 0;
    uint32_t height = 0;
    for (const Image& img : images)
    {
        if (!img.isValid())
            return Image();
        width += img.width;
        height = std::max(height, img.height);
    }
    width += uint64_t(gap) * (images.size() - 1);
    if (width > uint64_t(INT_MAX) / 4u)
        return Image();

    Image strip{uint32_t(width), height, 3, fill};
    uint32_t x0 = 0;
    for (const Image& img : images)
    {
        for (uint32_t y = 0; y < img.height; ++y)
        {
            for (uint32_t x = 0; x < img.width; ++x)
            {
                for (uint32_t c = 0; c < 3; ++c)
                {
                    float v = 0.0f; // B of a 2-channel (R, G) image
                    if (img.channels == 1)
                        v = img.at(x, y, 0);
                    else if (c < img.channels)
                        v = img.at(x, y, c);
                    strip.at(x0 + x, y, c) = v;
                }
            }
        }
        x0 += img.width + gap;
    }
    return strip;
}

bool WriteSideBySide(const std::string& path, const std::vector<Image>& images, std::string* error,
                     uint32_t gap, const PngOptions& options)
{
    const Image strip = MakeSideBySide(images, gap);
    if (!strip.isValid())
    {
        SetError(error, images.empty() ? "no images to put side by side"
                                       : "an input image is invalid or the strip is too wide");
        return false;
    }
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : std::string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char ch) { return char(std::tolower(ch)); });
    if (ext == ".exr")
        return WriteExr(path, strip, error, false);
    return WritePng(path, strip, error, options);
}

} // namespace nrdlab
