// REBLUR_* on the lab's diffuse and specular signals (packed as radiance + normalized hit distance
// with the default HitDistanceParameters, which the method uses too). The radiance methods compare
// rgb ("diffuse", "specular"), the occlusion variants the normalized hit distance
// ("diffuse_occlusion", "specular_occlusion").
#include "Adapters.h"

#include "NRDIntegration.h"


namespace nrdlab
{

const char* const kReblurSettingsKey = "reblur";

namespace
{

class ReblurAdapter : public MethodAdapter
{
public:
    ReblurAdapter(bool diffuse, bool specular, bool occlusion) : m_Diffuse(diffuse), m_Specular(specular), m_Occlusion(occlusion) {}

    std::vector<std::string> GetSignals() const override
    {
        std::vector<std::string> signals;
        if (m_Diffuse)
            signals.push_back(m_Occlusion ? "diffuse_occlusion" : "diffuse");
        if (m_Specular)
            signals.push_back(m_Occlusion ? "specular_occlusion" : "specular");
        return signals;
    }
    // Both signals are rendered for a diffuse + specular method (both inputs are read).
    SignalMask GetLabSignals(const std::string&) const override
    {
        return SignalMask((m_Diffuse ? SignalMask(SIGNAL_DIFFUSE) : 0u) | (m_Specular ? SignalMask(SIGNAL_SPECULAR) : 0u));
    }
    void GetSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth) const override
    {
        GetLabSignalImages(f, signal, noisy, truth);
    }

    const char* GetSettingsKey() const override { return kReblurSettingsKey; }
    bool ParseSettings(const nlohmann::json& s, std::string&) override
    {
        nrd::ReblurSettings& r = m_Settings;
        ReadSetting(s, "maxAccumulatedFrameNum", r.maxAccumulatedFrameNum);
        ReadSetting(s, "maxFastAccumulatedFrameNum", r.maxFastAccumulatedFrameNum);
        ReadSetting(s, "historyFixFrameNum", r.historyFixFrameNum);
        ReadSetting(s, "historyFixStride", r.historyFixStride);
        ReadSetting(s, "blurRadius", r.blurRadius);
        ReadSetting(s, "minBlurRadius", r.minBlurRadius);
        ReadSetting(s, "diffusePrePassBlurRadius", r.diffusePrePassBlurRadius);
        ReadSetting(s, "specularPrePassBlurRadius", r.specularPrePassBlurRadius);
        ReadSetting(s, "occlusionPrePassBlurRadius", r.occlusionPrePassBlurRadius);
        ReadSetting(s, "postBlurRadiusScale", r.postBlurRadiusScale);
        ReadSetting(s, "planeDistanceSensitivity", r.planeDistanceSensitivity);
        ReadSetting(s, "lobeAngleFraction", r.lobeAngleFraction);
        ReadSetting(s, "roughnessFraction", r.roughnessFraction);
        ReadSetting(s, "antilagSigmaScale", r.antilagSigmaScale);
        ReadSetting(s, "maxStabilizedFrameNum", r.maxStabilizedFrameNum);
        ReadSetting(s, "colorCompression", r.colorCompression);
        ReadSetting(s, "antiFireflySigma", r.antiFireflySigma);
        ReadSetting(s, "forceReferenceAccumulation", r.forceReferenceAccumulation);
        ReadSetting(s, "isConfidenceInput", r.isConfidenceInput);
        uint32_t checkerboard = uint32_t(r.checkerboardMode);
        ReadSetting(s, "checkerboardMode", checkerboard);
        r.checkerboardMode = nrd::CheckerboardMode(checkerboard);
        return true;
    }
    bool EnableConfidenceInputs() override
    {
        if (m_Occlusion)
            return false;
        m_Settings.isConfidenceInput = true;
        return true;
    }
    nrd::Result ApplySettings(nrd::Integration& integration, nrd::Identifier id) override
    {
        return integration.SetMethodSettings(id, m_Settings);
    }

    void GetInputs(const FrameData& f, const std::string&, const Image&, std::vector<AdapterTexture>& inputs) const override
    {
        using F = nrd::rhi::Format;
        using R = nrd::ResourceType;
        for (int s = 0; s < 2; s++)
        {
            bool diffuse = s == 0;
            if (diffuse ? !m_Diffuse : !m_Specular)
                continue;
            const Image& signal = diffuse ? f.diffuse : f.specular;
            if (m_Occlusion)
            {
                std::vector<float> hitDist(size_t(signal.width) * signal.height);
                for (size_t i = 0; i < hitDist.size(); i++)
                    hitDist[i] = signal.pixels[i * signal.channels + 3];
                inputs.push_back({diffuse ? R::IN_DIFF_HITDIST : R::IN_SPEC_HITDIST, F::R16_SFLOAT, hitDist});
            }
            else
                inputs.push_back({diffuse ? R::IN_DIFF_RADIANCE_HITDIST : R::IN_SPEC_RADIANCE_HITDIST, F::RGBA16_SFLOAT,
                                  ExpandChannels(signal, 4)});
        }
    }

    nrd::ResourceType GetOutput(const std::string& signal) const override
    {
        using R = nrd::ResourceType;
        if (signal == "diffuse" || signal == "diffuse_occlusion")
            return m_Occlusion ? R::OUT_DIFF_HITDIST : R::OUT_DIFF_RADIANCE_HITDIST;
        return m_Occlusion ? R::OUT_SPEC_HITDIST : R::OUT_SPEC_RADIANCE_HITDIST;
    }
    Image DecodeOutput(const std::string&, const Image& output) const override
    {
        return KeepChannels(output, m_Occlusion ? 1 : 3);
    }

private:
    bool m_Diffuse, m_Specular, m_Occlusion;
    nrd::ReblurSettings m_Settings;
};

} // namespace

std::unique_ptr<MethodAdapter> CreateReblurAdapter(const std::string& method)
{
    struct Entry
    {
        const char* name;
        bool diffuse, specular, occlusion;
    };
    const Entry entries[] = {{"REBLUR_DIFFUSE", true, false, false},
                             {"REBLUR_SPECULAR", false, true, false},
                             {"REBLUR_DIFFUSE_SPECULAR", true, true, false},
                             {"REBLUR_DIFFUSE_OCCLUSION", true, false, true},
                             {"REBLUR_SPECULAR_OCCLUSION", false, true, true},
                             {"REBLUR_DIFFUSE_SPECULAR_OCCLUSION", true, true, true}};
    for (const Entry& e : entries)
        if (method == e.name)
            return std::unique_ptr<MethodAdapter>(new ReblurAdapter(e.diffuse, e.specular, e.occlusion));
    return nullptr;
}

} // namespace nrdlab
