// REFLECTION spatial pass (document 002, "prefilter"): 16 Halton(2, 3) samples in 7x7, mirrored by
// the pixel's position in its quad, weighted by normal, depth, roughness and similarity to the
// tile's 8x8 average.
NRD_PASS_BEGIN(Reflection_Spatial, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REFLECTION_DENOISE_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Radiance)
NRD_INPUT(1, gIn_NormalRoughness)
NRD_INPUT(2, gIn_ViewZ)
NRD_INPUT(3, gIn_TileAverage)
NRD_BUFFER(4, gTileList, uint)
NRD_INOUT(5, gOut_Spatial, rgba16f)
NRD_PASS_END
