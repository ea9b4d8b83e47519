// REFLECTION temporal pass (document 002, "resolve temporal"): outlier removal of the spatial
// result, history clipped to the 5x5 neighbourhood statistics with leeway, blended by sample
// count; stores the history and the temporal variance the next frame's classification reads.
NRD_PASS_BEGIN(Reflection_Temporal, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REFLECTION_DENOISE_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Spatial)
NRD_INPUT(1, gIn_Reprojected)
NRD_INPUT(2, gIn_NormalRoughness)
NRD_INPUT(3, gIn_ViewZ)
NRD_BUFFER(4, gTileList, uint)
NRD_INOUT(5, gOut_History, rgba16f)
NRD_INOUT(6, gOut_TemporalVariance, r16f)
NRD_INOUT(7, gOut_Temporal, rgba16f)
NRD_OUTPUT(8, gOut_Output)
NRD_PASS_END
