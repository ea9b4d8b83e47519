// SceneEval.cpp - keyframe evaluation, per-frame scene state and the camera matrices.
#include "Scene.h"

#include <algorithm>
#include <cmath>

namespace nrdlab
{

namespace
{

constexpr float kDegToRad = 0.017453292519943295f;

Float3 Lerp(const Float3& a, const Float3& b, float t)
{
    return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
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

float Dot(const Float3& a, const Float3& b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

Float3 Cross(const Float3& a, const Float3& b)
{
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

Float3 Normalize(const Float3& v, const Float3& fallback)
{
    float len = std::sqrt(Dot(v, v));
    return len > 1e-12f ? Float3{v.x / len, v.y / len, v.z / len} : fallback;
}

Float3 Sub(const Float3& a, const Float3& b)
{
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}

// Row-major R = Rz * Ry * Rx (X applied first).
void EulerToMatrix(const Float3& deg, float m[9])
{
    float cx = std::cos(deg.x * kDegToRad), sx = std::sin(deg.x * kDegToRad);
    float cy = std::cos(deg.y * kDegToRad), sy = std::sin(deg.y * kDegToRad);
    float cz = std::cos(deg.z * kDegToRad), sz = std::sin(deg.z * kDegToRad);
    // Rx = [1 0 0; 0 cx -sx; 0 sx cx], Ry = [cy 0 sy; 0 1 0; -sy 0 cy], Rz = [cz -sz 0; sz cz 0; 0 0 1]
    m[0] = cz * cy;
    m[1] = cz * sy * sx - sz * cx;
    m[2] = cz * sy * cx + sz * sx;
    m[3] = sz * cy;
    m[4] = sz * sy * sx + cz * cx;
    m[5] = sz * sy * cx - cz * sx;
    m[6] = -sy;
    m[7] = cy * sx;
    m[8] = cy * cx;
}

} // namespace

float Evaluate(const Track<float>& track, float frame)
{
    return EvaluateTrack(track, frame);
}

Float3 Evaluate(const Track<Float3>& track, float frame)
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
        EulerToMatrix(Evaluate(scene.objects[i].rotation, f), s.objects[i].rotation);
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
            ls.direction = Normalize(Evaluate(l.direction, f), {0, 1, 0});
            ls.tanAngularRadius = std::tan(l.angularRadiusDeg * kDegToRad);
            ls.cosAngularRadius = std::cos(l.angularRadiusDeg * kDegToRad);
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
    Float3 f = Normalize(Sub(camera.target, camera.position), {0, 0, -1});
    Float3 up = Normalize(camera.up, {0, 1, 0});
    if (std::fabs(Dot(f, up)) > 0.9999f) // Looking along 'up': any perpendicular will do.
        up = std::fabs(f.y) < 0.9f ? Float3{0, 1, 0} : Float3{0, 0, 1};
    Float3 r = Normalize(Cross(f, up), {1, 0, 0});
    Float3 d = Cross(f, r); // Down: view space is x right, y down, z forward.

    const Float3& p = camera.position;
    const Float3 rows[3] = {r, d, f};
    std::fill(worldToView, worldToView + 16, 0.0f);
    for (int row = 0; row < 3; row++)
    {
        worldToView[0 * 4 + row] = rows[row].x;
        worldToView[1 * 4 + row] = rows[row].y;
        worldToView[2 * 4 + row] = rows[row].z;
        worldToView[3 * 4 + row] = -Dot(rows[row], p);
    }
    worldToView[15] = 1.0f;

    float sy = 1.0f / std::tan(0.5f * camera.fovDeg * kDegToRad);
    float sx = sy * float(height) / float(std::max(width, 1u));
    std::fill(viewToClip, viewToClip + 16, 0.0f);
    viewToClip[0] = sx;
    viewToClip[5] = sy;
    viewToClip[3 * 4 + 2] = camera.nearZ; // clip.z = near -> ndc.z = near / viewZ (reversed, infinite)
    viewToClip[2 * 4 + 3] = 1.0f;         // clip.w = viewZ
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
    float v[4], c[4];
    for (int row = 0; row < 4; row++)
        v[row] = worldToView[row] * p[0] + worldToView[4 + row] * p[1] + worldToView[8 + row] * p[2] +
                 worldToView[12 + row];
    for (int row = 0; row < 4; row++)
        c[row] = viewToClip[row] * v[0] + viewToClip[4 + row] * v[1] + viewToClip[8 + row] * v[2] +
                 viewToClip[12 + row] * v[3];
    outViewZ = c[3];
    if (c[3] <= 0.0f)
        return false;
    outPixelX = (c[0] / c[3] * 0.5f + 0.5f) * float(width);
    outPixelY = (c[1] / c[3] * 0.5f + 0.5f) * float(height);
    return true;
}

} // namespace nrdlab
