// REBLUR: edge-aware sparse blur on the tangent plane; one pipeline for the pre-pass, the blur and
// the post-blur (gPassIndex), radius from history length, hit distance and roughness.
#include "Reblur_Constants.h"

#if REBLUR_SPECULAR && REBLUR_OCCLUSION
NRD_PASS_BEGIN(Reblur_SpecularOcclusion_Blur, 16, 16)
#elif REBLUR_SPECULAR
NRD_PASS_BEGIN(Reblur_Specular_Blur, 16, 16)
#elif REBLUR_OCCLUSION
NRD_PASS_BEGIN(Reblur_DiffuseOcclusion_Blur, 16, 16)
#else
NRD_PASS_BEGIN(Reblur_Diffuse_Blur, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REBLUR_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Tiles)
NRD_INPUT(3, gIn_Fast)
NRD_INPUT(4, gIn_Signal)
NRD_OUTPUT(5, gOut_Signal)
NRD_INPUT(6, gIn_Debt) // Confidence debt / REBLUR_DEBT_SCALE (history fix).
NRD_PASS_END
