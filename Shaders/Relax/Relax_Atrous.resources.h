// RELAX: one edge-stopping a-trous iteration (5x5 B3-spline taps gAtrousStep pixels apart). The first
// iteration of a frame reads its taps from shared memory (RELAX_ATROUS_SMEM, step 1).
#if RELAX_SPECULAR && RELAX_ATROUS_SMEM
NRD_PASS_BEGIN(Relax_Specular_AtrousSmem, 8, 8)
#elif RELAX_SPECULAR
NRD_PASS_BEGIN(Relax_Specular_Atrous, 8, 8)
#elif RELAX_ATROUS_SMEM
NRD_PASS_BEGIN(Relax_Diffuse_AtrousSmem, 8, 8)
#else
NRD_PASS_BEGIN(Relax_Diffuse_Atrous, 8, 8)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    RELAX_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Tiles)
NRD_INPUT(3, gIn_RadianceVariance)               // .rgb radiance, .w luminance variance (transient or output).
NRD_INPUT(4, gIn_HitDist)                        // .w hit distance (slow history), read by the last iteration.
NRD_OUTPUT(5, gOut)                              // Next iteration's input (output or transient), or the result (last).
NRD_PASS_END
