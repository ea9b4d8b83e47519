// REBLUR: 16x16 tiles with at least one pixel to denoise (1) or only sky (0); stores this frame's
// viewZ for the next frame's reprojection (ping-pong by frame parity). One pipeline for all variants.
#include "Reblur_Constants.h"

NRD_PASS_BEGIN(Reblur_ClassifyTiles, 16, 16)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REBLUR_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_ViewZ)
NRD_OUTPUT(1, gOut_Tiles)
NRD_OUTPUT(2, gOut_ViewZ)
NRD_PASS_END
