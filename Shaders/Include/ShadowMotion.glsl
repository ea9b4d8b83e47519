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
// motion vector says how it moved beyond the camera's motion, relative to the receiver. An occluder
// out of view, or hidden behind another surface, reads as still. The pass binds gIn_ViewZ and gIn_Mv
// (IN_VIEWZ, IN_MV).
#define NRD_SHADOW_MOTION_OCCLUDER_DEPTH 0.05
// Where the light meets the receiver's plane at a cosine under this (a terminator), the shadow's
// motion over it is taken as the occluder's screen motion (the projection along the light diverges).
#define NRD_SHADOW_MOTION_GRAZING 0.05
// The denoisers output a hard shadow's sample (no history) where the shadowed samples around a pixel
// all have penumbra radii under this many pixels: there the 1-spp sample is nearly exact, and a
// history that the occluder's move displaced lags at least by the error of the motion (mesh_thin: the
// spider's legs, a pixel or two wide, turn over a still floor). Wider penumbrae keep a history taken
// where the shadow was (TILED_SHADOW) or where the surface was (SIGMA): their samples are noise that
// it averages (at 0.6 pixel SIGMA's relMSE ratio on moving_occluder at 64x64 fell from 2.09 to 1.42).
#define NRD_SHADOW_MOTION_OCCLUDER_EXACT_PENUMBRA 0.5
// Under a moving occluder's penumbrae of up to this many pixels around (a soft shadow next to hard
// ones: a spider's body and legs), a pixel whose own 3x3 holds only hard ones, or whose 3x3 samples
// all agree, is a hard shadow's: the history where the wider shadow was is not its own (mesh_thin at
// 128x128: FLIP 1.014x -> 1.006x the input's for TILED_SHADOW, 1.014x -> 1.004x for SIGMA).
#define NRD_SHADOW_MOTION_OCCLUDER_NARROW_PENUMBRA 1.0

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

// Motion (view space, previous minus current position) of the surface point at pixel 'p' with viewZ
// 'z' beyond the camera's: its world-space motion vector, or with 2D motion vectors (their depth
// change unknown) the move parallel to the plane of view-space normal 'Nv' that gives their screen
// motion beyond the camera's.
vec3 _NRD_ShadowMotion_OwnMotionView(ivec2 p, float z, vec3 Nv)
{
    if (gMotionVectorScale.w != 0.0)
    {
        vec3 mv = _NRD_Sanitize(texelFetch(sampler2D(gIn_Mv, gNearestClamp), p, 0).xyz, 0.0);
        return (mv * gMotionVectorScale.xyz) * mat3(gViewToWorld); // World -> view (transposed rotation).
    }
    vec2 uv = _NRD_PixelUv(p);
    vec3 X = _NRD_ViewPosition(uv, z);
    vec3 ray = _NRD_ViewPosition(uv + _NRD_ShadowMotion_OwnMotion(p, z), 1.0);
    float rayN = dot(ray, Nv);
    if (!(abs(rayN) > NRD_EPS))
        return vec3(0.0);
    return ray * (dot(X, Nv) / rayN) - X;
}

