// RELAX: luminance variance for the a-trous luminance stopper, spatial while the history is short.
NRD_PASS_BEGIN(Relax_SpatialVariance, 8, 8)
NRD_CONSTANTS_BEGIN
    NRD_COMMON_CONSTANTS
    RELAX_CONSTANTS
NRD_CONSTANTS_END
NRD_INPUT(0, gIn_NormalRoughness)
NRD_INPUT(1, gIn_ViewZ)
NRD_INPUT(2, gIn_Tiles)
NRD_INPUT(3, gIn_Slow)                           // Permanent histories after the history fix.
NRD_INPUT(4, gIn_Fast)
NRD_INPUT(5, gIn_Length)
NRD_OUTPUT(6, gOut_RadianceVariance)             // .rgb radiance, .w luminance variance of the mean.
NRD_PASS_END
