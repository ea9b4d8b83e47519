// Shadows that a moving light (or, below, a moving occluder) carries across still surfaces, shared
// by the shadow denoisers (SIGMA, TILED_SHADOW). Their surfaces' motion vectors are zero there, so a
// shadow's history is the shadow where it was; the application says where its light is every frame,
// and Source/ShadowLightMotion.h turns the light's move into the constants below:
//   gShadowMotionPerPenumbra  an infinite light: penumbra radii its turn moved every shadow;
//   gLightPositionView        a sphere light: .xyz position in view space, .w 1 / its radius;
//   gLightMotionView          .xyz its move since the previous frame (view space), .w 1 if it moved;
//   gOccluderLightView        an infinite light: .xyz direction towards it (view space), .w 1 / tan
//                             of its angular radius (0: unknown).
// A pixel's shadow moved (penumbra radii) * (its penumbra radius in pixels) pixels; a hard shadow
// keeps NRD_SHADOW_MOTION_HISTORY_PIXELS of that motion at most in its history, and outputs its
// sample where not a whole frame fits (the history of a shadow that moved is the shadow elsewhere).
// Include after the pass's constant block.
#ifndef NRD_SHADOW_MOTION_GLSL
#define NRD_SHADOW_MOTION_GLSL

// Pixels of a hard shadow's motion its history may hold: 1/20 pixel. A time-of-day sun (0.004 degrees
// a frame under a 0.27-degree radius) moves a 0.3-pixel penumbra 0.0045 pixel a frame: 11 frames.
#define NRD_SHADOW_MOTION_HISTORY_PIXELS 0.05

// The light moved since the previous frame (uniform over the dispatch).
bool _NRD_ShadowMotion_IsLightMoving()
{
    return gShadowMotionPerPenumbra > 0.0 || gLightMotionView.w != 0.0;
}

// Penumbra radii the light's move carried the shadow at view-space position Xv.
float _NRD_ShadowMotion_PerPenumbra(vec3 Xv)
{
    if (gLightMotionView.w == 0.0)
        return gShadowMotionPerPenumbra;
    // A sphere light: its move across the direction to the point, over its radius (the angle it turned
    // by and tan of its angular radius both scale with 1 / the distance).
    vec3 toLight = gLightPositionView.xyz - Xv;
    float distance = length(toLight);
    vec3 across = distance > 0.0 ? cross(gLightMotionView.xyz, toLight / distance) : vec3(0.0);
    return min(length(across) * gLightPositionView.w, NRD_FP16_MAX);
}

// Pixels the shadow moved, from the largest penumbra radius (pixels) around the pixel; a negative
// radius (no shadowed sample around) while the light moves reads as moved beyond reach (a shadow
// that was there has gone; a lit sample is exact).
float _NRD_ShadowMotion_Pixels(float widestPenumbraPixels, float perPenumbra)
{
    if (widestPenumbraPixels >= 0.0)
        return widestPenumbraPixels * perPenumbra;
    return perPenumbra > 0.0 ? NRD_FP16_MAX : 0.0;
}

// Frames of history a hard shadow that moved 'motionPixels' may keep; below 1, none (output the
// sample).
float _NRD_ShadowMotion_KeptFrames(float motionPixels)
{
    return motionPixels > 0.0 ? NRD_SHADOW_MOTION_HISTORY_PIXELS / motionPixels : NRD_FP16_MAX;
}

