// Lighting change record, shared by the radiance denoisers (REBLUR, RELAX): a small per-pixel count
// of how persistently this pixel's lighting has kept changing, so that a history test that fires
// in recent frames again and again (a shadow or a stripe of light that moves over a still surface
// without motion vectors: venetian_blinds) can keep the history short there, while the same test
// firing once at random (a rare sample, noise) leaves it alone.
//
// Semantics: each frame the record rises by _NRD_LIGHTING_CHANGE_RISE where the caller's test found
// a change in this pixel's lighting (beyond its noise), and falls by 1 where it did not; it is
// capped at _NRD_LIGHTING_CHANGE_MAX. The lighting "moves" at a pixel while the record is at least
// _NRD_LIGHTING_CHANGE_MOVING: with the defaults (rise 3, moving at 4, max 7) two changes found at
// most three frames apart start it, one alone does not, changes found every fourth frame or more
// often keep it going, and from the cap it lasts 3 frames after the last change found. A history
// that is reset (disocclusion) starts from record 0.
//
// Storage: the record needs _NRD_LIGHTING_CHANGE_BITS (3) bits. _NRD_LightingChange_Pack puts it in
// the top bits of an UNORM8 channel beside a value in [0, 1] quantized to the remaining bits (5:
// steps of 1 / 31), so that a texture that already holds such a value (a confidence debt) carries
// the record without new memory. The record is not a quantity to interpolate: read it from one
// texel (the nearest valid tap of a reprojection footprint), and interpolate the value after
// unpacking each tap.
#ifndef NRD_LIGHTING_CHANGE_GLSL
#define NRD_LIGHTING_CHANGE_GLSL

#include "Common.glsl"

#define _NRD_LIGHTING_CHANGE_BITS 3u
#define _NRD_LIGHTING_CHANGE_MAX 7u
#ifndef _NRD_LIGHTING_CHANGE_RISE
#define _NRD_LIGHTING_CHANGE_RISE 3u
#endif
#ifndef _NRD_LIGHTING_CHANGE_MOVING
#define _NRD_LIGHTING_CHANGE_MOVING 4u
#endif

// The record after this frame's test ('isChanged': the test found a change of this pixel's lighting).
uint _NRD_LightingChange_Update(uint record, bool isChanged)
{
    return isChanged ? min(record + _NRD_LIGHTING_CHANGE_RISE, _NRD_LIGHTING_CHANGE_MAX) : (record > 0u ? record - 1u : 0u);
}

// Whether the lighting at this pixel keeps changing (the record is high enough).
bool _NRD_LightingChange_IsMoving(uint record)
{
    return record >= _NRD_LIGHTING_CHANGE_MOVING;
}

// UNORM8 channel holding the record (top bits) and 'value' in [0, 1] (the other bits, rounded;
// clamped to [0, 1], non-finite: 0).
float _NRD_LightingChange_Pack(uint record, float value)
{
    const uint valueLevels = (1u << (8u - _NRD_LIGHTING_CHANGE_BITS)) - 1u;
    uint v = uint(clamp(_NRD_Sanitize(value, 0.0), 0.0, 1.0) * float(valueLevels) + 0.5);
    uint r = min(record, _NRD_LIGHTING_CHANGE_MAX);
    return float((r << (8u - _NRD_LIGHTING_CHANGE_BITS)) | v) / 255.0;
}

// The record from such a channel (0 for a non-finite one).
uint _NRD_LightingChange_UnpackRecord(float packed)
{
    uint u = uint(clamp(_NRD_Sanitize(packed, 0.0), 0.0, 1.0) * 255.0 + 0.5);
    return u >> (8u - _NRD_LIGHTING_CHANGE_BITS);
}

// The value in [0, 1] from such a channel (0 for a non-finite one).
float _NRD_LightingChange_UnpackValue(float packed)
{
    const uint valueLevels = (1u << (8u - _NRD_LIGHTING_CHANGE_BITS)) - 1u;
    uint u = uint(clamp(_NRD_Sanitize(packed, 0.0), 0.0, 1.0) * 255.0 + 0.5);
    return float(u & valueLevels) / float(valueLevels);
}

// A residual z (a sample's departure from its history in its standard deviations, the change tests
// of REBLUR and RELAX) as the 5-bit value beside the record: steps of 0.5 in [-8, 7.5].
float _NRD_LightingChange_PackResidual(float z) { return clamp(floor(_NRD_Sanitize(z, 0.0) * 2.0 + 0.5) + 16.0, 0.0, 31.0) / 31.0; }
float _NRD_LightingChange_UnpackResidual(float value) { return (floor(value * 31.0 + 0.5) - 16.0) * 0.5; }

#endif
