// LabPrimary.comp - one frame of noisy inputs, one variant per signal (LAB_SIGNAL):
//   0:                      the G-buffer (primary ray through the pixel centre, no jitter);
//   LAB_SIGNAL_SHADOW:      SIGMA shadowData + visibility, and the 8x4 tile hit mask;
//   LAB_SIGNAL_TRANSLUCENCY: SIGMA multi-light translucency over all lights;
//   LAB_SIGNAL_DIFFUSE / LAB_SIGNAL_SPECULAR: 1 sample of radiance + hit distance.
// Every variant traces the same primary ray, so they all see the same surfaces. Inputs are packed
// with the app-facing helpers of Shaders/Include/NRD.glsl, exactly as an engine would.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "LabScene.glsl"

#ifndef LAB_SIGNAL
#  define LAB_SIGNAL 0
#endif

layout(local_size_x = LAB_GROUP_X, local_size_y = LAB_GROUP_Y, local_size_z = 1) in;

#if LAB_SIGNAL == 0
layout(set = 0, binding = LAB_BINDING_GBUFFER0, rgba32f) uniform writeonly image2D gOut_GBuffer0;
layout(set = 0, binding = LAB_BINDING_NORMAL_ROUGHNESS, rgba32f) uniform writeonly image2D gOut_NormalRoughness;
layout(set = 0, binding = LAB_BINDING_MV3D, rgba32f) uniform writeonly image2D gOut_Mv3d;
layout(set = 0, binding = LAB_BINDING_ALBEDO, rgba32f) uniform writeonly image2D gOut_Albedo;
layout(set = 0, binding = LAB_BINDING_SPEC_ALBEDO, rgba32f) uniform writeonly image2D gOut_SpecAlbedo;
#elif LAB_SIGNAL == LAB_SIGNAL_SHADOW
layout(set = 0, binding = LAB_BINDING_SHADOW, rgba32f) uniform writeonly image2D gOut_Shadow;
layout(set = 0, binding = LAB_BINDING_HIT_MASK, r32ui) uniform writeonly uimage2D gOut_HitMask;
// The two 8x4 shadow tiles of this 8x8 group.
shared uint sTileMask[2];
#elif LAB_SIGNAL == LAB_SIGNAL_TRANSLUCENCY
layout(set = 0, binding = LAB_BINDING_TRANSLUCENCY, rgba32f) uniform writeonly image2D gOut_Translucency;
layout(set = 0, binding = LAB_BINDING_TRANSLUCENCY_DATA, rgba32f) uniform writeonly image2D gOut_TranslucencyData;
#elif LAB_SIGNAL == LAB_SIGNAL_DIFFUSE
layout(set = 0, binding = LAB_BINDING_DIFFUSE, rgba32f) uniform writeonly image2D gOut_Diffuse;
#elif LAB_SIGNAL == LAB_SIGNAL_SPECULAR
layout(set = 0, binding = LAB_BINDING_SPECULAR, rgba32f) uniform writeonly image2D gOut_Specular;
#endif

