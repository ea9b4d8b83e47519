// REFLECTION reprojection (document 002, "reproject"): per pixel of the listed tiles, the history
// by surface motion (rough) or hit-distance parallax (shiny), per-tap disocclusion by depth, normal
// and roughness (2x2 slow path at edges); the 8x8 average radiance and luminance variance of the
// tile; mirrors are output as traced.
NRD_PASS_BEGIN(Reflection_Reproject, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REFLECTION_DENOISE_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Radiance)
NRD_INPUT(1, gIn_NormalRoughness)
NRD_INPUT(2, gIn_ViewZ)
NRD_INPUT(3, gIn_Mv)
NRD_INPUT(4, gIn_PrevViewZ)
NRD_INPUT(5, gIn_PrevNormalRoughness)
NRD_INPUT(6, gIn_History)
NRD_BUFFER(7, gTileList, uint)
NRD_INOUT(8, gOut_Reprojected, rgba16f)
NRD_INOUT(9, gOut_TileAverage, rgba16f)
NRD_OUTPUT(10, gOut_Output)
NRD_PASS_END
