// NRD-style real-time denoiser SDK: entry points.
//
// The library makes no graphics API calls. It describes pipelines, texture pools and per-frame
// compute dispatches; the application (or Integration/NRDIntegration.h) executes them.
//
// Flow: GetLibraryDesc -> CreateDenoiser -> GetDenoiserDesc (once) -> per frame SetCommonSettings,
// SetMethodSettings, GetComputeDispatches -> DestroyDenoiser.
#pragma once

#include <cstddef>
#include <cstdint>

#define NRD_VERSION_MAJOR 0
#define NRD_VERSION_MINOR 1
#define NRD_VERSION_BUILD 0
#define NRD_VERSION_DATE "22 November 2026"

#if defined(_WIN32) && defined(NRD_SHARED_LIBRARY)
#  if defined(NRD_EXPORTS)
#    define NRD_API extern "C++" __declspec(dllexport)
#  else
#    define NRD_API extern "C++" __declspec(dllimport)
#  endif
#elif defined(__GNUC__) || defined(__clang__)
// The core is compiled with hidden visibility: only NRD_API functions leave libNRD.so.
#  define NRD_API extern "C++" __attribute__((visibility("default")))
#else
#  define NRD_API extern "C++"
#endif

#include "NRDDescs.h"
#include "NRDSettings.h"

namespace nrd
{

// Library information: version, supported methods, SPIR-V binding model. Never fails.
// The returned reference is static and valid for the lifetime of the process.
NRD_API const LibraryDesc& GetLibraryDesc();

// Creates a denoiser holding the methods of 'desc'. On success '*outDenoiser' is non-null.
// Returns INVALID_ARGUMENT for zero / too large sizes, an empty or null method list or an unknown
// method, NON_UNIQUE_IDENTIFIER if two methods share an identifier, FAILURE on allocation failure.
// On failure '*outDenoiser' is null and a message goes to desc.logCallback (if set).
NRD_API Result CreateDenoiser(const DenoiserCreationDesc& desc, Denoiser*& outDenoiser);

// Everything needed once at initialization: pipelines, samplers, pools, buffers, descriptor counts.
// The returned reference stays valid until DestroyDenoiser. 'denoiser' must not be null.
NRD_API const DenoiserDesc& GetDenoiserDesc(const Denoiser& denoiser);

// Settings shared by all methods of the denoiser, for the next GetComputeDispatches call.
// Returns INVALID_ARGUMENT (and keeps the previous settings) for NaN / Inf / singular matrices,
// jitter outside [-0.5, 0.5], a zero resource size or one larger than the creation size,
// a negative / NaN denoising range or motion vector scale.
NRD_API Result SetCommonSettings(Denoiser& denoiser, const CommonSettings& settings);

// Per-method settings. The type must match the method family of 'identifier' (SigmaSettings for
// SIGMA_*, ReferenceSettings for REFERENCE, TiledShadowSettings for TILED_SHADOW, ReblurSettings for REBLUR_*,
// ConfidenceSettings for CONFIDENCE, ReflectionSettings for REFLECTION, RelaxSettings for RELAX_*); otherwise
// INVALID_ARGUMENT. Out-of-range values return INVALID_ARGUMENT and keep the previous settings.
// Unknown identifier: INVALID_ARGUMENT.
NRD_API Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const SigmaSettings& settings);
NRD_API Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const ReferenceSettings& settings);
NRD_API Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const TiledShadowSettings& settings);
NRD_API Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const ReblurSettings& settings);
NRD_API Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const ConfidenceSettings& settings);
NRD_API Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const ReflectionSettings& settings);
NRD_API Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const RelaxSettings& settings);

// Checks hit distance parameters against their documented ranges (finite, A > 0, B >= 0, C >= 1,
// D <= 0); the settings of every method that takes HitDistanceParameters call it. Returns SUCCESS or
// INVALID_ARGUMENT, with a message naming the field to 'logCallback' (optional, may be null).
NRD_API Result ValidateHitDistanceParameters(const HitDistanceParameters& parameters, LogCallback logCallback = nullptr,
                                             void* logUserArg = nullptr);

// Produces the dispatches of one frame, in execution order, for the methods listed in
// 'identifiers' (or for all methods, in creation order, if 'identifiersNum' is 0; 'identifiers' may
// then be null). Each method's part of the frame is produced once per SetCommonSettings call.
// '*outDispatches' and everything it points to (resources, constants, names) belong to the
// denoiser and stay valid until the next GetComputeDispatches / SetCommonSettings / Destroy call.
// Returns INVALID_ARGUMENT for an unknown or repeated identifier or if SetCommonSettings never succeeded.
NRD_API Result GetComputeDispatches(Denoiser& denoiser, const Identifier* identifiers, uint32_t identifiersNum,
                                    const DispatchDesc*& outDispatches, uint32_t& outDispatchesNum);

// As above, limited to one part of the frame (DispatchStage): CLASSIFICATION before the
// application's ray pass, then DENOISING after it, for the same SetCommonSettings call. Methods
// without a classification part return nothing for CLASSIFICATION. INVALID_ARGUMENT for an unknown
// stage, as above otherwise.
NRD_API Result GetComputeDispatches(Denoiser& denoiser, const Identifier* identifiers, uint32_t identifiersNum,
                                    DispatchStage stage, const DispatchDesc*& outDispatches, uint32_t& outDispatchesNum);

// Destroys a denoiser created by CreateDenoiser. Null is allowed and ignored.
NRD_API void DestroyDenoiser(Denoiser* denoiser);

// Readable names; never null ("UNKNOWN" for out-of-range values).
NRD_API const char* GetResultString(Result result);
NRD_API const char* GetMethodString(Method method);
NRD_API const char* GetResourceTypeString(ResourceType resourceType);
NRD_API const char* GetFormatString(Format format);

// Parses a method name as printed by GetMethodString (e.g. "SIGMA_SHADOW"). Returns false if unknown.
NRD_API bool GetMethodFromString(const char* name, Method& outMethod);

// Bytes per pixel of a pool format (for memory estimates).
NRD_API uint32_t GetFormatBytesPerPixel(Format format);

} // namespace nrd
