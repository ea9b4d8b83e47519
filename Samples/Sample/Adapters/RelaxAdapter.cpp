// RELAX_DIFFUSE, RELAX_SPECULAR, RELAX_DIFFUSE_SPECULAR on the lab's radiance + normalized hit
// distance signals (the default HitDistanceParameters, which the method uses too).
#include "Adapters.h"

#include "NRDIntegration.h"

namespace nrdlab
{

const char* const kRelaxSettingsKey = "relax";

namespace
{

class RelaxAdapter : public MethodAdapter
{
public:
    explicit RelaxAdapter(nrd::Method method) : m_Method(method) {}

    std::vector<std::string> GetSignals() const override
    {
        if (m_Method == nrd::Method::RELAX_DIFFUSE)
            return {"diffuse"};
        if (m_Method == nrd::Method::RELAX_SPECULAR)
            return {"specular"};
        return {"diffuse", "specular"};
    }
    SignalMask GetLabSignals(const std::string&) const override
    {
        return (HasDiffuse() ? SIGNAL_DIFFUSE : 0u) | (HasSpecular() ? SIGNAL_SPECULAR : 0u);
    }
    void GetSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth) const override
    {
        GetLabSignalImages(f, signal, noisy, truth);
    }

    const char* GetSettingsKey() const override { return kRelaxSettingsKey; }
    bool ParseSettings(const nlohmann::json& j, std::string&) override
    {
        nrd::RelaxSettings& s = m_Settings;
        ReadSetting(j, "diffuseMaxAccumulatedFrameNum", s.diffuseMaxAccumulatedFrameNum);
        ReadSetting(j, "specularMaxAccumulatedFrameNum", s.specularMaxAccumulatedFrameNum);
        ReadSetting(j, "diffuseMaxFastAccumulatedFrameNum", s.diffuseMaxFastAccumulatedFrameNum);
        ReadSetting(j, "specularMaxFastAccumulatedFrameNum", s.specularMaxFastAccumulatedFrameNum);
        ReadSetting(j, "historyFixFrameNum", s.historyFixFrameNum);
        ReadSetting(j, "historyFixStride", s.historyFixStride);
        ReadSetting(j, "diffuseHistoryClampingColorBoxSigmaScale", s.diffuseHistoryClampingColorBoxSigmaScale);
        ReadSetting(j, "specularHistoryClampingColorBoxSigmaScale", s.specularHistoryClampingColorBoxSigmaScale);
        ReadSetting(j, "antilagSigmaScale", s.antilagSigmaScale);
        ReadSetting(j, "spatialVarianceEstimationHistoryThreshold", s.spatialVarianceEstimationHistoryThreshold);
        ReadSetting(j, "atrousIterationNum", s.atrousIterationNum);
        ReadSetting(j, "diffusePhiLuminance", s.diffusePhiLuminance);
        ReadSetting(j, "specularPhiLuminance", s.specularPhiLuminance);
        ReadSetting(j, "diffuseLobeAngleFraction", s.diffuseLobeAngleFraction);
        ReadSetting(j, "specularLobeAngleFraction", s.specularLobeAngleFraction);
        ReadSetting(j, "specularLobeAngleSlack", s.specularLobeAngleSlack);
        ReadSetting(j, "roughnessFraction", s.roughnessFraction);
        ReadSetting(j, "depthThreshold", s.depthThreshold);
        ReadSetting(j, "enableAntiFirefly", s.enableAntiFirefly);
        ReadSetting(j, "enableRoughnessEdgeStopping", s.enableRoughnessEdgeStopping);
        ReadSetting(j, "useConfidenceInputs", s.useConfidenceInputs);
        uint32_t checkerboard = uint32_t(s.checkerboardMode);
        ReadSetting(j, "checkerboardMode", checkerboard);
        s.checkerboardMode = nrd::CheckerboardMode(checkerboard);
        return true;
    }
    bool EnableConfidenceInputs() override
    {
        m_Settings.useConfidenceInputs = true;
        return true;
    }
    nrd::Result ApplySettings(nrd::Integration& integration, nrd::Identifier id) override
    {
        return integration.SetMethodSettings(id, m_Settings);
    }

    void GetInputs(const FrameData& f, const std::string&, const Image&, std::vector<AdapterTexture>& inputs) const override
    {
        // The lab packs the hit distances normalized with the default HitDistanceParameters.
        if (HasDiffuse())
            inputs.push_back({nrd::ResourceType::IN_DIFF_RADIANCE_HITDIST, nrd::rhi::Format::RGBA16_SFLOAT,
                              ExpandChannels(f.diffuse, 4)});
        if (HasSpecular())
            inputs.push_back({nrd::ResourceType::IN_SPEC_RADIANCE_HITDIST, nrd::rhi::Format::RGBA16_SFLOAT,
                              ExpandChannels(f.specular, 4)});
    }

    nrd::ResourceType GetOutput(const std::string& signal) const override
    {
        return signal == "specular" ? nrd::ResourceType::OUT_SPEC_RADIANCE_HITDIST : nrd::ResourceType::OUT_DIFF_RADIANCE_HITDIST;
    }
    Image DecodeOutput(const std::string&, const Image& output) const override { return KeepChannels(output, 3); }

private:
    bool HasDiffuse() const { return m_Method != nrd::Method::RELAX_SPECULAR; }
    bool HasSpecular() const { return m_Method != nrd::Method::RELAX_DIFFUSE; }

    nrd::Method m_Method;
    nrd::RelaxSettings m_Settings;
};

} // namespace

std::unique_ptr<MethodAdapter> CreateRelaxAdapter(const std::string& method)
{
    for (nrd::Method m : {nrd::Method::RELAX_DIFFUSE, nrd::Method::RELAX_SPECULAR, nrd::Method::RELAX_DIFFUSE_SPECULAR})
        if (method == nrd::GetMethodString(m))
            return std::unique_ptr<MethodAdapter>(new RelaxAdapter(m));
    return nullptr;
}

} // namespace nrdlab
