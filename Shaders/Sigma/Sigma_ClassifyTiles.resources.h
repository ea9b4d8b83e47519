// SIGMA: per 16x16 tile, whether the input varies (penumbra to denoise), is uniform (copy) or sky.
#include "Sigma_Constants.h"

#if SIGMA_TRANSLUCENCY
NRD_PASS_BEGIN(Sigma_ShadowTranslucency_ClassifyTiles, 16, 16)
#else
NRD_PASS_BEGIN(Sigma_Shadow_ClassifyTiles, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    SIGMA_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_ViewZ)
NRD_INPUT(1, gIn_ShadowData)
#if SIGMA_TRANSLUCENCY
NRD_INPUT(2, gIn_ShadowTranslucency)
NRD_INOUT(3, gOut_Tiles, rg16f)
#else
NRD_INOUT(2, gOut_Tiles, rg16f)
#endif
NRD_PASS_END
