// RELAX: temporal accumulation of radiance, hit distance and the second luminance moment into a slow
// and a fast history (one pipeline per signal, with or without the confidence input).
#if RELAX_SPECULAR && RELAX_CONFIDENCE
NRD_PASS_BEGIN(Relax_Specular_TemporalAccumulationConfidence, 8, 8)
#elif RELAX_SPECULAR
NRD_PASS_BEGIN(Relax_Specular_TemporalAccumulation, 8, 8)
#elif RELAX_CONFIDENCE
NRD_PASS_BEGIN(Relax_Diffuse_TemporalAccumulationConfidence, 8, 8)
#else
NRD_PASS_BEGIN(Relax_Diffuse_TemporalAccumulation, 8, 8)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    RELAX_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_MV)
NRD_INPUT(3, gIn_Signal)                         // IN_*_RADIANCE_HITDIST.
NRD_INPUT(4, gIn_Tiles)
NRD_INPUT(5, gPrev_ViewZ)                        // R16F, 0 = sky (or beyond FP16).
NRD_INPUT(6, gPrev_Slow)                         // .rgb radiance, .w hit distance.
NRD_INPUT(7, gPrev_Fast)                         // .rgb fast radiance, .w sqrt(second luminance moment).
NRD_INPUT(8, gPrev_Length)                       // Length and debt, change record (Relax_Common.glsl).
NRD_OUTPUT(9, gOut_Slow)                         // Transient.
NRD_OUTPUT(10, gOut_Fast)                        // The application's output texture (scratch).
NRD_OUTPUT(11, gOut_Length)                      // Transient.
#if RELAX_CONFIDENCE
NRD_INPUT(12, gIn_Confidence)                    // IN_*_CONFIDENCE, .x in [0, 1].
#endif
NRD_PASS_END
