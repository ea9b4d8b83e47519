// CONFIDENCE local limit (not in document 003; Shaders/Confidence/README.md, "The local limit"):
// the mean of the unfiltered gradients over the (2 r + 1) x (2 r + 1) strata around each stratum
// (texels outside the image repeat the edge's), differences and luminances separately. The
// temporal pass interpolates it bilinearly as the filtered gradients and takes, per signal, the
// smaller of the two normalized gradients. Separable in shared memory: the group's texels and an
// apron of r load once, row sums, then column sums.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Confidence_Local.resources.h"
#include "CommonFrame.glsl"
#include "Confidence_Common.glsl"

#define GROUP 8
#define TILE (GROUP + 2 * CONFIDENCE_MAX_LOCAL_RADIUS)

shared vec4 s_Texels[TILE][TILE];
shared vec4 s_Rows[TILE][GROUP];

void main()
{
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 maxTexel = ivec2(gGradientSize) - 1;
    const int r = clamp(gRadius, 0, CONFIDENCE_MAX_LOCAL_RADIUS);
    const int size = GROUP + 2 * r;
    ivec2 tileOrigin = ivec2(gl_WorkGroupID.xy) * GROUP - r;

    for (int i = local.y * GROUP + local.x; i < size * size; i += GROUP * GROUP)
    {
        ivec2 t = ivec2(i % size, i / size);
        s_Texels[t.y][t.x] = _Confidence_LoadGradient(gIn_Gradients, clamp(tileOrigin + t, ivec2(0), maxTexel));
    }
    barrier();

    // Row sums over the 2 r + 1 columns of each output column, for every row of the tile.
    for (int row = local.y; row < size; row += GROUP)
    {
        vec4 sum = vec4(0.0);
        for (int i = 0; i <= 2 * r; i++)
            sum += s_Texels[row][local.x + i];
        s_Rows[row][local.x] = sum;
    }
    barrier();

    if (any(greaterThanEqual(uvec2(texel), gGradientSize)))
        return;
    vec4 sum = vec4(0.0);
    for (int j = 0; j <= 2 * r; j++)
        sum += s_Rows[local.y + j][local.x];
    // The mean, not the sum: fp16 storage (values up to NRD_FP16_MAX each).
    float n = float(2 * r + 1);
    imageStore(gOut_Local, texel, _NRD_ClampToHalf(sum / (n * n)));
}
