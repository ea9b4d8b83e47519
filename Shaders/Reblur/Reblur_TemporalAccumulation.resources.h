// REBLUR: reprojects the slow, fast and stabilized histories (surface motion; specular also virtual
// motion), accumulates this frame, anti-lag of the slow history towards the fast one. Writes the
// accumulated signal (gInOut_Signal, in place of the pre-pass result) and the auxiliary values
// (fast history, history length, reprojected stabilized luminance) for the history fix.
#include "Reblur_Constants.h"

#if REBLUR_SPECULAR && REBLUR_OCCLUSION
NRD_PASS_BEGIN(Reblur_SpecularOcclusion_TemporalAccumulation, 16, 16)
#elif REBLUR_SPECULAR
NRD_PASS_BEGIN(Reblur_Specular_TemporalAccumulation, 16, 16)
#elif REBLUR_OCCLUSION
NRD_PASS_BEGIN(Reblur_DiffuseOcclusion_TemporalAccumulation, 16, 16)
#else
NRD_PASS_BEGIN(Reblur_Diffuse_TemporalAccumulation, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REBLUR_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Mv)
NRD_INPUT(3, gIn_Signal)
NRD_INPUT(4, gIn_Confidence)
NRD_INPUT(5, gIn_Tiles)
NRD_INPUT(6, gPrev_ViewZ)
NRD_INPUT(7, gPrev_History)
NRD_INPUT(8, gPrev_Fast)
NRD_INPUT(9, gPrev_Stabilized)
NRD_INOUT(10, gInOut_Signal, rgba16f)
#if !REBLUR_OCCLUSION
NRD_OUTPUT(11, gOut_Aux)
NRD_INPUT(12, gPrev_Debt) // Confidence debt / REBLUR_DEBT_SCALE.
#else
NRD_INPUT(11, gPrev_Debt)
#endif
NRD_PASS_END
