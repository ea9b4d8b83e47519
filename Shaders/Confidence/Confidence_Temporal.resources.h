// CONFIDENCE: filtered gradients -> confidence at full resolution, blended with last frame's
// confidence (short temporal filter); writes the outputs and the history.
NRD_PASS_BEGIN(Confidence_Temporal, 16, 16)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    NRD_CONSTANT(uvec2, gGradientSize)
    NRD_CONSTANT(float, gGradientThreshold)
    NRD_CONSTANT(float, gGradientSensitivity)
    NRD_CONSTANT(float, gFallHistoryWeight)
    NRD_CONSTANT(float, gRiseHistoryWeight)
    NRD_CONSTANT(float, gSpecularGradientSensitivity)
    NRD_CONSTANT(uint, gLocalRadius)
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Gradients)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Mv)
NRD_INPUT(3, gIn_History)
NRD_INPUT(4, gIn_Local) // Confidence_Local (gLocalRadius > 0)
NRD_INOUT(5, gOut_History, rg16f)
NRD_OUTPUT(6, gOut_DiffConfidence)
NRD_OUTPUT(7, gOut_SpecConfidence)
NRD_PASS_END
