// REFERENCE: plain accumulation of the lab's diffuse or specular radiance (or its shadow).
#include "Adapters.h"

#include "NRDIntegration.h"

namespace nrdlab
{

const char* const kReferenceSettingsKey = "reference";

namespace
{

class ReferenceAdapter : public MethodAdapter
{
public:
    std::vector<std::string> GetSignals() const override { return GetLabSignalNames(); }
    SignalMask GetLabSignals(const std::string& signal) const override { return GetLabSignalMask(signal); }
    void GetSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth) const override
    {
        GetLabSignalImages(f, signal, noisy, truth);
    }

    const char* GetSettingsKey() const override { return kReferenceSettingsKey; }
    bool ParseSettings(const nlohmann::json& s, std::string&) override
    {
        ReadSetting(s, "maxAccumulatedFrameNum", m_Settings.maxAccumulatedFrameNum);
        return true;
    }
    nrd::Result ApplySettings(nrd::Integration& integration, nrd::Identifier id) override
    {
        return integration.SetMethodSettings(id, m_Settings);
    }

    // Every channel is accumulated: the compared ones, zeros beyond.
    void GetInputs(const FrameData&, const std::string&, const Image& noisy, std::vector<AdapterTexture>& inputs) const override
    {
        inputs.push_back({nrd::ResourceType::IN_RADIANCE, nrd::rhi::Format::RGBA32_SFLOAT, ExpandChannels(noisy, 4)});
    }

    nrd::ResourceType GetOutput(const std::string&) const override { return nrd::ResourceType::OUT_RADIANCE; }
    nrd::rhi::Format GetOutputFormat(const std::string&) const override { return nrd::rhi::Format::RGBA32_SFLOAT; }
    Image DecodeOutput(const std::string& signal, const Image& output) const override
    {
        Image out = KeepChannels(output, signal == "diffuse" || signal == "specular" ? 3 : 1);
        if (signal == "shadow")
            UnpackShadow(out);
        return out;
    }

private:
    nrd::ReferenceSettings m_Settings;
};

} // namespace

std::unique_ptr<MethodAdapter> CreateReferenceAdapter(const std::string& method)
{
    if (method != "REFERENCE")
        return nullptr;
    return std::unique_ptr<MethodAdapter>(new ReferenceAdapter());
}

} // namespace nrdlab
