// How far a moving light carries the shadows it casts, for the shadow denoisers (SIGMA, TILED_SHADOW).
//
// A shadow cast from distance d by a light of angular radius a has a penumbra of radius d tan(a); a
// turn of the light by t moves it by d tan(t). Their ratio does not depend on d: an infinite light that
// turned by t moved every shadow tan(t) / tan(a) penumbra radii. A sphere light of radius r that moved
// by D, seen from a point at distance L in direction 'dir', turned by |D x dir| / L with tan(a) = r / L
// there: |D x dir| / r penumbra radii. The shaders turn that into pixels with each pixel's penumbra
// estimate (Shaders/Include/ShadowMotion.glsl).
#pragma once

#include "InstanceImpl.h"
#include "PassDecl.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace nrd
{

// A world-space direction in view space, normalized (column-major world -> view, as
// CommonSettings::worldToViewMatrix); .w 1, or all 0 where the direction is zero or not finite.
inline glsl::vec4 DirectionInViewSpace(const float* worldToView, const float* direction)
{
    float v[3];
    for (int row = 0; row < 3; row++)
        v[row] = worldToView[0 * 4 + row] * direction[0] + worldToView[1 * 4 + row] * direction[1] +
                 worldToView[2 * 4 + row] * direction[2];
    float length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(length > 1e-12f) || !std::isfinite(length))
        return {0.0f, 0.0f, 0.0f, 0.0f};
    return {v[0] / length, v[1] / length, v[2] / length, 1.0f};
}

// The light as the application describes it every frame: an infinite light (direction, tan of its
// angular radius) or a sphere light (world-space position, radius; wins where both are set). Zeros:
// unknown.
struct ShadowLightDesc
{
    const float* direction = nullptr; // 3 floats, need not be normalized
    float tanOfAngularRadius = 0.0f;
    const float* position = nullptr; // 3 floats
    float radius = 0.0f;
};

// The shaders' constants (NRD_SHADOW_MOTION_CONSTANTS in ShadowMotion.glsl).
struct ShadowLightMotionConstants
{
    glsl::vec4 lightPositionView = {}; // .xyz sphere light in view space, .w 1 / radius
    glsl::vec4 lightMotionView = {};   // .xyz its move since the previous frame in view space, .w 1 if it moved
    float motionPerPenumbra = 0.0f;    // infinite light: penumbra radii its turn moved every shadow
    glsl::vec4 occluderLightView = {}; // infinite light: .xyz direction towards it in view space, .w distance
                                       // to the occluder per unit of penumbra radius (1 / tan of its
                                       // angular radius); zeros: unknown (a sphere light uses the above)
};

// The light's fields of a shadow denoiser's settings: tan of an infinite light's angular radius in
// [0, 1], a sphere light's position finite (within 1e30) and radius in [0, 1e6].
inline Result ValidateShadowLight(const char* settingsName, float tanOfAngularRadius, const float* position, float radius,
                                  const Logger& log)
{
    if (!(tanOfAngularRadius >= 0.0f && tanOfAngularRadius <= 1.0f))
    {
        log.Error("SetMethodSettings: %s::tanOfLightAngularRadius %g is outside [0, 1]", settingsName, double(tanOfAngularRadius));
        return Result::INVALID_ARGUMENT;
    }
    for (int i = 0; i < 3; i++)
    {
        if (!(std::abs(position[i]) <= 1e30f))
        {
            log.Error("SetMethodSettings: %s::lightPosition[%d] is not finite (or beyond 1e30)", settingsName, i);
            return Result::INVALID_ARGUMENT;
        }
    }
    if (!(radius >= 0.0f && radius <= 1e6f))
    {
        log.Error("SetMethodSettings: %s::lightRadius %g is outside [0, 1e6]", settingsName, double(radius));
        return Result::INVALID_ARGUMENT;
    }
    return Result::SUCCESS;
}