// The occluder of the shadowed sample at pixel 'p' (viewZ 'z', penumbra radius 'penumbraPixels' in
// pixels, negative if unknown): the pixel 'q' and viewZ 'zq' of the surface seen where it projects,
// and the direction 'L' towards the light (view space). False where the light or the occluder is
// unknown or out of view.
bool _NRD_ShadowMotion_FindOccluder(ivec2 p, float z, float penumbraPixels, out ivec2 q, out float zq, out vec3 L)
{
    q = p;
    zq = z;
    L = vec3(0.0);
    bool isSphere = gLightPositionView.w > 0.0;
    if (!(penumbraPixels >= 0.0) || (!isSphere && gOccluderLightView.w == 0.0))
        return false;
    vec3 Xv = _NRD_ViewPosition(_NRD_PixelUv(p), z);
    float penumbra = penumbraPixels * z / gProjectY; // World units at the receiver.
    vec3 toLight;
    if (isSphere)
    {
        // tan = radius / distance to the light: the occluder lies penumbra / radius of the way there.
        toLight = (gLightPositionView.xyz - Xv) * min(penumbra * gLightPositionView.w, 1.0);
        L = normalize(gLightPositionView.xyz - Xv);
    }
    else
    {
        toLight = gOccluderLightView.xyz * (penumbra * gOccluderLightView.w);
        L = gOccluderLightView.xyz;
    }
    vec3 Ov = Xv + toLight;
    vec4 clip = gViewToClip * vec4(Ov, 1.0);
    if (!(clip.w > NRD_EPS))
        return false;
    q = ivec2(floor(((clip.xy / clip.w) * 0.5 + 0.5) * vec2(gResourceSize)));
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(uvec2(q), gResourceSize)))
        return false;
    zq = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
    float zO = Ov.z * gViewZSign;
    // Where the occluder's point projects onto the sample's own pixel (an occluder within a pixel of
    // the surface: a leg's tip on the floor), that pixel shows the receiver, not the occluder.
    bool isOwnPixel = all(equal(q, p));
    if (!isOwnPixel && !_NRD_IsSky(zq) && zq - zO <= NRD_SHADOW_MOTION_OCCLUDER_DEPTH * zO)
        return true;
    // Around the sample's own pixel, the three neighbours toward the light on screen (an occluder lies
    // between the shadow and the light): the surface that moves most relative to the sample (its
    // neighbours on the receiver move as it does: a delta of 0, as the receiver itself would give).
    if (isOwnPixel)
    {
        vec2 ownMotion = _NRD_ShadowMotion_OwnMotion(p, z);
        vec4 c = gViewToClip * vec4(Xv + L * (0.05 * z), 1.0);
        vec2 toward = c.w > NRD_EPS ? ((c.xy / c.w) * 0.5 + 0.5) * vec2(gResourceSize) - (vec2(p) + 0.5) : vec2(0.0);
        // The nearest of the 8 directions (45-degree steps, counter-clockwise from +x) and its two
        // neighbours; all 8 where the light lies along the view.
        bool isAlongView = !(dot(toward, toward) > 1e-6);
        int principal = isAlongView ? 0 : int(round(atan(toward.y, toward.x) * (4.0 / 3.14159265))) + 8;
        float fastest = -1.0;
        for (int k = isAlongView ? 0 : -1; k <= (isAlongView ? 7 : 1); k++)
        {
            int d = (principal + k) & 7;
            ivec2 t = p + ivec2(d == 0 || d == 1 || d == 7 ? 1 : (d >= 3 && d <= 5 ? -1 : 0),
                                d >= 1 && d <= 3 ? 1 : (d >= 5 ? -1 : 0));
            if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(uvec2(t), gResourceSize)))
                continue;
            float zt = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), t, 0).x;
            if (_NRD_IsSky(zt) || abs(zt - zO) > NRD_SHADOW_MOTION_OCCLUDER_DEPTH * zO)
                continue;
            vec2 m = (_NRD_ShadowMotion_OwnMotion(t, zt) - ownMotion) * vec2(gResourceSize);
            float speed = max(abs(m.x), abs(m.y));
            if (speed > fastest)
            {
                fastest = speed;
                q = t;
                zq = zt;
            }
        }
        return !_NRD_IsSky(zq); // Else the receiver's own pixel: no motion relative to it.
    }
    // An occluder thinner than a pixel (or placed a pixel off by the penumbra's rounding) may not
    // cover the pixel its point projects to: the 3x3 around it, the surface nearest in depth.
    ivec2 centre = q;
    float best = NRD_SHADOW_MOTION_OCCLUDER_DEPTH * zO;
    bool isFound = false;
    for (int i = 0; i < 9; i++)
    {
        ivec2 t = centre + ivec2(i % 3 - 1, i / 3 - 1);
        if (i == 4 || any(lessThan(t, ivec2(0))) || any(greaterThanEqual(uvec2(t), gResourceSize)))
            continue;
        float zt = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), t, 0).x;
        if (!_NRD_IsSky(zt) && abs(zt - zO) <= best)
        {
            best = abs(zt - zO);
            q = t;
            zq = zt;
            isFound = true;
        }
    }
    return isFound;
}

