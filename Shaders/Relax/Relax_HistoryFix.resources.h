// RELAX: history fix for short histories, anti-firefly, clamping of the slow history to the fast
// one's neighbourhood (anti-lag); writes the permanent histories (one pipeline per signal).
#if RELAX_SPECULAR
NRD_PASS_BEGIN(Relax_Specular_HistoryFix, 8, 8)
#else
NRD_PASS_BEGIN(Relax_Diffuse_HistoryFix, 8, 8)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    RELAX_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Tiles)
NRD_INPUT(3, gIn_Slow)                           // Temporal accumulation's outputs (the fast
                                                 // history in the application's output texture).
NRD_INPUT(4, gIn_Fast)
NRD_INPUT(5, gIn_Length)
NRD_OUTPUT(6, gOut_Slow)                         // Permanent histories.
NRD_OUTPUT(7, gOut_Fast)
NRD_OUTPUT(8, gOut_Length)
NRD_OUTPUT(9, gOut_ViewZ)                        // R16F, written with RELAX_FLAG_WRITE_VIEWZ (every pixel; 0 = sky).
NRD_PASS_END
