// LabRayQuery.comp - traces a list of object-space rays through one mesh's BVH with the lab's own
// traversal (LabScene.glsl IntersectMesh, the function every lab pass calls), so that tests can
// compare its hits with a CPU brute-force intersection ray by ray. Not part of any rendered frame
// (and not part of the frame cache's shader key).
#version 450
#extension GL_GOOGLE_include_directive : require

#define LAB_TRACE_TRIANGLE
#include "LabScene.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(push_constant) uniform LabRayQueryBlock
{
    LabRayQuery query;
};

layout(set = 0, binding = LAB_BINDING_RAYS, std430) readonly buffer LabRaysBlock
{
    LabRay gRays[];
};
layout(set = 0, binding = LAB_BINDING_RAY_HITS, std430) writeonly buffer LabRayHitsBlock
{
    LabRayHit gRayHits[];
};

void main()
{
    uint r = gl_GlobalInvocationID.x;
    if (r >= query.gQuery.x)
        return;
    vec3 n;
    float t = IntersectMesh(query.gQuery.y, gRays[r].originTMax.xyz, gRays[r].direction.xyz, gRays[r].originTMax.w,
                            gRays[r].direction.w != 0.0, n);
    bool hit = t < LAB_NO_HIT && gTracedTriangle >= 0;
    gRayHits[r].triangle = uvec4(hit ? uint(gTracedTriangle) : 0xFFFFFFFFu, 0u, 0u, 0u);
    gRayHits[r].tUv = hit ? vec4(t, gTracedUv, 0.0) : vec4(0.0);
}
