// REBLUR_* on the lab's diffuse and specular signals. The lab's hit distances are in world units:
// they are normalized here as REBLUR_FrontEnd_GetNormHitDist does (diffuse with roughness 1), with
// the method's HitDistanceParameters. The compared channels are the radiance (rgb); the occlusion
// variants compare the normalized hit distance against the normalized mean hit distance of the truth.
#include "Adapters.h"

#include "NRDIntegration.h"

#include <algorithm>
#include <cmath>

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
            signals.push_back("diffuse");
        if (m_Specular)
            signals.push_back("specular");
        return signals;
    }
    // Both signals are rendered for a diffuse + specular method (both inputs are read).
    SignalMask GetLabSignals(const std::string&) const override
    {
        return SignalMask((m_Diffuse ? SignalMask(SIGNAL_DIFFUSE) : 0u) | (m_Specular ? SignalMask(SIGNAL_SPECULAR) : 0u));
    }
    void GetSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth) const override
    {
        if (!m_Occlusion)
            return GetLabSignalImages(f, signal, noisy, truth);
        bool diffuse = signal == "diffuse";
        noisy = NormalizedHitDistance(f, diffuse ? f.diffuse : f.specular, diffuse);
        truth = NormalizedHitDistance(f, diffuse ? f.diffuseTruth : f.specularTruth, diffuse);
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
        ReadSetting(s, "prePassBlurRadius", r.prePassBlurRadius);
        ReadSetting(s, "postBlurRadiusScale", r.postBlurRadiusScale);
        ReadSetting(s, "planeDistanceSensitivity", r.planeDistanceSensitivity);
        ReadSetting(s, "lobeAngleFraction", r.lobeAngleFraction);
        ReadSetting(s, "roughnessFraction", r.roughnessFraction);
        ReadSetting(s, "antilagSigmaScale", r.antilagSigmaScale);
        ReadSetting(s, "maxStabilizedFrameNum", r.maxStabilizedFrameNum);
        ReadSetting(s, "colorCompression", r.colorCompression);
        ReadSetting(s, "antiFireflySigma", r.antiFireflySigma);
        ReadSetting(s, "forceReferenceAccumulation", r.forceReferenceAccumulation);
        uint32_t checkerboard = uint32_t(r.checkerboardMode);
        ReadSetting(s, "checkerboardMode", checkerboard);
        r.checkerboardMode = nrd::CheckerboardMode(checkerboard);
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
            Image norm = NormalizedHitDistance(f, signal, diffuse);
            if (m_Occlusion)
            {
                inputs.push_back({diffuse ? R::IN_DIFF_HITDIST : R::IN_SPEC_HITDIST, F::R16_SFLOAT, norm.pixels});
                continue;
            }
            std::vector<float> packed = ExpandChannels(signal, 4);
            for (size_t i = 0; i < norm.pixels.size(); i++)
                packed[i * 4 + 3] = norm.pixels[i];
            inputs.push_back({diffuse ? R::IN_DIFF_RADIANCE_HITDIST : R::IN_SPEC_RADIANCE_HITDIST, F::RGBA16_SFLOAT, packed});
        }
    }

    nrd::ResourceType GetOutput(const std::string& signal) const override
    {
        using R = nrd::ResourceType;
        if (signal == "diffuse")
            return m_Occlusion ? R::OUT_DIFF_HITDIST : R::OUT_DIFF_RADIANCE_HITDIST;
        return m_Occlusion ? R::OUT_SPEC_HITDIST : R::OUT_SPEC_RADIANCE_HITDIST;
    }
    Image DecodeOutput(const std::string&, const Image& output) const override
    {
        return KeepChannels(output, m_Occlusion ? 1 : 3);
    }

private:
    // REBLUR_FrontEnd_GetNormHitDist on the CPU (NaN / negative: 0; no hit: 1).
    Image NormalizedHitDistance(const FrameData& f, const Image& signal, bool diffuse) const
    {
        const nrd::HitDistanceParameters& p = m_Settings.hitDistanceParameters;
        Image out(signal.width, signal.height, 1);
        for (size_t i = 0; i < out.pixels.size(); i++)
        {
            float d = signal.pixels[i * signal.channels + 3];
            d = std::isnan(d) ? 0.0f : std::max(d, 0.0f);
            float z = std::fabs(f.viewZ.pixels[i]);
            z = std::isfinite(z) ? z : 0.0f;
            float r = diffuse ? 1.0f : std::min(std::max(f.normalRoughness.pixels[i * 4 + 3], 0.0f), 1.0f);
            float norm = (p.A + z * p.B) * (1.0f + (p.C - 1.0f) * std::min(std::exp2(p.D * r * r), 1.0f));
            out.pixels[i] = d >= kNoHitDistance ? 1.0f : std::min(d / norm, 1.0f);
        }
        return out;
    }

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
