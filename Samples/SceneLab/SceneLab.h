// SceneLab.h - renders denoiser inputs and their ground truth for a scene (Scene.h) on the GPU,
// through nrd::rhi, and reads them back as nrdlab::Image.
//
// Per frame: the G-buffer (primary ray through each pixel centre, no jitter), 1 sample per pixel of
// every requested signal (the noisy input) packed with Shaders/Include/NRD.glsl, and, for the same
// primary hits, the mean of 'truthSpp' independent samples of each signal (the ground truth).
// Same scene + params (+ seed) => bit-identical output, on the same device and driver.
// Conventions of every image: FrameData below; of the matrices: FrameCamera in Scene.h; of the
// estimators: README.md next to this file.
//
// Typical use:
//     nrd::lab::VulkanContext vk;  vk.Create({});
//     nrdlab::SceneLab lab(vk);    // or SceneLab(rhiDevice)
//     nrdlab::Scene scene;         nrdlab::LoadScene("static", scene, error);
//     nrdlab::RenderParams p;      p.signals = nrdlab::SIGNAL_SHADOW; p.frameIndex = f;
//     nrdlab::FrameData frame;     lab.Render(scene, p, frame, error);
#pragma once

#include "Image.h"
#include "Mesh.h"
#include "Scene.h"

#include "NRD.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nrd
{
namespace rhi
{
class Device;
}
namespace lab
{
class VulkanContext;
}
} // namespace nrd

namespace nrdlab
{

// Signals to render. The G-buffer is always rendered (every method needs it).
enum SignalBits : uint32_t
{
    SIGNAL_SHADOW = 1u << 1,       // One light: SIGMA shadowData, visibility mask, tile hit mask.
    SIGNAL_TRANSLUCENCY = 1u << 2, // All lights: SIGMA_SHADOW_TRANSLUCENCY inputs.
    SIGNAL_DIFFUSE = 1u << 3,      // Diffuse radiance + hit distance.
    SIGNAL_SPECULAR = 1u << 4,     // Specular radiance + hit distance.
    SIGNAL_GRADIENTS = 1u << 5,    // Temporal gradients (confidence method); no truth.

    SIGNAL_ALL = SIGNAL_SHADOW | SIGNAL_TRANSLUCENCY | SIGNAL_DIFFUSE | SIGNAL_SPECULAR | SIGNAL_GRADIENTS,
};
typedef uint32_t SignalMask;

// RenderParams::seed value meaning "use Scene::seed".
constexpr uint32_t kSceneSeed = 0xFFFFFFFFu;

// viewZ of sky pixels (far beyond any denoisingRange; the denoisers skip them).
constexpr float kSkyViewZ = 1e7f;

// Hit distance / occluder distance meaning "nothing hit" (NRD_FP16_MAX).
constexpr float kNoHitDistance = 65504.0f;

struct RenderParams
{
    uint32_t width = 256;          // 1..8192
    uint32_t height = 256;         // 1..8192
    uint32_t frameIndex = 0;       // Animation frame; the previous frame is frameIndex - 1 (itself for 0).
    uint32_t truthSpp = 256;       // Ground-truth samples per pixel; 0 = no ground truth.
    uint32_t truthChunkSpp = 16;   // Samples per truth dispatch (keeps each GPU submission short).
    uint32_t seed = kSceneSeed;    // Random seed of every sample.
    SignalMask signals = SIGNAL_SHADOW;
    uint32_t lightIndex = 0;       // Light of SIGNAL_SHADOW (index into Scene::lights).
    uint32_t bounces = 1;          // Diffuse / specular / gradients: 1 (direct light at the bounce hit) or 2.
    bool directLighting = true;    // Diffuse / specular / gradients include the primary surface's direct light.
    // Normalization of the diffuse / specular hit distances (their .w), as the application gives it
    // to the denoiser (REBLUR_FrontEnd_GetNormHitDist; diffuse with roughness 1).
    nrd::HitDistanceParameters hitDistanceParameters;
    bool useCache = true;          // Read / write the disk cache (if the lab has a cache directory).
};

// What SigmaSettings and the app need about a light on this frame.
struct LightInfo
{
    LightType type = LightType::SUN;
    bool enabled = true;
    // SigmaSettings::lightDirection: unit vector towards the sun; {0, 0, 0} ("unknown") for local lights.
    float direction[3] = {};
    float position[3] = {};          // SPHERE, POINT.
    float radius = 0.0f;             // SPHERE.
    // SUN: tan(angular radius), the value packed into every pixel's shadowData. Local lights: 0
    // here (the shader uses radius / distance per pixel).
    float tanOfLightAngularRadius = 0.0f;
    float intensity[3] = {};         // 0 if disabled.
};

// One rendered frame. Images are float32, width x height unless stated; images of signals that
// were not requested are empty (width 0). Sky pixels: viewZ = kSkyViewZ, signals as noted.
struct FrameData
{
    uint32_t width = 0, height = 0, frameIndex = 0;
    uint32_t seed = 0;               // Effective seed.
    SignalMask signals = 0;          // As requested.
    uint32_t truthSpp = 0;           // 0 if no truth was rendered.

