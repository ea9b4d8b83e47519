// Scene.h - scene description of the scene lab: JSON loading, keyframed animation, per-frame
// evaluation and the camera matrices handed to the denoiser.
//
// The JSON schema is documented in Samples/Scenes/README.md. World space is right-handed, +Y up,
// metres. Angles in the JSON are degrees; everything here is in the units stated next to it.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace nrdlab
{

struct MeshData; // Mesh.h

// ------------------------------------------------------------------------------------------------
// Animation tracks

template <class T>
struct Keyframe
{
    uint32_t frame = 0;
    T value = {};
};

// A numeric property: 'value' when no keyframe sets it; otherwise linear interpolation between the
// keyframes that set it (sorted by frame), held constant before the first and after the last.
template <class T>
struct Track
{
    T value = {};
    std::vector<Keyframe<T>> keys;
};

// A switch ('enabled'): 'value' before the first keyframe that sets it, then the value of the last
// keyframe at or before the frame (a step, no interpolation).
struct SwitchTrack
{
    bool value = true;
    std::vector<Keyframe<bool>> keys;
};

float Evaluate(const Track<float>& track, float frame);
glm::vec3 Evaluate(const Track<glm::vec3>& track, float frame);
bool Evaluate(const SwitchTrack& track, float frame);

// ------------------------------------------------------------------------------------------------
// Scene

enum class PrimitiveType : uint32_t
{
    SPHERE, // 'radius' around the local origin.
    BOX,    // 'size' (full extents along local X, Y, Z), centred on the local origin.
    PLANE,  // Infinite, through the local origin, normal local +Y, two-sided.
    QUAD,   // size.x along local X by size.z along local Z, centred, normal local +Y, two-sided.
    MESH,   // The triangles of a model file ('mesh', 'scale' applied), two-sided, smooth normals.

    MAX_NUM
};

enum class LightType : uint32_t
{
    SUN,    // Infinite distant disc: 'direction' (towards the sun), 'angularRadiusDeg'.
            // 'intensity' = irradiance on a surface facing the sun (no shadow).
    SPHERE, // Sphere of 'radius' at 'position', uniform radiance intensity / (pi radius^2), so that
            // far away the irradiance is intensity / distance^2 like a point light.
    POINT,  // At 'position'; irradiance intensity * cos / distance^2. Hard shadows.

    MAX_NUM
};

// Metallic-roughness material. Diffuse albedo = albedo * (1 - metalness); specular F0 =
// mix(0.04, albedo, metalness); GGX with alpha = roughness^2 (roughness is NRD's linear roughness).
struct Material
{
    glm::vec3 albedo = {0.8f, 0.8f, 0.8f}; // [0, 1] each.
    float roughness = 0.5f;             // [0, 1].
    float metalness = 0.0f;             // [0, 1].
    glm::vec3 emission = {};            // Radiance emitted, >= 0, seen only by rays that hit it.
};

struct Object
{
    std::string name;
    PrimitiveType type = PrimitiveType::SPHERE;
    float radius = 0.5f;          // SPHERE.
    glm::vec3 size = {1, 1, 1};   // BOX: x, y, z extents; QUAD: x and z extents (y unused).
    std::string file;             // MESH: the path as written in the scene.
    glm::vec3 scale = {1, 1, 1};  // MESH: per-axis scale of the model (constant, baked into 'mesh').
    std::shared_ptr<const MeshData> mesh; // MESH: the loaded triangles and their BVH (shared, immutable).
    Material material;
    Track<glm::vec3> position; // World position of the local origin.
    Track<glm::vec3> rotation; // Euler angles in degrees, applied about X, then Y, then Z.
};

struct Light
{
    std::string name;
    LightType type = LightType::SUN;
    Track<glm::vec3> direction;     // SUN: towards the light, normalized when evaluated.
    Track<glm::vec3> position;      // SPHERE, POINT.
    float angularRadiusDeg = 0.27f; // SUN, [0, 30].
    float radius = 0.1f;          // SPHERE, > 0.
    Track<glm::vec3> intensity;   // RGB, >= 0 (units: see LightType).
    SwitchTrack enabled;          // A disabled light emits nothing and shadows everything.
};

struct CameraDesc
{
    Track<glm::vec3> position;
    Track<glm::vec3> target;
    Track<glm::vec3> up;          // Need not be orthogonal to the view direction.
    Track<float> fovDeg;          // Vertical field of view, (0, 180).
    float nearZ = 0.1f;           // Near plane of viewToClip (viewZ of the depth value 1).
};

// Sky radiance seen by rays that leave the scene: 'horizon' at dir.y = 0, blending linearly in
// dir.y to 'zenith' (dir.y = 1) and to 'ground' (dir.y = -1). A uniform sky has all three equal.
// The sky lights the scene only through bounce rays (it is not sampled by next-event estimation).
struct Sky
{
    glm::vec3 zenith = {0.25f, 0.45f, 0.85f};
    glm::vec3 horizon = {0.7f, 0.8f, 0.95f};
    glm::vec3 ground = {0.3f, 0.28f, 0.25f};
};

struct Scene
{
    std::string name;
    std::string description;
    uint32_t frameNum = 48;
    uint32_t seed = 1;
    Sky sky;
    CameraDesc camera;
    std::vector<Object> objects;
    std::vector<Light> lights;

    // Canonical JSON text (as parsed, re-serialized) that identifies the scene in cache keys.
    // Set by LoadScene; a scene built in code without it is never cached.
    std::string canonicalJson;
};

// Limits of the path tracer (storage buffer sizes, per-pixel light loops).
constexpr uint32_t kMaxObjects = 128;
constexpr uint32_t kMaxLights = 8;

// Loads a scene. 'pathOrText' is JSON text if its first non-blank character is '{'; otherwise a
// file path, or the name of a built-in scene ("static" -> <built-in dir>/static.json) if no such
// file exists. Returns false and a one-line message in 'error' on failure, naming the JSON path of
// the problem, e.g. `objects[2].material.roughness: expected number in [0, 1], got "x"`. Unknown
// keys are errors. Never throws. 'out' is only written on success. Mesh objects load their model
// here: a relative "file" is looked up next to the scene file (the working directory for JSON
// text), then in GetModelsDirectory() (Mesh.h); errors name the file and the JSON path.
bool LoadScene(const std::string& pathOrText, Scene& out, std::string& error);

// True when the camera, an object or a light changes over the frames (a track with keyframes):
// quality bars tell still scenes from moving ones by it.
bool IsSceneAnimated(const Scene& scene);

// Directory of the built-in scenes (Samples/Scenes of the source tree, or NRDLAB_SCENES_DIR from
// the environment if set).
std::string GetBuiltinScenesDirectory();

// Names (file names without ".json") of the built-in scenes, sorted.
std::vector<std::string> GetBuiltinSceneNames();

// ------------------------------------------------------------------------------------------------
// Per-frame evaluation

struct ObjectState
{
    glm::vec3 position;
    glm::mat3 rotation = glm::mat3(1.0f); // World-from-local (world = rotation * local + position).
};

struct LightState
{
    LightType type = LightType::SUN;
    glm::vec3 direction;          // SUN: unit vector towards the light.
    glm::vec3 position;           // SPHERE, POINT.
    float radius = 0.0f;          // SPHERE.
    float tanAngularRadius = 0.0f; // SUN: tan(angular radius).
    float cosAngularRadius = 1.0f; // SUN: cos(angular radius).
    glm::vec3 intensity;           // Zero if disabled.
    bool enabled = true;
};

struct CameraState
{
    glm::vec3 position, target, up;
    float fovDeg = 60.0f;
    float nearZ = 0.1f;
};

struct SceneState
{
    CameraState camera;
    std::vector<ObjectState> objects; // Same order as Scene::objects.
    std::vector<LightState> lights;   // Same order as Scene::lights.
};

// The scene at 'frame' (any value; frames beyond the keyframes hold the last values).
SceneState EvaluateScene(const Scene& scene, uint32_t frame);

// ------------------------------------------------------------------------------------------------
// Camera matrices for the denoiser (copy them into nrd::CommonSettings)
//
// Conventions:
//   - Column-major: m[column * 4 + row]; a point transforms as M * (x, y, z, 1).
//   - View space: x right, y down, z forward (right-handed); viewZ = z > 0 in front of the camera
//     (the IN_VIEWZ value).
//   - viewToClip: Vulkan clip space, x right, y down, clip w = +viewZ, reversed infinite depth:
//     ndc.z = nearZ / viewZ. Non-jittered.
//   - uv = ndc.xy * 0.5 + 0.5 addresses the image with v growing downwards; pixel (x, y) has its
//     centre at uv = ((x + 0.5) / width, (y + 0.5) / height), where the primary ray goes.
//   - Frame 0's "previous" camera is frame 0's own (no motion on the first frame).
struct FrameCamera
{
    float worldToView[16] = {};
    float viewToClip[16] = {};
    float worldToViewPrev[16] = {};
    float viewToClipPrev[16] = {};
    float position[3] = {};       // World-space camera position (this frame).
    float positionPrev[3] = {};
    float fovDeg = 0.0f;          // Vertical.
    float nearZ = 0.0f;
    uint32_t width = 0, height = 0;
};

FrameCamera ComputeFrameCamera(const Scene& scene, uint32_t frame, uint32_t width, uint32_t height);

// The matrices of one camera state for an image of width x height.
void ComputeCameraMatrices(const CameraState& camera, uint32_t width, uint32_t height, float worldToView[16],
                           float viewToClip[16]);

// Projects a world-space point with column-major matrices to pixel coordinates (pixel centres at
// .5) and its viewZ. Returns false if the point is behind the camera (clip w <= 0).
bool ProjectToPixel(const float worldToView[16], const float viewToClip[16], uint32_t width, uint32_t height,
                    const float worldPosition[3], float& outPixelX, float& outPixelY, float& outViewZ);

} // namespace nrdlab
