// CONFIDENCE: one a-trous pass (3x3 kernel, step gStep) over the sparse gradients at 1/3
// resolution; differences and luminances are filtered independently, with edge stopping by the
// viewZ and normal of each stratum's centre pixel.
NRD_PASS_BEGIN(Confidence_Filter, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    NRD_CONSTANT(uvec2, gGradientSize) // DivideUp(gResourceSize, 3)
    NRD_CONSTANT(int, gStep)           // Tap distance in gradient texels: 1, 2, 4, ...
    NRD_CONSTANT(float, gDepthThreshold)
    NRD_CONSTANT(float, gNormalPower)
    NRD_CONSTANT(uint, gPad0)
    NRD_CONSTANT(uint, gPad1)
    NRD_CONSTANT(uint, gPad2)
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Gradients)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_NormalRoughness)
NRD_OUTPUT(3, gOut_Gradients)
NRD_PASS_END
