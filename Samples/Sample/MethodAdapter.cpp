#include "MethodAdapter.h"

#include "Adapters/Adapters.h"

namespace nrdlab
{

namespace
{

// One line per method family: its factory (nullptr for methods of other families) and settings key.
struct AdapterFamily
{
    std::unique_ptr<MethodAdapter> (*create)(const std::string& method);
    const char* settingsKey;
};

const AdapterFamily kFamilies[] = {
    {CreatePassThroughAdapter, nullptr},
    {CreateSigmaAdapter, kSigmaSettingsKey},
    {CreateReferenceAdapter, kReferenceSettingsKey},
    {CreateTiledShadowAdapter, kTiledShadowSettingsKey},
    {CreateReblurAdapter, kReblurSettingsKey},
    {CreateConfidenceAdapter, kConfidenceSettingsKey},
    {CreateReflectionAdapter, kReflectionSettingsKey},
    {CreateRelaxAdapter, kRelaxSettingsKey},
};

} // namespace

std::unique_ptr<MethodAdapter> CreateMethodAdapter(const std::string& method)
{
    for (const AdapterFamily& family : kFamilies)
        if (std::unique_ptr<MethodAdapter> adapter = family.create(method))
            return adapter;
    return nullptr;
}

std::vector<std::string> GetAdapterSettingsKeys()
{
    std::vector<std::string> keys;
    for (const AdapterFamily& family : kFamilies)
        if (family.settingsKey)
            keys.push_back(family.settingsKey);
    return keys;
}

std::vector<float> MethodAdapter::GetOutputInitialization(const std::string& signal, const Image& noisy) const
{
    return ExpandChannels(noisy, nrd::rhi::GetFormatInfo(GetOutputFormat(signal)).channelNum, 1.0f);
}

Image KeepChannels(const Image& src, uint32_t channels)
{
    Image out(src.width, src.height, channels);
    for (uint32_t i = 0; i < src.width * src.height; i++)
        for (uint32_t c = 0; c < channels; c++)
            out.pixels[i * channels + c] = c < src.channels ? src.pixels[i * src.channels + c] : 0.0f;
    return out;
}

Image KeepChannel(const Image& src, uint32_t channel)
{
    Image out(src.width, src.height, 1);
    for (uint32_t i = 0; i < src.width * src.height; i++)
        out.pixels[i] = channel < src.channels ? src.pixels[i * src.channels + channel] : 0.0f;
    return out;
}

std::vector<float> ExpandChannels(const Image& src, uint32_t channels, float fill)
{
    std::vector<float> out(size_t(src.width) * src.height * channels, fill);
    for (uint32_t i = 0; i < src.width * src.height; i++)
        for (uint32_t c = 0; c < channels && c < src.channels; c++)
            out[size_t(i) * channels + c] = src.pixels[size_t(i) * src.channels + c];
    return out;
}

} // namespace nrdlab
