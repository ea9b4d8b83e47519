// SIGMA: penumbra-driven spatial blur of the noisy input (dense 5x5 + sparse disk in the tangent plane).
#include "Sigma_Constants.h"

#if SIGMA_TRANSLUCENCY
NRD_PASS_BEGIN(Sigma_ShadowTranslucency_Blur, 16, 16)
#else
NRD_PASS_BEGIN(Sigma_Shadow_Blur, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    SIGMA_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_ShadowData)
NRD_INPUT(3, gIn_TileModes)
#if SIGMA_TRANSLUCENCY
NRD_INPUT(4, gIn_ShadowTranslucency)
NRD_INOUT(5, gOut_Shadow, rgba16f)
NRD_INOUT(6, gOut_Penumbra, r16f)
#else
NRD_INOUT(4, gOut_Shadow, r16f)
NRD_INOUT(5, gOut_Penumbra, r16f)
#endif
NRD_PASS_END
