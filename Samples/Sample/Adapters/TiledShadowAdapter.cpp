// TILED_SHADOW on the lab's 1-ray shadow visibility.
#include "Adapters.h"

#include "NRDIntegration.h"

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
        if (t.contains("debugView"))
            m_Settings.debugView = nrd::TiledShadowDebug(t["debugView"].get<int>());
        return true;
    }
    nrd::Result ApplySettings(nrd::Integration& integration, nrd::Identifier id) override
    {
        return integration.SetMethodSettings(id, m_Settings);
    }

    void GetInputs(const FrameData& f, const std::string&, const Image&, std::vector<AdapterTexture>& inputs) const override
    {
        inputs.push_back({nrd::ResourceType::IN_SHADOW_VISIBILITY, nrd::rhi::Format::R8_UNORM, ExpandChannels(f.shadowVisibility, 1)});
    }

    nrd::ResourceType GetOutput(const std::string&) const override { return nrd::ResourceType::OUT_SHADOW_TRANSLUCENCY; }
    Image DecodeOutput(const std::string&, const Image& output) const override
    {
        Image shadow = KeepChannels(output, 1);
        UnpackShadow(shadow);
        return shadow;
    }

private:
    nrd::TiledShadowSettings m_Settings;
};

} // namespace

std::unique_ptr<MethodAdapter> CreateTiledShadowAdapter(const std::string& method)
{
    if (method != "TILED_SHADOW")
        return nullptr;
    return std::unique_ptr<MethodAdapter>(new TiledShadowAdapter());
}

} // namespace nrdlab
