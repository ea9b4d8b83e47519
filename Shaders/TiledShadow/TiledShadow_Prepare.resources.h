// TILED_SHADOW prepare: packs IN_SHADOW_VISIBILITY into one 32-bit mask per 8x4-pixel tile
// (document 000, "Denoiser shadows prepare"). One invocation per tile, 8x8 tiles per group.
NRD_PASS_BEGIN(TiledShadow_Prepare, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Visibility)
NRD_INPUT(1, gIn_ViewZ)
NRD_INOUT_UINT(2, gOut_Mask, r32ui)
NRD_PASS_END
