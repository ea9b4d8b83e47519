// LabGradients.comp - sparse temporal gradients for the confidence method (document 003, after
// A-SVGF, Schied et al. 2018): one pixel per 3x3 stratum, chosen at random each frame; its surface
// is reprojected to the previous frame, the previous frame's sample there (pixel q, its random
// numbers) is shaded again on THIS frame's scene with the same random numbers, and the two results
// are compared. Equal lighting gives equal values, so only lighting changes (lights moving or
// switching, shadows moving) produce gradients; camera motion alone does not for diffuse.
// Backward projection with the previous frame re-traced here (the lab keeps no history).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "LabScene.glsl"

layout(local_size_x = LAB_GROUP_X, local_size_y = LAB_GROUP_Y, local_size_z = 1) in;

layout(set = 0, binding = LAB_BINDING_GRADIENTS, rgba32f) uniform writeonly image2D gOut_Gradients;

// A hit of the previous frame moved to the scene state of this frame.
Hit MoveToThisFrame(Hit hp)
{
    Hit h = hp;
    uint o = uint(hp.object);
    if (gObjects[o].info.z == 0u)
    {
        h.pos = ToWorldPoint(o, 0u, hp.localPos);
        h.N = normalize(ToWorldVector(o, 0u, ToLocalVector(o, 1u, hp.N)));
    }
    return h;
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

    // The stratum's pixel for this frame (strata at the right / bottom edge may be cut).
    uvec2 base = stratum * 3u;
    uvec2 extent = min(uvec2(3u), c.gSize.xy - base);
    uint rng = InitRng(stratum, frame, 0u, seed, LAB_STREAM_STRATUM);
    uvec2 pixel = base + uvec2(Pcg(rng) % extent.x, Pcg(rng ^ 0x68E31DA4u) % extent.y);

    vec3 origin, dir;
    PrimaryRay(pixel, 0u, origin, dir);
    Hit hc = TraceClosest(origin, dir, LAB_NO_HIT, 0u);
    if (hc.object < 0)
    {
        imageStore(gOut_Gradients, ip, vec4(0.0));
        return;
    }

    // Where this surface point was on the previous frame, and which pixel saw it there.
    uint o = uint(hc.object);
    bool isStatic = gObjects[o].info.z != 0u;
    vec3 posPrev = isStatic ? hc.pos : ToWorldPoint(o, 1u, hc.localPos);
    vec3 NPrev = isStatic ? hc.N : normalize(ToWorldVector(o, 1u, ToLocalVector(o, 0u, hc.N)));
    vec2 uvPrev;
    bool valid = ProjectUv(vec4(posPrev, 1.0), 1u, uvPrev);
    ivec2 q = ivec2(floor(uvPrev * vec2(c.gSize.xy)));
    valid = valid && all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(c.gSize.xy)));

    Hit hp;
    hp.object = -1;
    if (valid)
    {
        PrimaryRay(uvec2(q), 1u, origin, dir);
        hp = TraceClosest(origin, dir, LAB_NO_HIT, 1u);
        // Same surface: same object, on the same plane (grazing-safe), similar orientation.
        float viewZPrev = max(abs(ViewZ(posPrev, 1u)), 1e-3);
        valid = hp.object == hc.object && abs(dot(hp.N, hp.pos - posPrev)) <= 0.01 * viewZPrev &&
                dot(hp.N, NPrev) > 0.8;
    }
    if (!valid)
    {
        imageStore(gOut_Gradients, ip, vec4(0.0));
        return;
    }

    // The previous frame's sample at q: its surface and random numbers, on both frames.
    uint prevFrame = frame - 1u;
    Surface sPrev = GetSurface(hp);
    Surface sCur = GetSurface(MoveToThisFrame(hp));
    vec3 VPrev = -dir; // exactly what LabPrimary used on the previous frame
    // A still camera looking at a still surface sees it from the same direction: reuse the exact
    // vector, so an unchanged frame gives exactly zero gradients.
    bool sameView = isStatic && all(equal(c.gCameraPos.xyz, c.gCameraPosPrev.xyz));
    vec3 VCur = sameView ? VPrev : normalize(c.gCameraPos.xyz - sCur.pos);

    uint rngA = InitRng(uvec2(q), prevFrame, 0u, seed, LAB_STREAM_DIFFUSE);
    uint rngB = rngA;
    float diffPrev = Luminance(DiffuseSample(sPrev, 1u, rngA).rgb);
    float diffCur = Luminance(DiffuseSample(sCur, 0u, rngB).rgb);

    rngA = InitRng(uvec2(q), prevFrame, 0u, seed, LAB_STREAM_SPECULAR);
    rngB = rngA;
    float specPrev = Luminance(SpecularSample(sPrev, VPrev, 1u, rngA).rgb);
    float specCur = Luminance(SpecularSample(sCur, VCur, 0u, rngB).rgb);

    imageStore(gOut_Gradients, ip, vec4(abs(diffCur - diffPrev), max(diffCur, diffPrev), abs(specCur - specPrev),
                                        max(specCur, specPrev)));
}
