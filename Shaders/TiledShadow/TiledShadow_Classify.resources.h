// TILED_SHADOW tile classification (document 000, "Denoiser shadows tile classification"): local
// neighbourhood moments from the bitmasks, disocclusion, reprojection, history clamp and blend.
// One invocation per pixel; a group is 16x16 pixels = 2x4 tiles.
#if TS_SHADOW_DATA
NRD_PASS_BEGIN(TiledShadow_ClassifyShadowData, 16, 16)
#else
NRD_PASS_BEGIN(TiledShadow_Classify, 16, 16)
#endif
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    NRD_CONSTANT(mat4, gClipToClipPrev)          // Current clip -> previous clip (double-precision product).
    NRD_CONSTANT(vec4, gMomentWeights0)          // Neighbourhood kernel w(i) = exp(-3 i^2 / (r + 1)^2), i = 0..3,
    NRD_CONSTANT(vec4, gMomentWeights1)          // i = 4..7,
    NRD_CONSTANT(vec4, gMomentWeights2)          // i = 8 (.x); 0 beyond the radius. .y: (sum of w(i), i = -8..8)^2.
    NRD_CONSTANT(vec4, gMomentSteps0)            // w(i) - w(i + 1), the weight of the popcount of the
    NRD_CONSTANT(vec4, gMomentSteps1)            // nested row window of half-width i.
    NRD_CONSTANT(vec4, gMomentSteps2)
    NRD_CONSTANT(float, gHistoryClampSigma)
    NRD_CONSTANT(float, gDisocclusionThresholdGrazing)
    NRD_CONSTANT(float, gMaxHistoryFrameNum)
    NRD_CONSTANT(uint, gFlags)                   // TS_FLAG_*.
    NRD_CONSTANT(uint, gDebugView)               // TS_DEBUG_*.
    NRD_CONSTANT(uint, gCounterSlot)             // Counter slot of this frame (0 or 1).
    NRD_CONSTANT(uint, gMethodFrame)             // Frames since creation, from 1.
    NRD_CONSTANT(float, gLocalMeanNoise)         // Standard error of the local mean per unit of sample sigma.
    NRD_CONSTANT(float, gShadowMotionPerPenumbra) // The light's move since the previous frame
    NRD_CONSTANT(vec4, gLightPositionView)       // (Shaders/Include/ShadowMotion.glsl; read by the
    NRD_CONSTANT(vec4, gLightMotionView)         // TS_SHADOW_DATA variant), and where the occluders
    NRD_CONSTANT(vec4, gOccluderLightView)       // of an infinite light's shadows lie.
    NRD_CONSTANT(vec2, gInvStateSize)            // 1 / the state texture's size (the render size; gResourceSize may be less).
NRD_CONSTANTS_END
NRD_INPUT_UINT(0, gIn_Mask)                      // Prepare's output or IN_SHADOW_BITMASK.
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Normal)
NRD_INPUT(3, gIn_Mv)
NRD_INPUT_UINT(4, gPrev_State)                   // Permanent state of the previous frame (TiledShadow_Common.glsl).
NRD_OUTPUT(5, gOut_Shadow)                       // .x blended shadow, .y variance (RG16F).
NRD_INOUT_UINT(6, gOut_Moments, r32ui)           // Temporal mean and samples, packed as in the state (history 0).
NRD_INOUT_UINT(7, gOut_TileClass, r32ui)         // One TS_TILE_* per tile.
NRD_OUTPUT(8, gOut_Debug)                        // OUT_SHADOW_TRANSLUCENCY, written for debug views only.
NRD_RW_BUFFER(9, gCounters, uint)                // TILED_SHADOW_COUNTERS_*, two slots.
#if TS_SHADOW_DATA
NRD_INPUT(10, gIn_ShadowData)                    // IN_SHADOWDATA: .y penumbra radius / viewZ (SIGMA_FrontEnd_PackShadow).
#endif
NRD_PASS_END
