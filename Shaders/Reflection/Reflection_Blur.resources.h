// REFLECTION blur (document 002, "blur"): 5x5 edge-aware Gaussian with roughness edge stopping.
NRD_PASS_BEGIN(Reflection_Blur, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    REFLECTION_DENOISE_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Temporal)
NRD_INPUT(1, gIn_NormalRoughness)
NRD_INPUT(2, gIn_ViewZ)
NRD_BUFFER(3, gTileList, uint)
NRD_OUTPUT(4, gOut_Output)
NRD_PASS_END