// Shadows that a moving occluder carries across surfaces (an animated object's shadow on a still
// floor): the surfaces' motion vectors say nothing of them either. The occluder of a shadowed sample
// lies toward the light at the distance its penumbra gives (penumbra radius = distance * tan of the
// light's angular radius, gOccluderLightView.w = 1 / tan; a sphere light's tan is its radius over the
// distance to it). Where the occluder is in view (the surface seen at its screen position is not
// behind it by more than NRD_SHADOW_MOTION_OCCLUDER_DEPTH of its depth: the occluder itself, or
// something in front of it, most often the same object seen from another side), that surface's
// motion vector says how far it moved on screen beyond the camera's motion, relative to the
// receiver's own: about as far as the shadow moved over the receiver. An occluder out of view, or
// hidden behind another surface, reads as still. The pass binds gIn_ViewZ and gIn_Mv (IN_VIEWZ,
// IN_MV).
#define NRD_SHADOW_MOTION_OCCLUDER_DEPTH 0.05
// The denoisers use an occluder's motion where the shadowed samples around a pixel all have penumbra
// radii under this many pixels: there the 1-spp sample is nearly exact, and a history that the
// occluder's move displaced only lags (mesh_thin: the spider's legs, a pixel or two wide, turn over a
// still floor). Wider penumbrae keep their history: their samples are noise that it averages (at 0.6
// pixel SIGMA's relMSE ratio on moving_occluder at 64x64 fell from 2.09 to 1.42, at 0.75
// TILED_SHADOW's from 2.30 to 1.30: its flying sphere, seen in front of another sphere's shadowed
// side, reads as that shadow's occluder).
#define NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA 0.5

// Screen motion (uv, beyond the camera's) of a surface point at pixel 'p' with viewZ 'z'.
vec2 _NRD_ShadowMotion_OwnMotion(ivec2 p, float z)
{
    vec2 uv = _NRD_PixelUv(p);
    vec3 X = _NRD_WorldPosition(uv, z), Xprev;
    vec2 uvPrev = _NRD_PreviousUv(uv, X, texelFetch(sampler2D(gIn_Mv, gNearestClamp), p, 0).xyz, Xprev);
    vec4 clip = gWorldToClipPrev * vec4(X, 1.0);
    if (!(clip.w > NRD_EPS) || !all(greaterThan(uvPrev, vec2(-1.0))))
        return vec2(0.0);
    return uvPrev - ((clip.xy / clip.w) * 0.5 + 0.5);
}

// Pixels the occluder of the shadowed sample at pixel 'p' (viewZ 'z', penumbra radius
// 'penumbraPixels' in pixels, negative if unknown) moved relative to it since the previous frame;
// 0 where the light or the occluder is unknown or out of view.
float _NRD_ShadowMotion_OccluderPixels(ivec2 p, float z, float penumbraPixels)
{
    bool isSphere = gLightPositionView.w > 0.0;
    if (!(penumbraPixels >= 0.0) || (!isSphere && gOccluderLightView.w == 0.0))
        return 0.0;
    vec3 Xv = _NRD_ViewPosition(_NRD_PixelUv(p), z);
    float penumbra = penumbraPixels * z / gProjectY; // World units at the receiver.
    vec3 toLight;
    if (isSphere)
    {
        // tan = radius / distance to the light: the occluder lies penumbra / radius of the way there.
        toLight = (gLightPositionView.xyz - Xv) * min(penumbra * gLightPositionView.w, 1.0);
    }
    else
        toLight = gOccluderLightView.xyz * (penumbra * gOccluderLightView.w);
    vec3 Ov = Xv + toLight;
    vec4 clip = gViewToClip * vec4(Ov, 1.0);
    if (!(clip.w > NRD_EPS))
        return 0.0;
    ivec2 q = ivec2(floor(((clip.xy / clip.w) * 0.5 + 0.5) * vec2(gResourceSize)));
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(uvec2(q), gResourceSize)))
        return 0.0;
    float zq = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
    float zO = Ov.z * gViewZSign;
    if (_NRD_IsSky(zq))
        return 0.0;
    if (zq - zO > NRD_SHADOW_MOTION_OCCLUDER_DEPTH * zO)
        return 0.0;
    vec2 pixels = abs(_NRD_ShadowMotion_OwnMotion(q, zq) - _NRD_ShadowMotion_OwnMotion(p, z)) * vec2(gResourceSize);
    return min(max(pixels.x, pixels.y), NRD_FP16_MAX);
}

#endif
