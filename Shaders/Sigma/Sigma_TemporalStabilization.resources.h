// SIGMA: reprojects the previous result, clamps it to the neighbourhood of the blurred current frame
// and blends; writes the output and this frame's history (ping-pong by frame parity).
#include "Sigma_Constants.h"

#if SIGMA_TRANSLUCENCY
NRD_PASS_BEGIN(Sigma_ShadowTranslucency_TemporalStabilization, 16, 16)
#else
NRD_PASS_BEGIN(Sigma_Shadow_TemporalStabilization, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    SIGMA_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Mv)
NRD_INPUT(3, gIn_Shadow)
NRD_INPUT(4, gIn_Penumbra)
NRD_INPUT(5, gIn_TileModes)
NRD_INPUT(6, gPrev_Shadow)
NRD_INPUT_UINT(7, gPrev_ViewZHistoryLength)
NRD_OUTPUT(8, gOut_ShadowTranslucency)
#if SIGMA_TRANSLUCENCY
NRD_INOUT(9, gHistory_Shadow, rgba16f)
#else
NRD_INOUT(9, gHistory_Shadow, r16f)
#endif
NRD_INOUT_UINT(10, gHistory_ViewZHistoryLength, r32ui)
NRD_PASS_END
