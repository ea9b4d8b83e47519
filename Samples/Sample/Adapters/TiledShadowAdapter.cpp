// TILED_SHADOW on the lab's 1-ray shadow visibility, with the penumbrae (IN_SHADOWDATA) and the
// shadow light of every frame for the moving lights (TiledShadowSettings::isShadowDataInput; set
// "isShadowDataInput": false for document 000's inputs alone).
#include "Adapters.h"

#include "NRDIntegration.h"

#include <algorithm>
#include <cstring>

namespace nrdlab
{

const char* const kTiledShadowSettingsKey = "tiledShadow";

namespace
{

class TiledShadowAdapter : public MethodAdapter
{
public:
    std::vector<std::string> GetSignals() const override { return {"shadow"}; }
    SignalMask GetLabSignals(const std::string&) const override { return SIGNAL_SHADOW; }
    void GetSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth) const override
    {
        GetLabSignalImages(f, signal, noisy, truth);
    }

    const char* GetSettingsKey() const override { return kTiledShadowSettingsKey; }
    bool ParseSettings(const nlohmann::json& t, std::string&) override
    {
        ReadSetting(t, "enableTileSkipping", m_Settings.enableTileSkipping);
        ReadSetting(t, "neighborhoodRadius", m_Settings.neighborhoodRadius);
        ReadSetting(t, "historyClampSigma", m_Settings.historyClampSigma);
        ReadSetting(t, "atrousPassNum", m_Settings.atrousPassNum);
        ReadSetting(t, "maxHistoryFrameNum", m_Settings.maxHistoryFrameNum);
        ReadSetting(t, "planeDistanceSensitivity", m_Settings.planeDistanceSensitivity);
        ReadSetting(t, "normalPower", m_Settings.normalPower);
        ReadSetting(t, "isShadowDataInput", m_Settings.isShadowDataInput);
        if (t.contains("debugView"))
            m_Settings.debugView = nrd::TiledShadowDebug(t["debugView"].get<int>());
        return true;
    }
    nrd::Result ApplySettings(nrd::Integration& integration, nrd::Identifier id) override
    {
        return integration.SetMethodSettings(id, m_Settings);
    }
    void ApplyFrameSettings(nrd::Integration& integration, nrd::Identifier id, const FrameData& frame) override
    {
        if (!m_Settings.isShadowDataInput)
            return;
        memcpy(m_Settings.lightDirection, frame.light.direction, sizeof(m_Settings.lightDirection));
        m_Settings.tanOfLightAngularRadius = std::min(frame.light.tanOfLightAngularRadius, 1.0f);
        memcpy(m_Settings.lightPosition, frame.light.position, sizeof(m_Settings.lightPosition));
        m_Settings.lightRadius = frame.light.type == LightType::SPHERE ? frame.light.radius : 0.0f;
        integration.SetMethodSettings(id, m_Settings);
    }

    void GetInputs(const FrameData& f, const std::string&, const Image&, std::vector<AdapterTexture>& inputs) const override
    {
        inputs.push_back({nrd::ResourceType::IN_SHADOW_VISIBILITY, nrd::rhi::Format::R8_UNORM, ExpandChannels(f.shadowVisibility, 1)});
        if (m_Settings.isShadowDataInput)
            inputs.push_back({nrd::ResourceType::IN_SHADOWDATA, nrd::rhi::Format::RG16_SFLOAT, ExpandChannels(f.shadowData, 2)});
    }

    nrd::ResourceType GetOutput(const std::string&) const override { return nrd::ResourceType::OUT_SHADOW_TRANSLUCENCY; }
    Image DecodeOutput(const std::string&, const Image& output) const override
    {
        Image shadow = KeepChannels(output, 1);
        UnpackShadow(shadow);
        return shadow;
    }

private:
    nrd::TiledShadowSettings m_Settings = DefaultSettings();

    static nrd::TiledShadowSettings DefaultSettings()
    {
        nrd::TiledShadowSettings s;
        s.isShadowDataInput = true;
        return s;
    }
};

} // namespace

std::unique_ptr<MethodAdapter> CreateTiledShadowAdapter(const std::string& method)
{
    if (method != "TILED_SHADOW")
        return nullptr;
    return std::unique_ptr<MethodAdapter>(new TiledShadowAdapter());
}

} // namespace nrdlab