class ShadowLightMotion
{
public:
    // Once per frame; a second call with the same frameIndex returns the first one's constants (the
    // previous frame's light is kept, not this one's). 'reset': the history restarts this frame.
    ShadowLightMotionConstants Update(const ShadowLightDesc& light, uint32_t frameIndex, bool reset, const float* worldToView)
    {
        if (!(m_HasFrame && frameIndex == m_FrameIndex))
        {
            Advance(light, reset);
            m_HasFrame = true;
            m_FrameIndex = frameIndex;
        }
        ShadowLightMotionConstants c = {};
        c.motionPerPenumbra = m_MotionPerPenumbra;
        if (m_HasDirection && light.tanOfAngularRadius > 0.0f)
        {
            c.occluderLightView = DirectionInViewSpace(worldToView, m_Direction);
            if (c.occluderLightView.w != 0.0f)
                c.occluderLightView.w = 1.0f / light.tanOfAngularRadius;
        }
        if (light.radius > 0.0f && light.position)
        {
            // Column-major world -> view, as CommonSettings::worldToViewMatrix.
            const float* m = worldToView;
            const float* p = light.position;
            float v[3], d[3];
            for (int row = 0; row < 3; row++)
            {
                v[row] = m[0 * 4 + row] * p[0] + m[1 * 4 + row] * p[1] + m[2 * 4 + row] * p[2] + m[3 * 4 + row];
                d[row] = m[0 * 4 + row] * m_Move[0] + m[1 * 4 + row] * m_Move[1] + m[2 * 4 + row] * m_Move[2];
            }
            bool isMoving = m_Move[0] != 0.0f || m_Move[1] != 0.0f || m_Move[2] != 0.0f;
            c.lightPositionView = {v[0], v[1], v[2], 1.0f / light.radius};
            c.lightMotionView = {d[0], d[1], d[2], isMoving ? 1.0f : 0.0f};
            c.motionPerPenumbra = 0.0f;
        }
        return c;
    }

private:
    void Advance(const ShadowLightDesc& light, bool reset)
    {
        const float* l = light.direction;
        float length = l ? std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]) : 0.0f;
        bool isKnown = length > 1e-12f && std::isfinite(length);
        m_MotionPerPenumbra = 0.0f;
        if (isKnown && m_HasDirection && !reset && light.tanOfAngularRadius > 0.0f)
        {
            float cosine = (l[0] * m_Direction[0] + l[1] * m_Direction[1] + l[2] * m_Direction[2]) / length;
            cosine = std::min(std::max(cosine, -1.0f), 1.0f);
            float sine = std::sqrt(std::max(1.0f - cosine * cosine, 0.0f));
            // A turn of 45 degrees or more leaves nothing of any shadow where it was.
            float tangent = cosine > 0.7071f ? sine / cosine : 1.0f;
            m_MotionPerPenumbra = std::min(tangent / light.tanOfAngularRadius, 65504.0f);
        }
        m_HasDirection = isKnown;
        for (int i = 0; i < 3; i++)
            m_Direction[i] = isKnown ? l[i] / length : 0.0f;

        bool isLocal = light.radius > 0.0f && light.position;
        for (int i = 0; i < 3; i++)
            m_Move[i] = isLocal && m_HasPosition && !reset ? light.position[i] - m_Position[i] : 0.0f;
        m_HasPosition = isLocal;
        for (int i = 0; i < 3; i++)
            m_Position[i] = isLocal ? light.position[i] : 0.0f;
    }

    float m_Direction[3] = {}; // normalized, the previous frame's
    bool m_HasDirection = false;
    float m_Position[3] = {};
    bool m_HasPosition = false;
    float m_Move[3] = {}; // world space, this frame's
    float m_MotionPerPenumbra = 0.0f;
    bool m_HasFrame = false;
    uint32_t m_FrameIndex = 0;
};

// The light fields of a shadow denoiser's settings (lightDirection, tanOfLightAngularRadius,
// lightPosition, lightRadius: SigmaSettings, TiledShadowSettings) into its pass constants
// (gShadowMotionPerPenumbra, gLightPositionView, gLightMotionView, gOccluderLightView).
template <class Settings, class Constants>
void SetShadowLightMotion(ShadowLightMotion& motion, const Settings& s, const FrameData& frame, Constants& c)
{
    ShadowLightDesc light;
    light.direction = s.lightDirection;
    light.tanOfAngularRadius = s.tanOfLightAngularRadius;
    light.position = s.lightPosition;
    light.radius = s.lightRadius;
    ShadowLightMotionConstants m = motion.Update(light, frame.common.frameIndex, frame.resetHistory, frame.common.worldToViewMatrix);
    c.gShadowMotionPerPenumbra = m.motionPerPenumbra;
    c.gLightPositionView = m.lightPositionView;
    c.gLightMotionView = m.lightMotionView;
    c.gOccluderLightView = m.occluderLightView;
}

} // namespace nrd
