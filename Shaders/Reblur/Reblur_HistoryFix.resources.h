// REBLUR: history fix (wide sparse reconstruction where the history is short) and anti-firefly;
// writes the slow history (input of the blur), the fast history + length and the reprojected
// stabilized luminance.
#include "Reblur_Constants.h"

#if REBLUR_SPECULAR && REBLUR_OCCLUSION
NRD_PASS_BEGIN(Reblur_SpecularOcclusion_HistoryFix, 16, 16)
#elif REBLUR_SPECULAR
NRD_PASS_BEGIN(Reblur_Specular_HistoryFix, 16, 16)
#elif REBLUR_OCCLUSION
NRD_PASS_BEGIN(Reblur_DiffuseOcclusion_HistoryFix, 16, 16)
#else
NRD_PASS_BEGIN(Reblur_Diffuse_HistoryFix, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REBLUR_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Tiles)
NRD_INPUT(3, gIn_Signal)
#if !REBLUR_OCCLUSION
NRD_INPUT(4, gIn_Aux)
NRD_OUTPUT(5, gOut_History)
NRD_OUTPUT(6, gOut_Fast)
NRD_OUTPUT(7, gOut_Stabilized)
NRD_OUTPUT(8, gOut_Debt)
#else
NRD_OUTPUT(4, gOut_History)
NRD_OUTPUT(5, gOut_Fast)
NRD_OUTPUT(6, gOut_Stabilized)
NRD_OUTPUT(7, gOut_Debt)
#endif
NRD_PASS_END
