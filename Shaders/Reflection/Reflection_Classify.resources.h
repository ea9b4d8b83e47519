// REFLECTION classification (document 002, "tile classification"): one 8x8 group per tile decides
// per pixel whether it needs the denoiser, traces a ray or receives a quad neighbour's copy, and
// compacts the rays into the ray list with a local prefix sum; tiles that need the denoiser go to
// the tile list. Also stores this frame's depth, normal and roughness for the next frame.
NRD_PASS_BEGIN(Reflection_Classify, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    NRD_CONSTANT(float, gMirrorRoughness)
    NRD_CONSTANT(float, gRoughnessThreshold)
    NRD_CONSTANT(float, gTemporalVarianceThreshold)
    NRD_CONSTANT(uint, gRaysPerQuad)
    NRD_CONSTANT(uint, gFlags)
    NRD_CONSTANT(uint, gClassifyPad0)
    NRD_CONSTANT(uint, gClassifyPad1)
    NRD_CONSTANT(uint, gClassifyPad2)
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_TemporalVariance)
NRD_INOUT(3, gOut_ViewZHistory, r32f)
NRD_INOUT(4, gOut_NormalRoughnessHistory, rgba16f)
NRD_RW_BUFFER(5, gRayList, uint)
NRD_RW_BUFFER(6, gTileList, uint)
NRD_RW_BUFFER(7, gCounters, uint)
NRD_PASS_END
