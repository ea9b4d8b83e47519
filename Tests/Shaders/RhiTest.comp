// Test shaders of the rhi itself (IntegrationTests.cpp): an indirect-argument writer (ARGS) and a
// fill pass that uses a storage image with a format, a read-only storage buffer, a uniform block
// and push constants.
#version 450

#ifdef ARGS
layout(local_size_x = 1, local_size_y = 1, local_size_z = 1) in;
layout(set = 0, binding = 0, std430) buffer Args { uint gArgs[]; };
layout(push_constant) uniform Push { uint gGroupsX; uint gGroupsY; };

void main()
{
    gArgs[0] = gGroupsX;
    gArgs[1] = gGroupsY;
    gArgs[2] = 1;
}
#else
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0, rgba32f) uniform image2D gOut;
layout(set = 0, binding = 1, std430) readonly buffer Values { float gValues[]; };
layout(set = 1, binding = 0, std140) uniform Constants { vec4 gScale; };
layout(push_constant) uniform Push { uint gWidth; uint gHeight; };

void main()
{
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= gWidth || p.y >= gHeight)
        return;
    imageStore(gOut, ivec2(p), vec4(p.x, p.y, gValues[p.y * gWidth + p.x], gScale.x));
}
#endif
