// RELAX: one edge-stopping a-trous iteration (5x5 B3-spline taps gAtrousStep pixels apart), its taps
// read from shared memory; a group holds 8x8 pixels gAtrousStep apart (dispatch
// DivideUp(size, 8 * gAtrousStep) * 8 * gAtrousStep threads per axis).
#if RELAX_SPECULAR
NRD_PASS_BEGIN(Relax_Specular_Atrous, 8, 8)
#else
NRD_PASS_BEGIN(Relax_Diffuse_Atrous, 8, 8)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    RELAX_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Tiles)                          // Read by step 1 only (its groups are the tiles).
NRD_INPUT(3, gIn_RadianceVariance)               // .rgb radiance, .w luminance variance (transient or output).
NRD_INPUT(4, gIn_HitDist)                        // .w hit distance (slow history), read by the last iteration.
NRD_OUTPUT(5, gOut)                              // Next iteration's input (output or transient), or the result (last).
NRD_PASS_END
