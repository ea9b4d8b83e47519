// REBLUR: temporal stabilization of the luminance (and hit distance) of the post-blurred history
// with neighbourhood clamping and anti-lag; writes the output and the stabilized luminance.
#include "Reblur_Constants.h"

#if REBLUR_SPECULAR && REBLUR_OCCLUSION
NRD_PASS_BEGIN(Reblur_SpecularOcclusion_TemporalStabilization, 16, 16)
#elif REBLUR_SPECULAR
NRD_PASS_BEGIN(Reblur_Specular_TemporalStabilization, 16, 16)
#elif REBLUR_OCCLUSION
NRD_PASS_BEGIN(Reblur_DiffuseOcclusion_TemporalStabilization, 16, 16)
#else
NRD_PASS_BEGIN(Reblur_Diffuse_TemporalStabilization, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REBLUR_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Tiles)
NRD_INPUT(3, gIn_History)
NRD_INPUT(4, gIn_Fast)
NRD_INOUT(5, gInOut_Stabilized, r16f)
NRD_OUTPUT(6, gOut_Signal)
NRD_PASS_END
