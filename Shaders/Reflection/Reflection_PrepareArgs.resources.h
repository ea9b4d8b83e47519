// REFLECTION indirect arguments: ray pass and denoising passes from this frame's counters, which
// are then reset for the next frame. One invocation.
NRD_PASS_BEGIN(Reflection_PrepareArgs, 1, 1)
NRD_NO_CONSTANTS
NRD_RW_BUFFER(0, gCounters, uint)
NRD_PASS_END
