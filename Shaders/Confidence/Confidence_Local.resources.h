// CONFIDENCE: the local limit's box of unfiltered gradients (localGradientRadius) at 1/3
// resolution, read by the temporal pass.
NRD_PASS_BEGIN(Confidence_Local, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    NRD_CONSTANT(uvec2, gGradientSize) // DivideUp(gResourceSize, 3)
    NRD_CONSTANT(int, gRadius)         // localGradientRadius, in gradient texels
    NRD_CONSTANT(uint, gPad0)
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Gradients)
NRD_OUTPUT(1, gOut_Local)
NRD_PASS_END
