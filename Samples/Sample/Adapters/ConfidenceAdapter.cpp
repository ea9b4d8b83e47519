// CONFIDENCE on the lab's sparse temporal gradients (FrameData::gradientsRaw, 1/3 resolution).
// Signals "diffuse_confidence" / "specular_confidence": the noisy image is the unfiltered
// confidence (each pixel converts its stratum's gradient with the method's function), the truth is
// the same function applied to the change of the lab's ground truth at the same pixel since the
// previous frame (meaningful with a still camera; the truth's own noise lowers it slightly).
// Chained in front of a consumer (RunOptions::confidence), only its inputs and settings are used.
#include "Adapters.h"

#include "NRDIntegration.h"

#include <algorithm>
#include <cmath>

namespace nrdlab
{

const char* const kConfidenceSettingsKey = "confidence";

namespace
{

float Luminance(const float* rgb) { return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2]; }

class ConfidenceAdapter : public MethodAdapter
{
public:
    std::vector<std::string> GetSignals() const override { return {"diffuse_confidence", "specular_confidence"}; }
    SignalMask GetLabSignals(const std::string& signal) const override
    {
        return SignalMask(SIGNAL_GRADIENTS | (signal == "specular_confidence" ? SIGNAL_SPECULAR : SIGNAL_DIFFUSE));
    }

    void GetSignalImages(const FrameData& f, const std::string& signal, Image& noisy, Image& truth) const override
    {
        const bool diffuse = signal != "specular_confidence";
        const Image& g = f.gradientsRaw;
        const Image& t = diffuse ? f.diffuseTruth : f.specularTruth;
        noisy = Image(f.viewZ.width, f.viewZ.height, 1);
        truth = Image(f.viewZ.width, f.viewZ.height, 1);
        std::vector<float> luminance(noisy.pixelCount(), 0.0f);
        for (uint32_t y = 0; y < noisy.height; y++)
            for (uint32_t x = 0; x < noisy.width; x++)
            {
                const size_t i = size_t(y) * noisy.width + x;
                if (g.isValid())
                {
                    const float* s = &g.pixels[(size_t(y / 3) * g.width + x / 3) * 4 + (diffuse ? 0 : 2)];
                    noisy.pixels[i] = Convert(s[0], s[1], diffuse);
                }
                luminance[i] = t.isValid() ? Luminance(&t.pixels[i * t.channels]) : 0.0f;
                truth.pixels[i] = m_PrevLuminance.size() == luminance.size()
                                      ? Convert(std::fabs(luminance[i] - m_PrevLuminance[i]), std::max(luminance[i], m_PrevLuminance[i]),
                                                diffuse)
                                      : 1.0f;
            }
        m_PrevLuminance = luminance;
    }

    const char* GetSettingsKey() const override { return kConfidenceSettingsKey; }
    bool ParseSettings(const nlohmann::json& s, std::string&) override
    {
        nrd::ConfidenceSettings& c = m_Settings;
        ReadSetting(s, "gradientThreshold", c.gradientThreshold);
        ReadSetting(s, "gradientSensitivity", c.gradientSensitivity);
        ReadSetting(s, "specularGradientSensitivity", c.specularGradientSensitivity);
        ReadSetting(s, "fallHistoryWeight", c.fallHistoryWeight);
        ReadSetting(s, "riseHistoryWeight", c.riseHistoryWeight);
        ReadSetting(s, "atrousPassNum", c.atrousPassNum);
        ReadSetting(s, "depthThreshold", c.depthThreshold);
        ReadSetting(s, "normalPower", c.normalPower);
        ReadSetting(s, "localGradientRadius", c.localGradientRadius);
        return true;
    }
    nrd::Result ApplySettings(nrd::Integration& integration, nrd::Identifier id) override
    {
        return integration.SetMethodSettings(id, m_Settings);
    }

    void GetInputs(const FrameData& f, const std::string&, const Image&, std::vector<AdapterTexture>& inputs) const override
    {
        AdapterTexture gradients;
        gradients.type = nrd::ResourceType::IN_GRADIENTS;
        gradients.format = nrd::rhi::Format::RGBA32_SFLOAT;
        gradients.width = f.gradientsRaw.width;
        gradients.height = f.gradientsRaw.height;
        gradients.pixels = ExpandChannels(f.gradientsRaw, 4);
        inputs.push_back(gradients);
    }

    nrd::ResourceType GetOutput(const std::string& signal) const override
    {
        return signal == "specular_confidence" ? nrd::ResourceType::OUT_SPEC_CONFIDENCE : nrd::ResourceType::OUT_DIFF_CONFIDENCE;
    }
    nrd::rhi::Format GetOutputFormat(const std::string&) const override { return nrd::rhi::Format::R16_SFLOAT; }
    std::vector<float> GetOutputInitialization(const std::string&, const Image& noisy) const override
    {
        return std::vector<float>(noisy.pixels.size(), 1.0f); // Sky: not written, full confidence.
    }
    Image DecodeOutput(const std::string&, const Image& output) const override { return KeepChannels(output, 1); }

private:
    float Convert(float difference, float luminance, bool diffuse) const
    {
        const nrd::ConfidenceSettings& s = m_Settings;
        float g = difference / std::max(luminance, 1e-6f);
        float sensitivity = diffuse ? s.gradientSensitivity : s.specularGradientSensitivity;
        return std::min(std::max(1.0f - std::max(g - s.gradientThreshold, 0.0f) * sensitivity, 0.0f), 1.0f);
    }

    nrd::ConfidenceSettings m_Settings;
    mutable std::vector<float> m_PrevLuminance; // The truth's luminance of the previous frame.
};

} // namespace

std::unique_ptr<MethodAdapter> CreateConfidenceAdapter(const std::string& method)
{
    if (method != "CONFIDENCE")
        return nullptr;
    return std::unique_ptr<MethodAdapter>(new ConfidenceAdapter());
}

} // namespace nrdlab
