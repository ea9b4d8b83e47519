// SIGMA_SHADOW and SIGMA_SHADOW_TRANSLUCENCY on the lab's shadow signal (translucency: all lights).
#include "Adapters.h"

#include "NRDIntegration.h"

#include <algorithm>
#include <cstring>

namespace nrdlab
{

const char* const kSigmaSettingsKey = "sigma";

namespace
{

class SigmaAdapter : public MethodAdapter
{
public:
    explicit SigmaAdapter(bool translucency) : m_Translucency(translucency) {}

    std::vector<std::string> GetSignals() const override { return {"shadow"}; }
    SignalMask GetLabSignals(const std::string&) const override
    {
        return m_Translucency ? SIGNAL_TRANSLUCENCY : SIGNAL_SHADOW;
    }
    void GetSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth) const override
    {
        if (!m_Translucency)
            return GetLabSignalImages(f, signal, noisy, truth);
        noisy = KeepChannels(f.translucency, 4);
        truth = KeepChannels(f.translucencyTruth, 4);
    }

    const char* GetSettingsKey() const override { return kSigmaSettingsKey; }
    bool ParseSettings(const nlohmann::json& s, std::string&) override
    {
        ReadSetting(s, "planeDistanceSensitivity", m_Settings.planeDistanceSensitivity);
        ReadSetting(s, "blurRadiusScale", m_Settings.blurRadiusScale);
        ReadSetting(s, "maxStabilizedFrameNum", m_Settings.maxStabilizedFrameNum);
        ReadSetting(s, "isLightSizeGiven", m_IsLightSizeGiven);
        return true;
    }
    nrd::Result ApplySettings(nrd::Integration& integration, nrd::Identifier id) override
    {
        return integration.SetMethodSettings(id, m_Settings);
    }
    void ApplyFrameSettings(nrd::Integration& integration, nrd::Identifier id, const FrameData& frame) override
    {
        memcpy(m_Settings.lightDirection, frame.light.direction, sizeof(m_Settings.lightDirection));
        // The moving light: the shadow light's. The translucency signal packs every light together,
        // whose shadows do not all move with it: unknown there.
        // "isLightSizeGiven": false leaves its size unknown (0), as an application that gives the direction
        // alone: the light's moves and its occluders' are then not followed.
        bool isSized = !m_Translucency && m_IsLightSizeGiven;
        m_Settings.tanOfLightAngularRadius = isSized ? std::min(frame.light.tanOfLightAngularRadius, 1.0f) : 0.0f;
        memcpy(m_Settings.lightPosition, frame.light.position, sizeof(m_Settings.lightPosition));
        m_Settings.lightRadius = isSized && frame.light.type == LightType::SPHERE ? frame.light.radius : 0.0f;
        integration.SetMethodSettings(id, m_Settings);
    }

    void GetInputs(const FrameData& f, const std::string&, const Image&, std::vector<AdapterTexture>& inputs) const override
    {
        using F = nrd::rhi::Format;
        using R = nrd::ResourceType;
        if (m_Translucency)
        {
            inputs.push_back({R::IN_SHADOWDATA, F::RG16_SFLOAT, ExpandChannels(f.translucencyShadowData, 2)});
            inputs.push_back({R::IN_SHADOW_TRANSLUCENCY, F::RGBA16_SFLOAT, ExpandChannels(f.translucency, 4)});
        }
        else
            inputs.push_back({R::IN_SHADOWDATA, F::RG16_SFLOAT, ExpandChannels(f.shadowData, 2)});
    }

    nrd::ResourceType GetOutput(const std::string&) const override { return nrd::ResourceType::OUT_SHADOW_TRANSLUCENCY; }
    Image DecodeOutput(const std::string&, const Image& output) const override
    {
        Image shadow = KeepChannels(output, m_Translucency ? 4 : 1);
        UnpackShadow(shadow);
        return shadow;
    }

private:
    bool m_Translucency = false;
    nrd::SigmaSettings m_Settings;
    bool m_IsLightSizeGiven = true;
};

} // namespace

std::unique_ptr<MethodAdapter> CreateSigmaAdapter(const std::string& method)
{
    if (method != "SIGMA_SHADOW" && method != "SIGMA_SHADOW_TRANSLUCENCY")
        return nullptr;
    return std::unique_ptr<MethodAdapter>(new SigmaAdapter(method == "SIGMA_SHADOW_TRANSLUCENCY"));
}

} // namespace nrdlab
