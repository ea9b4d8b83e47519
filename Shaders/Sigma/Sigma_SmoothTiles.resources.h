// SIGMA: dilates the tile classification by how far kernels reach: the per-tile mode (sky, copy or
// denoise) that the filtering passes read. Shared by SIGMA_SHADOW and SIGMA_SHADOW_TRANSLUCENCY.
#include "Sigma_Constants.h"

NRD_PASS_BEGIN(Sigma_SmoothTiles, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    SIGMA_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Tiles)
NRD_INOUT(1, gOut_TileModes, r8)
NRD_PASS_END