    FrameCamera camera;              // Matrices for nrd::CommonSettings (see Scene.h).
    uint32_t lightIndex = 0;
    LightInfo light;                 // The shadow light (RenderParams::lightIndex), if any.
    std::vector<LightInfo> lights;   // All lights.

    // G-buffer (always).
    Image viewZ;           // 1 ch: positive linear view depth (IN_VIEWZ); sky kSkyViewZ.
    Image normalRoughness; // 4 ch: NRD_FrontEnd_PackNormalAndRoughness, n * 0.5 + 0.5 and linear roughness.
    Image motion2d;        // 2 ch: uvPrev - uv (v down, non-jittered); sky: camera rotation only.
                           //   IN_MV with motionVectorScale {1, 1, 0}, isMotionVectorInWorldSpace false.
    Image motion3d;        // 3 ch: world posPrev - pos (0 on static objects and the sky).
                           //   IN_MV with motionVectorScale {1, 1, 1}, isMotionVectorInWorldSpace true.
    Image albedo;          // 3 ch: diffuse albedo = albedo * (1 - metalness); sky 0.
    Image specularAlbedo;  // 3 ch: specular directional albedo (the specular signals are divided by it).
    Image objectIndex;     // 1 ch: index into Scene::objects, -1 for sky.

    // SIGNAL_SHADOW (light 'lightIndex').
    Image shadowData;       // 2 ch: SIGMA_FrontEnd_PackShadow(viewZ, distanceToOccluder, tan) (IN_SHADOWDATA); sky SIGMA_INF_SHADOW.
    Image shadowVisibility; // 1 ch: the raw 1-ray visibility, 0 or 1 (sky 1).
    Image shadowTruth;      // 1 ch: expected visibility for the same primary hit (sky 1).
    // Tile shadow method input: ceil(width / 8) x ceil(height / 4) uints, row-major; bit
    // (x % 8) + 8 * (y % 4) of tile (x / 8, y / 4) is set when pixel (x, y) is lit (visibility 1).
    // Pixels outside the image and sky pixels count as lit.
    std::vector<uint32_t> shadowHitMask;
    uint32_t shadowHitMaskWidth = 0, shadowHitMaskHeight = 0;

    // SIGNAL_TRANSLUCENCY (all lights, weight 1, SIGMA_FrontEnd_MultiLight*).
    Image translucency;          // 4 ch: shadowTranslucency of MultiLightEnd (IN_SHADOW_TRANSLUCENCY); sky 1.
    Image translucencyShadowData; // 2 ch: the shadowData MultiLightEnd returns (IN_SHADOWDATA); sky SIGMA_INF_SHADOW.
    // 4 ch: .x expected mean-over-lights visibility, .yzw sum(L_i V_i) / sum(L_i) (1 where sum L_i = 0).
    Image translucencyTruth;

    // SIGNAL_DIFFUSE / SIGNAL_SPECULAR: 4 ch, packed by REBLUR_FrontEnd_PackRadianceAndNormHitDist
    // (IN_DIFF_RADIANCE_HITDIST / IN_SPEC_RADIANCE_HITDIST, sanitized): rgb radiance, .w normalized
    // hit distance of the bounce ray (RenderParams::hitDistanceParameters; 1 if it left the scene
    // or went beyond the range). Sky pixels: (0, 0, 0, 1).
    // Both are demodulated: final colour = albedo * diffuse + specularAlbedo * specular.
    //   diffuse: [direct light of every light, 1 shadow ray each, / pi] + incoming radiance along
    //     one cosine-sampled direction (emission + direct light at the hit [+ 1 more bounce] or
    //     sky). NOT multiplied by the primary's albedo: its expectation is irradiance / pi.
    //   specular: ([GGX direct light of every light] + one GGX VNDF-sampled reflection weighted
    //     F * G2 / G1) / specularAlbedo. Direct light uses roughness >= 0.25 (see the README).
    //   [..] only with RenderParams::directLighting (default).
    // Truth .w: mean normalized hit distance over the truth samples (misses count as 1), i.e. what
    // a perfect ambient / specular occlusion denoiser returns, in [0, 1]; sky 1.
    Image diffuse, diffuseTruth;
    Image specular, specularTruth;

