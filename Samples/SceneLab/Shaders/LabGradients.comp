// LabGradients.comp - sparse temporal gradients for the confidence method, as document 003's
// gradient pass ("Temporal Gradients in RTXDI"), one invocation per 3x3 stratum:
//   1. Selection: among the stratum's pixels on this frame and on the previous frame, those with
//      valid history (the same surface is seen on the other frame too) are candidates; the one with
//      the highest luminance (diffuse + specular direct light of that frame's light sample) is
//      chosen, so the brighter frame's light sample is the reference.
//   2. Shading on the other frame: the chosen surface is moved to the other frame's scene state
//      and shaded there with the other frame's lights and BVH and the SAME light sample (the lab's
//      light sample is its random-number sequence: the pixel's and frame's sequence is replayed).
//      The view vector is the reference sample's on both sides, so camera motion alone does not
//      count as a lighting change (document 003: not needed with NRD).
// Output per stratum: |diffuse luminance difference|, max diffuse luminance, |specular luminance
// difference|, max specular luminance; all 0 where no pixel of the stratum has valid history.
// The lab keeps no history: the previous frame's samples are traced again here, exactly as
// LabPrimary traced them a frame earlier.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "LabScene.glsl"

layout(local_size_x = LAB_GROUP_X, local_size_y = LAB_GROUP_Y, local_size_z = 1) in;

layout(set = 0, binding = LAB_BINDING_GRADIENTS, rgba32f) uniform writeonly image2D gOut_Gradients;

// A hit of frame 'fromSlot' moved to the scene state of frame 'toSlot' (object transforms).
Hit MoveHit(Hit h, uint fromSlot, uint toSlot)
{
    Hit m = h;
    uint o = uint(h.object);
    if (gObjects[o].info.z == 0u)
    {
        m.pos = ToWorldPoint(o, toSlot, h.localPos);
        m.N = normalize(ToWorldVector(o, toSlot, ToLocalVector(o, fromSlot, h.N)));
    }
    return m;
}

// Valid history: the surface of 'h' (frame 'fromSlot'), moved to frame 'toSlot', is what the
// camera of 'toSlot' sees at its projection: same object, on the same plane, similar orientation.
bool HasHistory(Hit h, uint fromSlot, uint toSlot)
{
    Hit moved = MoveHit(h, fromSlot, toSlot);
    vec2 uv;
    if (!ProjectUv(vec4(moved.pos, 1.0), toSlot, uv))
        return false;
    ivec2 q = ivec2(floor(uv * vec2(c.gSize.xy)));
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(c.gSize.xy))))
        return false;
    vec3 origin, dir;
    PrimaryRay(uvec2(q), toSlot, origin, dir);
    Hit other = TraceClosest(origin, dir, LAB_NO_HIT, toSlot);
    float viewZ = max(abs(ViewZ(moved.pos, toSlot)), 1e-3);
    return other.object == h.object && abs(dot(other.N, other.pos - moved.pos)) <= 0.01 * viewZ &&
           dot(other.N, moved.N) > 0.8;
}

// Luminance of the direct light of surface 's' on frame 'slot' (diffuse, specular; demodulated
// as the noisy signals) from the light sample of (pixel, frame): the light points the lab's noisy
// diffuse / specular sample of that pixel and frame used (DiffuseSample and SpecularSample draw
// them first). Like RTXDI's gradients, only the light sample is compared: the bounce is left out.
vec2 ShadeLuminance(Surface s, vec3 V, uint slot, uvec2 pixel, uint frame, uint seed)
{
    uint rng = InitRng(pixel, frame, 0u, seed, LAB_STREAM_DIFFUSE);
    float diffuse = Luminance(DirectDiffuse(s, slot, rng));
    rng = InitRng(pixel, frame, 0u, seed, LAB_STREAM_SPECULAR);
    float specular = Luminance(DirectSpecular(s, V, slot, rng));
    return vec2(diffuse, specular);
}

void main()
{
    uvec2 stratum = gl_GlobalInvocationID.xy;
    uvec2 strataNum = (c.gSize.xy + 2u) / 3u;
    if (any(greaterThanEqual(stratum, strataNum)))
        return;
    ivec2 ip = ivec2(stratum);
    uint frame = c.gSize.z;
    uint seed = c.gSize.w;
    if (c.gOptions.y == 0u)
    {
        imageStore(gOut_Gradients, ip, vec4(0.0)); // First frame: no previous sample.
        return;
    }
    uint prevFrame = frame - 1u;

    // 1. Selection over the stratum's pixels on both frames (strata at the right / bottom edge
    //    may be cut). Slot 0 is this frame, slot 1 the previous one.
    uvec2 base = stratum * 3u;
    uvec2 extent = min(uvec2(3u), c.gSize.xy - base);
    float bestLuminance = -1.0;
    Hit best;
    best.object = -1;
    uint bestSlot = 0u;
    uvec2 bestPixel = base;
    vec3 bestV = vec3(0.0);
    vec2 bestValue = vec2(0.0);
    for (uint slot = 0u; slot < 2u; slot++)
    {
        for (uint j = 0u; j < extent.y; j++)
        {
            for (uint i = 0u; i < extent.x; i++)
            {
                uvec2 pixel = base + uvec2(i, j);
                vec3 origin, dir;
                PrimaryRay(pixel, slot, origin, dir);
                Hit h = TraceClosest(origin, dir, LAB_NO_HIT, slot);
                if (h.object < 0)
                    continue;
                vec2 value = ShadeLuminance(GetSurface(h), -dir, slot, pixel, slot == 0u ? frame : prevFrame, seed);
                float luminance = value.x + value.y;
                if (luminance <= bestLuminance || !HasHistory(h, slot, 1u - slot))
                    continue;
                bestLuminance = luminance;
                best = h;
                bestSlot = slot;
                bestPixel = pixel;
                bestV = -dir;
                bestValue = value;
            }
        }
    }
    if (best.object < 0)
    {
        imageStore(gOut_Gradients, ip, vec4(0.0));
        return;
    }

    // 2. The chosen surface on the other frame, with the other frame's lights and the same light
    //    sample (random numbers of the chosen pixel and frame) and view vector.
    uint otherSlot = 1u - bestSlot;
    Surface moved = GetSurface(MoveHit(best, bestSlot, otherSlot));
    vec2 otherValue = ShadeLuminance(moved, bestV, otherSlot, bestPixel, bestSlot == 0u ? frame : prevFrame, seed);
    vec2 difference = abs(bestValue - otherValue);
    vec2 maximum = max(bestValue, otherValue);
    imageStore(gOut_Gradients, ip, vec4(difference.x, maximum.x, difference.y, maximum.y));
}
