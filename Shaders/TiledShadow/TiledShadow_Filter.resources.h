// TILED_SHADOW edge-avoiding a-trous pass (document 000, "Denoiser shadows filter"), 3x3 taps
// TILED_SHADOW_STEP pixels apart (1, 2, 4: one pipeline each), samples cached in shared memory.
// One invocation per pixel; a group is 16x16 pixels = 2x4 tiles. Includers define TILED_SHADOW_STEP.
#if TILED_SHADOW_STEP == 1
NRD_PASS_BEGIN(TiledShadow_Filter1, 16, 16)
#elif TILED_SHADOW_STEP == 2
NRD_PASS_BEGIN(TiledShadow_Filter2, 16, 16)
#elif TILED_SHADOW_STEP == 4
NRD_PASS_BEGIN(TiledShadow_Filter4, 16, 16)
#else
#error "TILED_SHADOW_STEP must be 1, 2 or 4"
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    NRD_CONSTANT(float, gPlaneDistanceScale)     // log2(e) / planeDistanceSensitivity.
    NRD_CONSTANT(float, gNormalPower)
    NRD_CONSTANT(uint, gIsFirstPass)             // Writes the history state.
    NRD_CONSTANT(uint, gIsLastPass)              // Writes OUT_SHADOW_TRANSLUCENCY instead of gOut_Shadow.
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_Shadow)                         // .x shadow, .y variance.
NRD_INPUT_UINT(1, gIn_Moments)                   // Classification's packed moments (read by the first pass).
NRD_INPUT(2, gIn_ViewZ)
NRD_INPUT(3, gIn_Normal)
NRD_INPUT_UINT(4, gIn_TileClass)
NRD_OUTPUT(5, gOut_Shadow)                       // .x shadow, .y variance for the next pass (RG16F).
NRD_OUTPUT(6, gOut_Final)                        // OUT_SHADOW_TRANSLUCENCY.
NRD_INOUT_UINT(7, gOut_State, rg32ui)            // Permanent state, written by the first pass.
NRD_PASS_END
