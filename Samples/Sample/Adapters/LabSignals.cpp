#include "Adapters.h"

#include <algorithm>
#include <cmath>

namespace nrdlab
{

std::vector<std::string> GetLabSignalNames()
{
    return {"shadow", "diffuse", "specular", "diffuse_occlusion", "specular_occlusion"};
}

SignalMask GetLabSignalMask(const std::string& signal)
{
    if (signal == "shadow")
        return SIGNAL_SHADOW;
    if (signal == "diffuse" || signal == "diffuse_occlusion")
        return SIGNAL_DIFFUSE;
    if (signal == "specular" || signal == "specular_occlusion")
        return SIGNAL_SPECULAR;
    return 0;
}

void GetLabSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth)
{
    if (signal == "shadow")
    {
        noisy = KeepChannels(f.shadowVisibility, 1);
        truth = KeepChannels(f.shadowTruth, 1);
    }
    else if (signal == "diffuse_occlusion" || signal == "specular_occlusion")
    {
        // The normalized hit distance (.w): AO / SO.
        const bool diffuse = signal == "diffuse_occlusion";
        noisy = KeepChannel(diffuse ? f.diffuse : f.specular, 3);
        truth = KeepChannel(diffuse ? f.diffuseTruth : f.specularTruth, 3);
    }
    else
    {
        const bool diffuse = signal == "diffuse";
        noisy = KeepChannels(diffuse ? f.diffuse : f.specular, 3);
        truth = KeepChannels(diffuse ? f.diffuseTruth : f.specularTruth, 3);
    }
}

void UnpackShadow(Image& image)
{
    for (float& v : image.pixels)
        v = std::isfinite(v) ? std::min(std::max(v, 0.0f), 1.0f) : 1.0f;
}

namespace
{

// "NONE": whatever the lab renders, passed through; never denoised, so no textures.
class PassThroughAdapter : public MethodAdapter
{
public:
    std::vector<std::string> GetSignals() const override { return GetLabSignalNames(); }
    SignalMask GetLabSignals(const std::string& signal) const override { return GetLabSignalMask(signal); }
    void GetSignalImages(const FrameData& frame, const std::string& signal, Image& noisy, Image& truth) const override
    {
        GetLabSignalImages(frame, signal, noisy, truth);
    }
    void GetInputs(const FrameData&, const std::string&, const Image&, std::vector<AdapterTexture>&) const override {}
    nrd::ResourceType GetOutput(const std::string&) const override { return nrd::ResourceType::MAX_NUM; }
    Image DecodeOutput(const std::string&, const Image& output) const override { return output; }
};

} // namespace

std::unique_ptr<MethodAdapter> CreatePassThroughAdapter(const std::string& method)
{
    if (method != "NONE")
        return nullptr;
    return std::unique_ptr<MethodAdapter>(new PassThroughAdapter());
}

} // namespace nrdlab