// Pixels the occluder of the shadowed sample at pixel 'p' moved on screen relative to it since the
// previous frame (the larger axis); 0 where it is unknown or out of view.
float _NRD_ShadowMotion_OccluderPixels(ivec2 p, float z, float penumbraPixels)
{
    ivec2 q;
    float zq;
    vec3 L;
    if (!_NRD_ShadowMotion_FindOccluder(p, z, penumbraPixels, q, zq, L))
        return 0.0;
    vec2 pixels = abs(_NRD_ShadowMotion_OwnMotion(q, zq) - _NRD_ShadowMotion_OwnMotion(p, z)) * vec2(gResourceSize);
    return min(max(pixels.x, pixels.y), NRD_FP16_MAX);
}

// Where, on screen, the shadow of the shadowed sample at pixel 'p' (viewZ 'z', view-space normal 'Nv',
// penumbra radius 'penumbraPixels' in pixels) lay in the previous frame, relative to the sample's
// surface: 'delta' pixels from it (previous minus current). The occluder's move relative to the
// surface, projected along the light onto the surface's tangent plane (exact for a translating
// occluder over a plane; the occluder's own screen motion there would overstate a shadow on a
// farther surface by the ratio of their depths). False where the occluder is unknown or out of view.
bool _NRD_ShadowMotion_OccluderDelta(ivec2 p, float z, vec3 Nv, float penumbraPixels, out vec2 delta)
{
    delta = vec2(0.0);
    ivec2 q;
    float zq;
    vec3 L;
    if (!_NRD_ShadowMotion_FindOccluder(p, z, penumbraPixels, q, zq, L))
        return false;
    float LN = dot(L, Nv);
    vec2 d;
    if (abs(LN) >= NRD_SHADOW_MOTION_GRAZING)
    {
        vec3 Xv = _NRD_ViewPosition(_NRD_PixelUv(p), z);
        vec3 dO = _NRD_ShadowMotion_OwnMotionView(q, zq, Nv) - _NRD_ShadowMotion_OwnMotionView(p, z, Nv);
        vec4 c0 = gViewToClip * vec4(Xv, 1.0);
        vec4 c1 = gViewToClip * vec4(Xv + dO - L * (dot(dO, Nv) / LN), 1.0);
        if (!(c1.w > NRD_EPS))
            return false;
        d = (c1.xy / c1.w - c0.xy / c0.w) * 0.5 * vec2(gResourceSize);
    }
    else
        d = (_NRD_ShadowMotion_OwnMotion(q, zq) - _NRD_ShadowMotion_OwnMotion(p, z)) * vec2(gResourceSize);
    delta = clamp(vec2(_NRD_Sanitize(d.x, 0.0), _NRD_Sanitize(d.y, 0.0)), -NRD_FP16_MAX, NRD_FP16_MAX);
    return true;
}

// The fraction of the light's disk above the receiver's tangent plane (view-space normal 'Nv',
// position 'Xv'): 1 where the surface faces the light by more than its angular radius, 0 where it
// faces away by more, in between on the light's terminator, where the surface itself hides part of
// the light (a sphere's or a cylinder's self-shadow edge; the self-occlusion's hit lies next to the
// sample and its penumbra estimate is 0, yet the visibility is fractional). -1 where the light's size
// is unknown.
float _NRD_ShadowMotion_HorizonVisibility(vec3 Xv, vec3 Nv)
{
    vec3 L;
    float sine;
    if (gLightPositionView.w > 0.0)
    {
        vec3 toLight = gLightPositionView.xyz - Xv;
        float distance = length(toLight);
        if (!(distance > NRD_EPS))
            return -1.0;
        L = toLight / distance;
        sine = min(1.0 / (gLightPositionView.w * distance), 1.0);
    }
    else if (gOccluderLightView.w > 0.0)
    {
        L = gOccluderLightView.xyz;
        sine = inversesqrt(1.0 + gOccluderLightView.w * gOccluderLightView.w);
    }
    else
        return -1.0;
    return _NRD_DiskFractionBeyondChord(dot(L, Nv) / sine);
}

#endif
