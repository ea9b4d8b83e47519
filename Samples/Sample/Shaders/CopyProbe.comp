#version 450
// Bandwidth probe of the benchmark: copies gSrc into gDst, 16 bytes per invocation and iteration,
// with a grid-stride loop so that any buffer size fits the dispatch limits.
layout(local_size_x = 256) in;

layout(set = 0, binding = 0, std430) readonly buffer Src { uvec4 gSrc[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Dst { uvec4 gDst[]; };
layout(push_constant) uniform Constants { uint gCount; }; // uvec4 elements to copy.

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < gCount; i += stride)
        gDst[i] = gSrc[i];
}
