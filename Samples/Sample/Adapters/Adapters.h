// The method families' adapters (one file each), listed by MethodAdapter.cpp.
#pragma once

#include "MethodAdapter.h"

#include <nlohmann/json.hpp>

namespace nrdlab
{

// Each returns the adapter of 'method' (nrd::GetMethodString name) if it belongs to its family,
// else nullptr.

// "NONE": the noisy input passed through (any lab signal).
std::unique_ptr<MethodAdapter> CreatePassThroughAdapter(const std::string& method);

// SIGMA_SHADOW, SIGMA_SHADOW_TRANSLUCENCY.
std::unique_ptr<MethodAdapter> CreateSigmaAdapter(const std::string& method);
extern const char* const kSigmaSettingsKey;

// REFERENCE.
std::unique_ptr<MethodAdapter> CreateReferenceAdapter(const std::string& method);
extern const char* const kReferenceSettingsKey;

// TILED_SHADOW.
std::unique_ptr<MethodAdapter> CreateTiledShadowAdapter(const std::string& method);
extern const char* const kTiledShadowSettingsKey;

// REBLUR_* (diffuse / specular, and the occlusion variants).
std::unique_ptr<MethodAdapter> CreateReblurAdapter(const std::string& method);
extern const char* const kReblurSettingsKey;
// RELAX_DIFFUSE, RELAX_SPECULAR, RELAX_DIFFUSE_SPECULAR.
std::unique_ptr<MethodAdapter> CreateRelaxAdapter(const std::string& method);
extern const char* const kRelaxSettingsKey;

// CONFIDENCE (also chained in front of a consumer, RunOptions::confidence).
std::unique_ptr<MethodAdapter> CreateConfidenceAdapter(const std::string& method);
extern const char* const kConfidenceSettingsKey;
// REFLECTION (traces the lab's specular signal for its ray list).
std::unique_ptr<MethodAdapter> CreateReflectionAdapter(const std::string& method);
extern const char* const kReflectionSettingsKey;

// Shared by the adapters: the lab's noisy input and truth of the shadow, diffuse and specular
// signals in their compared channels (shadow: 1, diffuse / specular: rgb radiance,
// diffuse_occlusion / specular_occlusion: 1, the normalized hit distance).
std::vector<std::string> GetLabSignalNames();
void GetLabSignalImages(const FrameData& frame, const std::string& signal, Image& noisy, Image& truth);
SignalMask GetLabSignalMask(const std::string& signal);

// Reads 'key' into 'value' if present (throws nlohmann::json exceptions on type errors; the runner
// reports them).
template <class T>
void ReadSetting(const nlohmann::json& j, const char* key, T& value)
{
    if (j.contains(key))
        value = j.at(key).get<T>();
}

// Denoised shadow (SIGMA_BackEnd_UnpackShadow on the CPU): clamped to [0, 1], non-finite = lit.
void UnpackShadow(Image& image);

} // namespace nrdlab
