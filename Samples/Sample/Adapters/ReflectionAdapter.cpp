// REFLECTION on the lab's specular signal (radiance + normalized hit distance with the default
// HitDistanceParameters, which the method uses too). The input is traced by the lab for the rays of
// the method's ray list only (IsRayListTraced); the compared noisy image stays the full-rate input.
#include "Adapters.h"

#include "NRDIntegration.h"

namespace nrdlab
{

const char* const kReflectionSettingsKey = "reflection";

namespace
{

class ReflectionAdapter : public MethodAdapter
{
public:
    std::vector<std::string> GetSignals() const override { return {"specular"}; }
    SignalMask GetLabSignals(const std::string&) const override { return SIGNAL_SPECULAR; }
    void GetSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth) const override
    {
        GetLabSignalImages(f, signal, noisy, truth);
    }

    const char* GetSettingsKey() const override { return kReflectionSettingsKey; }
    bool ParseSettings(const nlohmann::json& s, std::string&) override
    {
        nrd::ReflectionSettings& r = m_Settings;
        ReadSetting(s, "roughnessThreshold", r.roughnessThreshold);
        ReadSetting(s, "mirrorRoughness", r.mirrorRoughness);
        ReadSetting(s, "raysPerQuad", r.raysPerQuad);
        ReadSetting(s, "enableTemporalVarianceGuidedTracing", r.enableTemporalVarianceGuidedTracing);
        ReadSetting(s, "temporalVarianceThreshold", r.temporalVarianceThreshold);
        ReadSetting(s, "maxHistoryFrameNum", r.maxHistoryFrameNum);
        ReadSetting(s, "hitReprojectionRoughness", r.hitReprojectionRoughness);
        ReadSetting(s, "historyClipSigma", r.historyClipSigma);
        ReadSetting(s, "historyClipLeeway", r.historyClipLeeway);
        ReadSetting(s, "normalSigma", r.normalSigma);
        ReadSetting(s, "depthSigma", r.depthSigma);
        ReadSetting(s, "enableSpatial", r.enableSpatial);
        ReadSetting(s, "enableBlur", r.enableBlur);
        return true;
    }
    nrd::Result ApplySettings(nrd::Integration& integration, nrd::Identifier id) override
    {
        return integration.SetMethodSettings(id, m_Settings);
    }

    void GetInputs(const FrameData& f, const std::string&, const Image&, std::vector<AdapterTexture>& inputs) const override
    {
        inputs.push_back({nrd::ResourceType::IN_SPEC_RADIANCE_HITDIST, nrd::rhi::Format::RGBA16_SFLOAT, ExpandChannels(f.specular, 4)});
    }
    bool IsRayListTraced() const override { return true; }

    nrd::ResourceType GetOutput(const std::string&) const override { return nrd::ResourceType::OUT_SPEC_RADIANCE_HITDIST; }
    Image DecodeOutput(const std::string&, const Image& output) const override { return KeepChannels(output, 3); }

private:
    nrd::ReflectionSettings m_Settings;
};

} // namespace

std::unique_ptr<MethodAdapter> CreateReflectionAdapter(const std::string& method)
{
    return method == "REFLECTION" ? std::unique_ptr<MethodAdapter>(new ReflectionAdapter()) : nullptr;
}

} // namespace nrdlab