    // SIGNAL_GRADIENTS: ceil(width / 3) x ceil(height / 3) strata.
    Image gradients;    // 2 ch: |cur - prev| / max(cur, prev) of luminance, diffuse and specular; 0 if invalid.
    Image gradientsRaw; // 4 ch: |dLum| diffuse, max lum diffuse, |dLum| specular, max lum specular.

    // Statistics of this call.
    double noisyMs = 0.0; // Wall time of the G-buffer + noisy signals + gradients (GPU + readback).
    double truthMs = 0.0; // Wall time of the ground truth.
    bool noisyFromCache = false;
    bool truthFromCache = false;
};

struct SceneLabDesc
{
    // Directory of the frame cache; empty = no cache. GetDefaultCacheDirectory() is a good choice.
    std::string cacheDirectory;
    // (Optional) Called after every truth chunk with (samples done, samples total).
    std::function<void(uint32_t, uint32_t)> truthProgress;
};

// $XDG_CACHE_HOME/nrd-lab, else $HOME/.cache/nrd-lab, else /tmp/nrd-lab.
std::string GetDefaultCacheDirectory();

// Not thread-safe: one thread renders at a time. Every Render call waits for the device.
class SceneLab
{
public:
    // The device must outlive the lab. Creates its buffers and the G-buffer pipeline (the other
    // shader variants are created on first use); check IsValid().
    explicit SceneLab(nrd::rhi::Device& device, const SceneLabDesc& desc = {});
    explicit SceneLab(nrd::lab::VulkanContext& context, const SceneLabDesc& desc = {});
    ~SceneLab();
    SceneLab(const SceneLab&) = delete;
    SceneLab& operator=(const SceneLab&) = delete;

    // False if creating the pipelines failed (GetError says why).
    bool IsValid() const;
    const std::string& GetError() const;

    // Renders (or loads from the cache) one frame of 'scene': the G-buffer and the requested signals,
    // with their truth if params.truthSpp > 0. Returns false with a message for bad params (size,
    // light index, bounces, too many objects) or a device error; 'out' is then unspecified.
    bool Render(const Scene& scene, const RenderParams& params, FrameData& out, std::string& error);

    // The application's ray pass of a variable-rate reflection denoiser (nrd::Method::REFLECTION):
    // traces the specular sample of frame 'params.frameIndex' (as Render's SIGNAL_SPECULAR, same
    // random stream, so a ray of pixel p gives exactly frame.specular at p) for the rays of
    // 'rayList' only (nrd::BufferContent::RAY_LIST entries), with one indirect dispatch over the
    // list; each result also goes to the quad neighbours its entry names. 'out' (4 ch, packed as
    // FrameData::specular) is (0, 0, 0, 1) wherever no ray wrote. Never cached. Returns false with a
    // message for bad params or a device error.
    bool TraceSpecularRays(const Scene& scene, const RenderParams& params, const std::vector<uint32_t>& rayList,
                           Image& out, std::string& error);

    void SetCacheDirectory(const std::string& directory);

    // Traces object-space rays through the BVH of mesh object 'objectIndex' of 'scene' on the device,
    // with the traversal every lab pass uses (Shaders/LabScene.glsl IntersectMesh), for tests that
    // compare it with a CPU intersection (Mesh.h IntersectMesh). One hit per ray: the triangle index
    // in MeshData::triangles (BVH order, -1 on a miss), t in (0, ray.tMax) and the barycentrics.
    // Returns false with a message if the object is not a mesh or the device fails.
    struct MeshRay
    {
        glm::vec3 origin = glm::vec3(0.0f);
        glm::vec3 direction = glm::vec3(0.0f, 0.0f, 1.0f); // Need not be unit length.
        float tMax = 1e30f;
        bool anyHit = false; // Stop at the first triangle found (as shadow rays do).
    };
    bool TraceMeshRays(const Scene& scene, uint32_t objectIndex, const std::vector<MeshRay>& rays,
                       std::vector<MeshHit>& hits, std::string& error);

private:
    struct Impl;
    std::unique_ptr<Impl> m_Impl;
};

// FNV-1a 64 of the image's size and raw pixel bytes (for determinism tests).
uint64_t HashImage(const Image& image);
// Hash of every image and the hit mask of a frame.
uint64_t HashFrame(const FrameData& frame);

// Shadow hit mask bit of pixel (x, y) (true = lit); pixels outside the image are lit.
bool IsLitInHitMask(const FrameData& frame, int32_t x, int32_t y);

// Per pixel (3 ch): object index, viewZ, and the viewZ its surface point had in the previous
// frame's camera (from the G-buffer: the point at viewZ through the pixel centre, plus motion3d).
// The surface id of ReuseBounds (ReuseBounds.h): an exact disocclusion test up to its depth
// tolerance, for meshes that hide parts of themselves too. Empty if the G-buffer is missing.
Image SurfaceIds(const FrameData& frame);

} // namespace nrdlab