void main()
{
    uvec2 pixel = gl_GlobalInvocationID.xy;
    uint frame = c.gSize.z;
    uint seed = c.gSize.w;
    bool inside = all(lessThan(pixel, c.gSize.xy));

#if LAB_SIGNAL == LAB_SIGNAL_SHADOW
    if (gl_LocalInvocationIndex < 2u)
        sTileMask[gl_LocalInvocationIndex] = 0u;
    barrier();
    // Pixels outside the image and sky pixels count as lit in the hit mask.
    bool lit = true;
#endif

    if (inside)
    {
        ivec2 ip = ivec2(pixel);
        vec3 origin, dir;
        PrimaryRay(pixel, 0u, origin, dir);
        Hit h = TraceClosest(origin, dir, LAB_NO_HIT, 0u);

        if (h.object < 0)
        {
#if LAB_SIGNAL == 0
            // Sky: far viewZ, camera-only motion (a direction reprojects with the rotation alone).
            vec2 uvPrev, uvCur;
            bool inFront = ProjectUv(vec4(dir, 0.0), 0u, uvCur);
            vec2 mv = ProjectUv(vec4(dir, 0.0), 1u, uvPrev) && inFront ? uvPrev - uvCur : vec2(0.0);
            imageStore(gOut_GBuffer0, ip, vec4(LAB_SKY_VIEWZ, mv, -1.0));
            imageStore(gOut_NormalRoughness, ip, NRD_FrontEnd_PackNormalAndRoughness(-dir, 1.0));
            imageStore(gOut_Mv3d, ip, vec4(0.0));
            imageStore(gOut_Albedo, ip, vec4(0.0));
            imageStore(gOut_SpecAlbedo, ip, vec4(0.0));
#elif LAB_SIGNAL == LAB_SIGNAL_SHADOW
            imageStore(gOut_Shadow, ip, vec4(SIGMA_INF_SHADOW, 1.0, NRD_FP16_MAX));
#elif LAB_SIGNAL == LAB_SIGNAL_TRANSLUCENCY
            imageStore(gOut_Translucency, ip, vec4(1.0));
            imageStore(gOut_TranslucencyData, ip, vec4(SIGMA_INF_SHADOW, 0.0, 0.0));
#elif LAB_SIGNAL == LAB_SIGNAL_DIFFUSE
            imageStore(gOut_Diffuse, ip, vec4(0.0, 0.0, 0.0, 1.0));
#elif LAB_SIGNAL == LAB_SIGNAL_SPECULAR
            imageStore(gOut_Specular, ip, vec4(0.0, 0.0, 0.0, 1.0));
#endif
        }
        else
        {
            Surface s = GetSurface(h);
            vec3 V = -dir;
            float viewZ = ViewZ(h.pos, 0u);
#if LAB_SIGNAL == 0
            // Motion: where this surface point was on the previous frame. Both ends are projections
            // (not the pixel centre), so a still camera on a still surface gives exactly 0.
            uint o = uint(h.object);
            vec3 posPrev = gObjects[o].info.z != 0u ? h.pos : ToWorldPoint(o, 1u, h.localPos);
            vec2 uvPrev, uvCur;
            bool inFront = ProjectUv(vec4(h.pos, 1.0), 0u, uvCur);
            vec2 mv = ProjectUv(vec4(posPrev, 1.0), 1u, uvPrev) && inFront ? uvPrev - uvCur : vec2(0.0);

            imageStore(gOut_GBuffer0, ip, vec4(viewZ, mv, float(o)));
            imageStore(gOut_NormalRoughness, ip, NRD_FrontEnd_PackNormalAndRoughness(s.N, s.linearRoughness));
            imageStore(gOut_Mv3d, ip, vec4(posPrev - h.pos, 0.0));
            imageStore(gOut_Albedo, ip, vec4(s.diffuseAlbedo, 0.0));
            float NoV = max(dot(s.N, V), 1e-4);
            imageStore(gOut_SpecAlbedo, ip, vec4(SpecularAlbedo(s.F0, NoV, s.linearRoughness), 0.0));
#elif LAB_SIGNAL == LAB_SIGNAL_SHADOW
            uint rng = InitRng(pixel, frame, 0u, seed, LAB_STREAM_SHADOW);
            LightSample ls = SampleLight(c.gCounts.z, 0u, h.pos, s.N, Next2(rng));
            float distanceToOccluder = OccluderDistance(ls, h.pos, s.N, 0u);
            vec2 shadowData = SIGMA_FrontEnd_PackShadow(viewZ, distanceToOccluder, ls.tanAngularRadius);
            float visibility = distanceToOccluder >= NRD_FP16_MAX ? 1.0 : 0.0;
            lit = visibility > 0.5;
            imageStore(gOut_Shadow, ip, vec4(shadowData, visibility, distanceToOccluder));
#elif LAB_SIGNAL == LAB_SIGNAL_TRANSLUCENCY
            // Quick start guide, multiple lights: one shadow ray per light, weight 1.
            uint rng = InitRng(pixel, frame, 0u, seed, LAB_STREAM_TRANSLUCENCY);
            mat2x3 multiLight = SIGMA_FrontEnd_MultiLightStart();
            vec3 Lsum = vec3(0.0);
            for (uint li = 0u; li < c.gCounts.y; li++)
            {
                LightSample ls = SampleLight(li, 0u, h.pos, s.N, Next2(rng));
                float distanceToOccluder = OccluderDistance(ls, h.pos, s.N, 0u);
                SIGMA_FrontEnd_MultiLightUpdate(ls.E, distanceToOccluder, ls.tanAngularRadius, 1.0, multiLight);
                Lsum += ls.E;
            }
            vec4 shadowTranslucency;
            vec2 shadowData = SIGMA_FrontEnd_MultiLightEnd(viewZ, multiLight, Lsum, shadowTranslucency);
            imageStore(gOut_Translucency, ip, shadowTranslucency);
            imageStore(gOut_TranslucencyData, ip, vec4(shadowData, 0.0, 0.0));
#elif LAB_SIGNAL == LAB_SIGNAL_DIFFUSE
            uint rng = InitRng(pixel, frame, 0u, seed, LAB_STREAM_DIFFUSE);
            // Packed as an application packs IN_DIFF_RADIANCE_HITDIST (diffuse: roughness 1).
            vec4 v = DiffuseSample(s, 0u, rng);
            float normHitDist = REBLUR_FrontEnd_GetNormHitDist(v.w, viewZ, c.gHitDistParams, 1.0);
            imageStore(gOut_Diffuse, ip, REBLUR_FrontEnd_PackRadianceAndNormHitDist(v.rgb, normHitDist, true));
#elif LAB_SIGNAL == LAB_SIGNAL_SPECULAR
            uint rng = InitRng(pixel, frame, 0u, seed, LAB_STREAM_SPECULAR);
            vec4 v = SpecularSample(s, V, 0u, rng);
            float normHitDist = REBLUR_FrontEnd_GetNormHitDist(v.w, viewZ, c.gHitDistParams, s.linearRoughness);
            imageStore(gOut_Specular, ip, REBLUR_FrontEnd_PackRadianceAndNormHitDist(v.rgb, normHitDist, true));
#endif
        }
    }

#if LAB_SIGNAL == LAB_SIGNAL_SHADOW
    // Hit mask: bit (x % 8) + 8 * (y % 4) of tile (x / 8, y / 4) is set where the light is visible.
    uvec2 local = gl_LocalInvocationID.xy;
    if (lit)
        atomicOr(sTileMask[local.y / 4u], 1u << (local.x + 8u * (local.y % 4u)));
    barrier();
    if (local.x == 0u && (local.y % 4u) == 0u)
    {
        uvec2 tile = uvec2(gl_WorkGroupID.x, gl_WorkGroupID.y * 2u + local.y / 4u);
        if (tile.y < (c.gSize.y + 3u) / 4u)
            imageStore(gOut_HitMask, ivec2(tile), uvec4(sTileMask[local.y / 4u]));
    }
#endif
}
