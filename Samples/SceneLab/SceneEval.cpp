// SceneEval.cpp - keyframe evaluation, per-frame scene state and the camera matrices.
#include "Scene.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace nrdlab
{

namespace
{

// Written as a + (b - a) t, so that t = 0 and t = 1 give the keys exactly.
glm::vec3 Lerp(const glm::vec3& a, const glm::vec3& b, float t)
{
    return a + (b - a) * t;
}

float Lerp(float a, float b, float t)
{
    return a + (b - a) * t;
}

template <class T>
T EvaluateTrack(const Track<T>& track, float frame)
{
    const auto& k = track.keys;
    if (k.empty())
        return track.value;
    if (frame <= float(k.front().frame))
        return k.front().value;
    if (frame >= float(k.back().frame))
        return k.back().value;
    size_t i = 1;
    while (float(k[i].frame) < frame)
        i++;
    float t = (frame - float(k[i - 1].frame)) / float(k[i].frame - k[i - 1].frame);
    return Lerp(k[i - 1].value, k[i].value, t);
}

// 'v' normalized, or 'fallback' where it has no direction.
glm::vec3 NormalizeOr(const glm::vec3& v, const glm::vec3& fallback)
{
    const float len = glm::length(v);
    return len > 1e-12f ? v / len : fallback;
}

// World-from-local rotation R = Rz * Ry * Rx (X applied first), angles in degrees.
glm::mat3 EulerToMatrix(const glm::vec3& deg)
{
    const glm::vec3 r = glm::radians(deg);
    const float cx = std::cos(r.x), sx = std::sin(r.x);
    const float cy = std::cos(r.y), sy = std::sin(r.y);
    const float cz = std::cos(r.z), sz = std::sin(r.z);
    // Column by column (GLM matrices are column-major).
    const glm::mat3 rx(1.0f, 0.0f, 0.0f, 0.0f, cx, sx, 0.0f, -sx, cx);
    const glm::mat3 ry(cy, 0.0f, -sy, 0.0f, 1.0f, 0.0f, sy, 0.0f, cy);
    const glm::mat3 rz(cz, sz, 0.0f, -sz, cz, 0.0f, 0.0f, 0.0f, 1.0f);
    return rz * ry * rx;
}

} // namespace

float Evaluate(const Track<float>& track, float frame)
{
    return EvaluateTrack(track, frame);
}

glm::vec3 Evaluate(const Track<glm::vec3>& track, float frame)
{
    return EvaluateTrack(track, frame);
}

bool Evaluate(const SwitchTrack& track, float frame)
{
    bool v = track.value;
    for (const auto& k : track.keys)
    {
        if (float(k.frame) <= frame)
            v = k.value;
    }
    return v;
}

SceneState EvaluateScene(const Scene& scene, uint32_t frame)
{
    const float f = float(frame);
    SceneState s;
    s.camera.position = Evaluate(scene.camera.position, f);
    s.camera.target = Evaluate(scene.camera.target, f);
    s.camera.up = Evaluate(scene.camera.up, f);
    s.camera.fovDeg = Evaluate(scene.camera.fovDeg, f);
    s.camera.nearZ = scene.camera.nearZ;

    s.objects.resize(scene.objects.size());
    for (size_t i = 0; i < scene.objects.size(); i++)
    {
        s.objects[i].position = Evaluate(scene.objects[i].position, f);
        s.objects[i].rotation = EulerToMatrix(Evaluate(scene.objects[i].rotation, f));
    }

    s.lights.resize(scene.lights.size());
    for (size_t i = 0; i < scene.lights.size(); i++)
    {
        const Light& l = scene.lights[i];
        LightState& ls = s.lights[i];
        ls.type = l.type;
        ls.enabled = Evaluate(l.enabled, f);
        ls.intensity = Evaluate(l.intensity, f);
        if (!ls.enabled)
            ls.intensity = {};
        if (l.type == LightType::SUN)
        {
            ls.direction = NormalizeOr(Evaluate(l.direction, f), glm::vec3(0.0f, 1.0f, 0.0f));
            ls.tanAngularRadius = std::tan(glm::radians(l.angularRadiusDeg));
            ls.cosAngularRadius = std::cos(glm::radians(l.angularRadiusDeg));
        }
        else
        {
            ls.position = Evaluate(l.position, f);
            ls.radius = l.type == LightType::SPHERE ? l.radius : 0.0f;
        }
    }
    return s;
}

void ComputeCameraMatrices(const CameraState& camera, uint32_t width, uint32_t height, float worldToView[16],
                           float viewToClip[16])
{
    const glm::vec3 f = NormalizeOr(camera.target - camera.position, glm::vec3(0.0f, 0.0f, -1.0f));
    glm::vec3 up = NormalizeOr(camera.up, glm::vec3(0.0f, 1.0f, 0.0f));
    if (std::fabs(glm::dot(f, up)) > 0.9999f) // Looking along 'up': any perpendicular will do.
        up = std::fabs(f.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    const glm::vec3 r = NormalizeOr(glm::cross(f, up), glm::vec3(1.0f, 0.0f, 0.0f));
    const glm::vec3 d = glm::cross(f, r); // Down: view space is x right, y down, z forward.

    // Rows r, d, f and the translation that puts the camera at the origin.
    const glm::vec3& p = camera.position;
    const glm::mat4 view = glm::transpose(glm::mat4(glm::vec4(r, -glm::dot(r, p)), glm::vec4(d, -glm::dot(d, p)),
                                                    glm::vec4(f, -glm::dot(f, p)), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)));
    std::memcpy(worldToView, glm::value_ptr(view), sizeof(float) * 16);

    const float sy = 1.0f / std::tan(glm::radians(0.5f * camera.fovDeg));
    const float sx = sy * float(height) / float(std::max(width, 1u));
    glm::mat4 proj(0.0f);
    proj[0][0] = sx;
    proj[1][1] = sy;
    proj[3][2] = camera.nearZ; // clip.z = near -> ndc.z = near / viewZ (reversed, infinite)
    proj[2][3] = 1.0f;         // clip.w = viewZ
    std::memcpy(viewToClip, glm::value_ptr(proj), sizeof(float) * 16);
}

FrameCamera ComputeFrameCamera(const Scene& scene, uint32_t frame, uint32_t width, uint32_t height)
{
    FrameCamera c;
    SceneState cur = EvaluateScene(scene, frame);
    SceneState prev = EvaluateScene(scene, frame > 0 ? frame - 1 : 0);
    ComputeCameraMatrices(cur.camera, width, height, c.worldToView, c.viewToClip);
    ComputeCameraMatrices(prev.camera, width, height, c.worldToViewPrev, c.viewToClipPrev);
    c.position[0] = cur.camera.position.x;
    c.position[1] = cur.camera.position.y;
    c.position[2] = cur.camera.position.z;
    c.positionPrev[0] = prev.camera.position.x;
    c.positionPrev[1] = prev.camera.position.y;
    c.positionPrev[2] = prev.camera.position.z;
    c.fovDeg = cur.camera.fovDeg;
    c.nearZ = cur.camera.nearZ;
    c.width = width;
    c.height = height;
    return c;
}

bool ProjectToPixel(const float worldToView[16], const float viewToClip[16], uint32_t width, uint32_t height,
                    const float p[3], float& outPixelX, float& outPixelY, float& outViewZ)
{
    const glm::vec4 c = glm::make_mat4(viewToClip) * (glm::make_mat4(worldToView) * glm::vec4(glm::make_vec3(p), 1.0f));
    outViewZ = c.w;
    if (c.w <= 0.0f)
        return false;
    outPixelX = (c.x / c.w * 0.5f + 0.5f) * float(width);
    outPixelY = (c.y / c.w * 0.5f + 0.5f) * float(height);
    return true;
}

} // namespace nrdlab
