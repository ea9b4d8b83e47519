// MethodAdapter.h - what the method runner (nrd-sample, the benchmark, the quality tests) needs to
// know about one method family, in one place: which scene-lab signals it denoises, which lab images
// feed which IN_* texture in which format, which OUT_* is read back and how it is decoded into the
// channels compared against the truth, and its settings struct (JSON key, parsing, application).
//
// A family is added by writing one adapter (MethodAdapters.cpp) and one line in its registry; the
// runner itself has no per-method code. The G-buffer inputs (IN_VIEWZ, IN_NORMAL_ROUGHNESS, IN_MV)
// and the common settings are the runner's.
#pragma once

#include "Image.h"
#include "SceneLab.h"

#include "NRD.h"
#include "RHI.h"

#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <string>
#include <vector>

namespace nrd
{
class Integration;
}

namespace nrdlab
{

// One application texture the runner creates, uploads every frame and binds.
struct AdapterTexture
{
    nrd::ResourceType type = nrd::ResourceType::MAX_NUM;
    nrd::rhi::Format format = nrd::rhi::Format::RGBA16_SFLOAT;
    std::vector<float> pixels; // width * height * GetFormatInfo(format).channelNum floats.
    uint32_t width = 0, height = 0; // 0: the render size.
};

class MethodAdapter
{
public:
    virtual ~MethodAdapter() = default;

    // Report names of the signals this adapter compares (nrd-sample --signal); the first is the
    // default.
    virtual std::vector<std::string> GetSignals() const = 0;

    // Scene-lab signals to render for 'signal' (one of GetSignals()).
    virtual SignalMask GetLabSignals(const std::string& signal) const = 0;

    // The noisy input and the truth of 'signal' in the compared channels.
    virtual void GetSignalImages(const FrameData& frame, const std::string& signal, Image& noisy,
                                 Image& truth) const = 0;

    // Key of the settings object in the runner's settings JSON ("sigma", ...); nullptr if none.
    virtual const char* GetSettingsKey() const { return nullptr; }

    // Reads the settings object under GetSettingsKey(). Unknown fields are ignored; a field of the
    // wrong type returns false with 'error' set.
    virtual bool ParseSettings(const nlohmann::json& /*settings*/, std::string& /*error*/) { return true; }

    // Sets the method settings once, after the denoiser is created.
    virtual nrd::Result ApplySettings(nrd::Integration& /*integration*/, nrd::Identifier /*id*/) { return nrd::Result::SUCCESS; }

    // Makes the method read IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE (before ApplySettings); false
    // if it cannot (RunOptions::confidence).
    virtual bool EnableConfidenceInputs() { return false; }

    // Updates per-frame method settings (e.g. the light direction) before a frame is denoised.
    virtual void ApplyFrameSettings(nrd::Integration& /*integration*/, nrd::Identifier /*id*/, const FrameData& /*frame*/) {}

    // The method's signal inputs of this frame ('noisy' is GetSignalImages' noisy image).
    virtual void GetInputs(const FrameData& frame, const std::string& signal, const Image& noisy,
                           std::vector<AdapterTexture>& inputs) const = 0;

    // The output texture that is read back, and its format.
    virtual nrd::ResourceType GetOutput(const std::string& signal) const = 0;
    virtual nrd::rhi::Format GetOutputFormat(const std::string& /*signal*/) const { return nrd::rhi::Format::RGBA16_SFLOAT; }

    // Content of the output texture before denoising. The denoisers do not write sky pixels: they
    // start from the noisy input so that they compare as passed through. Default: 'noisy' widened
    // to the output's channels, missing channels 1.
    virtual std::vector<float> GetOutputInitialization(const std::string& signal, const Image& noisy) const;

    // True for a method whose application traces rays between its two dispatch stages
    // (nrd::Method::REFLECTION): the runner then runs DispatchStage::CLASSIFICATION, reads back the
    // ray list, has the scene lab trace exactly those rays (SceneLab::TraceSpecularRays), uploads
    // the result as IN_SPEC_RADIANCE_HITDIST and runs DispatchStage::DENOISING.
    virtual bool IsRayListTraced() const { return false; }

    // Decodes the read-back output (all its channels) into the compared channels.
    virtual Image DecodeOutput(const std::string& signal, const Image& output) const = 0;
};

// The adapter of 'method' (nrd::GetMethodString name, or "NONE": the noisy input passed through),
// or nullptr if there is none.
std::unique_ptr<MethodAdapter> CreateMethodAdapter(const std::string& method);

// Settings keys of every adapter (for the settings JSON's unknown-key check).
std::vector<std::string> GetAdapterSettingsKeys();

// Helpers shared by adapters.

// Keeps the first 'channels' channels of an image (missing ones are 0).
Image KeepChannels(const Image& src, uint32_t channels);

// Channel 'channel' of an image, as a 1-channel image.
Image KeepChannel(const Image& src, uint32_t channel);

// Widens an image to 'channels' channels (missing ones get 'fill').
std::vector<float> ExpandChannels(const Image& src, uint32_t channels, float fill = 0.0f);

} // namespace nrdlab
