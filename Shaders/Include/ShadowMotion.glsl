// Shadows that a moving light carries across still surfaces, shared by the shadow denoisers (SIGMA,
// TILED_SHADOW). Their surfaces' motion vectors are zero there, so a shadow's history is the shadow
// where it was; the application says where its light is every frame, and Source/ShadowLightMotion.h
// turns the light's move into the constants below:
//   gShadowMotionPerPenumbra  an infinite light: penumbra radii its turn moved every shadow;
//   gLightPositionView        a sphere light: .xyz position in view space, .w 1 / its radius;
//   gLightMotionView          .xyz its move since the previous frame (view space), .w 1 if it moved.
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

#endif
