// RELAX: marks the 8x8 tiles that hold at least one pixel to denoise (the other passes skip the rest).
NRD_PASS_BEGIN(Relax_ClassifyTiles, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    RELAX_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_ViewZ)
NRD_OUTPUT(1, gOut_Tiles)                        // R8: 1 = denoise, 0 = sky only. 1/8 x 1/8 size.
NRD_PASS_END
