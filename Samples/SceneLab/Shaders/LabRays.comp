// LabRays.comp - the specular sample of LabPrimary.comp (LAB_SIGNAL_SPECULAR), traced for a ray list
// only, as an application's ray pass does for a variable-rate reflection denoiser: an indirect
// dispatch of LAB_GROUP_X * LAB_GROUP_Y rays per group over the list; each ray's result goes to its
// pixel and to the quad neighbours its entry names (nrd::BufferContent::RAY_LIST). A ray of pixel p
// gives exactly the value LabPrimary writes at p (same random stream).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "LabScene.glsl"

layout(local_size_x = LAB_GROUP_X, local_size_y = LAB_GROUP_Y, local_size_z = 1) in;

layout(set = 0, binding = LAB_BINDING_SPECULAR, rgba32f) uniform writeonly image2D gOut_Specular;
layout(set = 0, binding = LAB_BINDING_RAY_LIST, std430) readonly buffer LabRayList { uint gRayList[]; };
layout(set = 0, binding = LAB_BINDING_RAY_ARGS, std430) readonly buffer LabRayArgs { uint gRayArgs[]; };

void Store(uvec2 pixel, vec4 value)
{
    if (all(lessThan(pixel, c.gSize.xy)))
        imageStore(gOut_Specular, ivec2(pixel), value);
}

void main()
{
    uint rayIndex = gl_WorkGroupID.x * uint(LAB_GROUP_X * LAB_GROUP_Y) + gl_LocalInvocationIndex;
    if (rayIndex >= gRayArgs[3])
        return;
    uint entry = gRayList[rayIndex];
    uvec2 pixel = uvec2(entry & 0x3FFFu, (entry >> 14u) & 0x3FFFu);
    if (any(greaterThanEqual(pixel, c.gSize.xy)))
        return;
    uint frame = c.gSize.z;
    uint seed = c.gSize.w;

    vec3 origin, dir;
    PrimaryRay(pixel, 0u, origin, dir);
    Hit h = TraceClosest(origin, dir, LAB_NO_HIT, 0u);
    vec4 value = vec4(0.0, 0.0, 0.0, 1.0);
    if (h.object >= 0)
    {
        Surface s = GetSurface(h);
        float viewZ = ViewZ(h.pos, 0u);
        uint rng = InitRng(pixel, frame, 0u, seed, LAB_STREAM_SPECULAR);
        vec4 v = SpecularSample(s, -dir, 0u, rng);
        float normHitDist = REBLUR_FrontEnd_GetNormHitDist(v.w, viewZ, c.gHitDistParams, s.linearRoughness);
        value = REBLUR_FrontEnd_PackRadianceAndNormHitDist(v.rgb, normHitDist, true);
    }
    Store(pixel, value);
    if ((entry & (1u << 28u)) != 0u)
        Store(pixel ^ uvec2(1u, 0u), value);
    if ((entry & (1u << 29u)) != 0u)
        Store(pixel ^ uvec2(0u, 1u), value);
    if ((entry & (1u << 30u)) != 0u)
        Store(pixel ^ uvec2(1u, 1u), value);
}
