// REFERENCE: running mean of IN_RADIANCE.
NRD_PASS_BEGIN(Reference_Accumulate, 16, 16)
NRD_CONSTANTS_BEGIN
    NRD_CONSTANT(uvec2, gSize)
    NRD_CONSTANT(float, gWeight) // Weight of the new frame: 1 / accumulated frames (1 on reset).
    NRD_CONSTANT(uint, gPad)
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Radiance)
NRD_INOUT(1, gHistory, rgba32f)
NRD_OUTPUT(2, gOut_Radiance)
NRD_PASS_END
