// SIGMA: second, smaller blur with a differently rotated kernel. Writes a transient texture, or the
// application's output directly when temporal stabilization is off.
#include "Sigma_Constants.h"

#if SIGMA_TRANSLUCENCY
NRD_PASS_BEGIN(Sigma_ShadowTranslucency_PostBlur, 16, 16)
#else
NRD_PASS_BEGIN(Sigma_Shadow_PostBlur, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    SIGMA_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Shadow)
NRD_INPUT(3, gIn_Penumbra)
NRD_INPUT(4, gIn_TileModes)
NRD_OUTPUT(5, gOut_Shadow)
NRD_PASS_END
