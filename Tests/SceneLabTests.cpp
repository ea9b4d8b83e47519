// Scene lab: scene loading and its errors, animation, camera conventions, and the path tracer's
// outputs on lavapipe (determinism, SIGMA packing vs the visibility mask, gradients, truth
// convergence, cache). Sizes are small so the whole file runs in a couple of minutes on 2 CPU cores.
#include <catch2/catch.hpp>

#include "Mesh.h"
#include "Metrics.h"
#include "SceneLab.h"
#include "VulkanContext.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

using namespace nrdlab;

namespace
{

// One device and one lab for the whole file (pipeline compilation is the slow part on a CPU).
struct LabFixture
{
    nrd::lab::VulkanContext vk;
    std::unique_ptr<SceneLab> lab;

    LabFixture()
    {
        nrd::lab::VulkanContextDesc desc;
        desc.quiet = true;
        if (vk.Create(desc) == VK_SUCCESS)
            lab.reset(new SceneLab(vk));
    }
};

SceneLab& Lab()
{
    static LabFixture fixture;
    REQUIRE(fixture.lab);
    REQUIRE(fixture.lab->IsValid());
    return *fixture.lab;
}

Scene LoadBuiltin(const std::string& name)
{
    Scene scene;
    std::string error;
    INFO(name << ": " << error);
    REQUIRE(LoadScene(name, scene, error));
    return scene;
}

std::string LoadError(const std::string& text)
{
    Scene scene;
    std::string error;
    CHECK_FALSE(LoadScene(text, scene, error));
    return error;
}

std::string ReadText(const std::string& path)
{
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

FrameData Render(const Scene& scene, RenderParams params)
{
    FrameData frame;
    std::string error;
    params.useCache = false;
    INFO(error);
    REQUIRE(Lab().Render(scene, params, frame, error));
    return frame;
}

bool AllFinite(const Image& image)
{
    for (float v : image.pixels)
        if (!std::isfinite(v))
            return false;
    return true;
}

Image Channels(const Image& src, uint32_t first, uint32_t num)
{
    Image dst(src.width, src.height, num);
    for (size_t p = 0; p < src.pixelCount(); p++)
        for (uint32_t ch = 0; ch < num; ch++)
            dst.pixels[p * num + ch] = src.pixels[p * src.channels + first + ch];
    return dst;
}

} // namespace

// ------------------------------------------------------------------------------------------------
// Scenes (CPU)

TEST_CASE("every built-in scene loads, has 32 to 64 frames and a light", "[scenelab]")
{
    std::vector<std::string> names = GetBuiltinSceneNames();
    for (const char* required : {"static", "camera_translation", "camera_rotation", "moving_occluder", "light_switch",
                                 "moving_light", "thin_geometry", "grazing_floor", "roughness_sweep", "sky",
                                 "disocclusion"})
        CHECK(std::find(names.begin(), names.end(), required) != names.end());
    for (const std::string& name : names)
    {
        Scene scene = LoadBuiltin(name);
        INFO(name);
        CHECK(scene.frameNum >= 32);
        CHECK(scene.frameNum <= 64);
        CHECK_FALSE(scene.lights.empty());
        CHECK_FALSE(scene.objects.empty());
        CHECK_FALSE(scene.description.empty());
    }
}

TEST_CASE("scene errors name the JSON path of the bad value", "[scenelab]")
{
    const std::string base = R"({ "camera": { "position": [0, 1, 5], "target": [0, 0, 0] },
        "objects": [ { "type": "plane" }, { "type": "sphere", "radius": 1, "material": { "roughness": 0.5 } } ],
        "lights": [ { "type": "sun", "direction": [0, 1, 0] } ] })";
    Scene ok;
    std::string error;
    REQUIRE(LoadScene(base, ok, error));
    CHECK(ok.objects.size() == 2);

    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string s = base;
        size_t at = s.find(from);
        REQUIRE(at != std::string::npos);
        return s.replace(at, from.size(), to);
    };

    CHECK(LoadError(replaced("\"roughness\": 0.5", "\"roughness\": \"x\"")) ==
          "objects[1].material.roughness: expected number in [0, 1], got \"x\"");
    CHECK(LoadError(replaced("\"roughness\": 0.5", "\"roughness\": 1.5")) ==
          "objects[1].material.roughness: expected number in [0, 1], got 1.5");
    CHECK(LoadError(replaced("\"radius\": 1", "\"radus\": 1")).find("objects[1].radus: unknown key (did you mean "
                                                                   "\"radius\"?)") == 0);
    CHECK(LoadError(replaced("\"type\": \"sphere\"", "\"type\": \"cone\"")).find("objects[1].type: expected") == 0);
    CHECK(LoadError(replaced("\"direction\": [0, 1, 0]", "\"direction\": [0, 1]")).find("lights[0].direction:") == 0);
    CHECK(LoadError(replaced("\"direction\": [0, 1, 0]", "\"direction\": [0, 0, 0]")).find("lights[0].direction:") ==
          0);
    CHECK(LoadError(replaced("\"camera\"", "\"camra\"")).find("camra: unknown key") == 0);
    CHECK(LoadError(replaced("\"type\": \"sun\"", "\"type\": \"sun\", \"keyframes\": [ { \"frame\": 4 }, { \"frame\": "
                                                  "2 } ]"))
              .find("lights[0].keyframes[1].frame: keyframes must have increasing frames") == 0);
    CHECK(LoadError(replaced("[0, 1, 5]", "[0, 1, 5")).find("JSON syntax error at line 1") != std::string::npos);
    CHECK(LoadError("no_such_scene_file").find("cannot read scene file") == 0);
}

TEST_CASE("a scene file with a typo or damage never crashes the loader", "[scenelab]")
{
    // Every single-character deletion of a small scene: either it loads or it says why.
    const std::string text = ReadText(GetBuiltinScenesDirectory() + "/sky.json");
    REQUIRE(text.size() > 100);
    uint32_t errors = 0;
    for (size_t i = 0; i < text.size(); i += 7)
    {
        std::string damaged = text;
        damaged.erase(i, 1);
        Scene scene;
        std::string error;
        if (!LoadScene(damaged, scene, error))
        {
            CHECK_FALSE(error.empty());
            errors++;
        }
    }
    CHECK(errors > 0);
}

TEST_CASE("keyframes interpolate linearly, hold at the ends, and switches step", "[scenelab]")
{
    Track<float> t;
    t.value = 7.0f;
    CHECK(Evaluate(t, 3.0f) == 7.0f); // no keys: the static value
    t.keys = {{10, 1.0f}, {20, 3.0f}};
    CHECK(Evaluate(t, 0.0f) == 1.0f);
    CHECK(Evaluate(t, 15.0f) == Approx(2.0f));
    CHECK(Evaluate(t, 99.0f) == 3.0f);

    SwitchTrack s;
    s.value = true;
    s.keys = {{16, false}, {24, true}};
    CHECK(Evaluate(s, 15.0f));
    CHECK_FALSE(Evaluate(s, 16.0f));
    CHECK_FALSE(Evaluate(s, 23.0f));
    CHECK(Evaluate(s, 24.0f));

    Scene sw = LoadBuiltin("light_switch");
    CHECK(EvaluateScene(sw, 15).lights[0].enabled);
    CHECK_FALSE(EvaluateScene(sw, 16).lights[0].enabled);
    CHECK(EvaluateScene(sw, 16).lights[0].intensity.x == 0.0f);
    CHECK(EvaluateScene(sw, 24).lights[0].enabled);
}

TEST_CASE("camera matrices follow the documented conventions", "[scenelab]")
{
    Scene scene = LoadBuiltin("static");
    FrameCamera cam = ComputeFrameCamera(scene, 0, 200, 100);
    const float target[3] = {0.0f, 0.5f, 0.0f}; // the camera looks at it: image centre
    float px, py, z;
    REQUIRE(ProjectToPixel(cam.worldToView, cam.viewToClip, 200, 100, target, px, py, z));
    CHECK(px == Approx(100.0f).margin(1e-3));
    CHECK(py == Approx(50.0f).margin(1e-3));
    const float distance = std::sqrt((2.4f - 0.5f) * (2.4f - 0.5f) + 5.6f * 5.6f); // |position - target|
    CHECK(z == Approx(distance).epsilon(1e-5)); // clip w = +viewZ
    const float above[3] = {0.0f, 1.5f, 0.0f};
    REQUIRE(ProjectToPixel(cam.worldToView, cam.viewToClip, 200, 100, above, px, py, z));
    CHECK(py < 50.0f); // v grows downwards
    const float right[3] = {1.0f, 0.5f, 0.0f};
    REQUIRE(ProjectToPixel(cam.worldToView, cam.viewToClip, 200, 100, right, px, py, z));
    CHECK(px > 100.0f);
    const float behind[3] = {0.0f, 2.4f, 9.0f};
    CHECK_FALSE(ProjectToPixel(cam.worldToView, cam.viewToClip, 200, 100, behind, px, py, z));
    // Frame 0's previous camera is itself.
    for (int i = 0; i < 16; i++)
    {
        CHECK(cam.worldToViewPrev[i] == cam.worldToView[i]);
        CHECK(cam.viewToClipPrev[i] == cam.viewToClip[i]);
    }
}

// ------------------------------------------------------------------------------------------------
// Path tracer (lavapipe)

TEST_CASE("a world point projects to the pixel where the path tracer sees it", "[scenelab][vulkan]")
{
    Scene scene = LoadBuiltin("static");
    RenderParams p;
    p.width = 96;
    p.height = 64;
    p.truthSpp = 0;
    p.signals = 0;
    FrameData f = Render(scene, p);
    REQUIRE(f.viewZ.width == 96);

    // The point of each sphere nearest the camera, and a floor point.
    struct Probe
    {
        float pos[3];
        int object;
    };
    std::vector<Probe> probes;
    for (size_t i = 0; i < scene.objects.size(); i++)
    {
        const Object& o = scene.objects[i];
        if (o.type != PrimitiveType::SPHERE)
            continue;
        glm::vec3 c = o.position.value;
        float d[3] = {f.camera.position[0] - c.x, f.camera.position[1] - c.y, f.camera.position[2] - c.z};
        float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        probes.push_back({{c.x + o.radius * d[0] / len, c.y + o.radius * d[1] / len, c.z + o.radius * d[2] / len},
                          int(i)});
    }
    probes.push_back({{-0.5f, 0.0f, 2.0f}, 0}); // floor (object 0), in front of everything
    REQUIRE(probes.size() >= 4);

    for (const Probe& probe : probes)
    {
        float px, py, z;
        REQUIRE(ProjectToPixel(f.camera.worldToView, f.camera.viewToClip, p.width, p.height, probe.pos, px, py, z));
        uint32_t x = uint32_t(px), y = uint32_t(py);
        REQUIRE(x < p.width);
        REQUIRE(y < p.height);
        INFO("object " << probe.object << " at pixel " << x << ", " << y);
        CHECK(f.objectIndex.at(x, y, 0) == float(probe.object));
        // The pixel centre is within half a pixel of the point: the depths agree closely.
        CHECK(f.viewZ.at(x, y, 0) == Approx(z).epsilon(0.02));
    }
}

TEST_CASE("motion vectors are zero for a still scene and follow moving objects", "[scenelab][vulkan]")
{
    RenderParams p;
    p.width = 48;
    p.height = 48;
    p.truthSpp = 0;
    p.signals = 0;
    p.frameIndex = 10;
    FrameData still = Render(LoadBuiltin("static"), p);
    for (float v : still.motion2d.pixels)
        CHECK(v == 0.0f);
    for (float v : still.motion3d.pixels)
        CHECK(v == 0.0f);

    Scene scene = LoadBuiltin("moving_occluder");
    FrameData moving = Render(scene, p);
    int flying = -1;
    for (size_t i = 0; i < scene.objects.size(); i++)
        if (scene.objects[i].name == "flying sphere")
            flying = int(i);
    REQUIRE(flying >= 0);
    uint32_t flyingPixels = 0;
    for (uint32_t y = 0; y < p.height; y++)
        for (uint32_t x = 0; x < p.width; x++)
        {
            bool isFlying = moving.objectIndex.at(x, y, 0) == float(flying);
            float mx = moving.motion3d.at(x, y, 0);
            if (isFlying)
            {
                flyingPixels++;
                // It moves +x by 5.6 / 47 per frame: posPrev - pos = (-0.119, 0, 0).
                CHECK(mx == Approx(-5.6f / 47.0f).epsilon(1e-3));
                CHECK(moving.motion2d.at(x, y, 0) < 0.0f); // it was further left: uvPrev.x < uv.x
            }
            else if (moving.objectIndex.at(x, y, 0) == 0.0f)
                CHECK(mx == 0.0f); // the floor does not move
        }
    CHECK(flyingPixels > 0);
}

TEST_CASE("equal seeds give identical output and different seeds differ", "[scenelab][vulkan]")
{
    Scene scene = LoadBuiltin("moving_light");
    RenderParams p;
    p.width = 40;
    p.height = 32;
    p.frameIndex = 5;
    p.truthSpp = 4;
    p.truthChunkSpp = 3; // chunking does not change the sums
    p.signals = SIGNAL_ALL;
    p.seed = 7;
    FrameData a = Render(scene, p);
    FrameData b = Render(scene, p);
    CHECK(HashFrame(a) == HashFrame(b));

    p.truthChunkSpp = 4;
    FrameData c = Render(scene, p);
    CHECK(HashFrame(a) == HashFrame(c));

    p.seed = 8;
    FrameData d = Render(scene, p);
    CHECK(HashImage(a.viewZ) == HashImage(d.viewZ)); // the G-buffer does not depend on the seed
    CHECK(HashImage(a.shadowVisibility) != HashImage(d.shadowVisibility));
    CHECK(HashImage(a.diffuse) != HashImage(d.diffuse));
    CHECK(HashImage(a.specularTruth) != HashImage(d.specularTruth));

    // A signal's values do not depend on which other signals are rendered with it.
    p.seed = 7;
    p.signals = SIGNAL_DIFFUSE;
    FrameData e = Render(scene, p);
    CHECK(HashImage(a.diffuse) == HashImage(e.diffuse));
    CHECK(HashImage(a.diffuseTruth) == HashImage(e.diffuseTruth));
    CHECK(e.shadowData.width == 0); // not requested, not rendered
    CHECK(e.specular.width == 0);
}

TEST_CASE("every built-in scene renders a frame with finite values", "[scenelab][vulkan]")
{
    for (const std::string& name : GetBuiltinSceneNames())
    {
        Scene scene = LoadBuiltin(name);
        RenderParams p;
        p.width = 64;
        p.height = 64;
        p.frameIndex = scene.frameNum / 2;
        p.truthSpp = 2;
        p.signals = SIGNAL_ALL;
        FrameData f = Render(scene, p);
        INFO(name);
        const Image* images[] = {&f.viewZ,        &f.normalRoughness,  &f.motion2d,          &f.motion3d,
                                 &f.albedo,       &f.specularAlbedo,   &f.shadowData,        &f.shadowVisibility,
                                 &f.shadowTruth,  &f.translucency,     &f.translucencyShadowData, &f.translucencyTruth,
                                 &f.diffuse,      &f.diffuseTruth,     &f.specular,          &f.specularTruth,
                                 &f.gradients,    &f.gradientsRaw};
        for (const Image* image : images)
        {
            CHECK(image->isValid());
            CHECK(AllFinite(*image));
        }
        uint32_t sky = 0;
        for (size_t i = 0; i < f.viewZ.pixelCount(); i++)
        {
            float z = f.viewZ.pixels[i];
            CHECK(z > 0.0f);
            sky += z >= kSkyViewZ ? 1 : 0;
            for (uint32_t ch = 0; ch < 4; ch++)
            {
                float v = f.normalRoughness.pixels[i * 4 + ch];
                CHECK((v >= 0.0f && v <= 1.0f));
            }
        }
        if (name == "sky")
            CHECK(sky > f.viewZ.pixelCount() / 3);
        CHECK(f.lights.size() == scene.lights.size());
    }
}

TEST_CASE("SIGMA shadow data and the tile hit mask agree with the visibility mask", "[scenelab][vulkan]")
{
    Scene scene = LoadBuiltin("thin_geometry");
    RenderParams p;
    p.width = 61; // odd sizes: partial tiles on the right and at the bottom
    p.height = 37;
    p.truthSpp = 0;
    p.signals = SIGNAL_SHADOW;
    FrameData f = Render(scene, p);
    REQUIRE(f.shadowHitMaskWidth == 8);
    REQUIRE(f.shadowHitMaskHeight == 10);
    REQUIRE(f.shadowHitMask.size() == 80);
    CHECK(f.light.type == LightType::SUN);
    CHECK(f.light.tanOfLightAngularRadius == Approx(std::tan(0.5 * 3.14159265358979 / 180.0)));

    uint32_t lit = 0, shadowed = 0, sky = 0;
    for (uint32_t y = 0; y < p.height; y++)
        for (uint32_t x = 0; x < p.width; x++)
        {
            float v = f.shadowVisibility.at(x, y, 0);
            float packedVisibility = f.shadowData.at(x, y, 0);
            float penumbra = f.shadowData.at(x, y, 1);
            bool isSky = f.viewZ.at(x, y, 0) >= kSkyViewZ;
            REQUIRE((v == 0.0f || v == 1.0f));
            CHECK(packedVisibility == v);
            if (v == 1.0f)
            {
                CHECK(penumbra == kNoHitDistance); // lit: no penumbra
                lit++;
            }
            else
            {
                CHECK(penumbra >= 0.0f);
                CHECK(penumbra < kNoHitDistance);
                shadowed++;
            }
            sky += isSky ? 1 : 0;
            if (isSky)
                CHECK(v == 1.0f);
            CHECK(IsLitInHitMask(f, int32_t(x), int32_t(y)) == (v == 1.0f));
        }
    CHECK(lit > 0);
    CHECK(shadowed > 0);
    // Bits of pixels beyond the image are set (lit).
    for (uint32_t ty = 0; ty < f.shadowHitMaskHeight; ty++)
        for (uint32_t tx = 0; tx < f.shadowHitMaskWidth; tx++)
            for (uint32_t bit = 0; bit < 32; bit++)
            {
                uint32_t x = tx * 8 + bit % 8, y = ty * 4 + bit / 8;
                if (x >= p.width || y >= p.height)
                    CHECK(((f.shadowHitMask[ty * f.shadowHitMaskWidth + tx] >> bit) & 1u) == 1u);
            }
    (void)sky;
}

TEST_CASE("multi-light translucency input and truth are consistent", "[scenelab][vulkan]")
{
    Scene scene = LoadBuiltin("light_switch"); // a sphere light and a sun
    RenderParams p;
    p.width = 48;
    p.height = 48;
    p.frameIndex = 4;
    p.truthSpp = 8;
    p.signals = SIGNAL_TRANSLUCENCY;
    FrameData f = Render(scene, p);
    for (size_t i = 0; i < f.translucency.pixelCount(); i++)
    {
        float v = f.translucency.pixels[i * 4];
        // Mean visibility over 2 lights, one ray each: 0, 0.5 or 1; the same in shadowData.x.
        CHECK((v == 0.0f || v == 0.5f || v == 1.0f));
        CHECK(f.translucencyShadowData.pixels[i * 2] == v);
        for (uint32_t ch = 0; ch < 4; ch++)
        {
            float t = f.translucencyTruth.pixels[i * 4 + ch];
            CHECK((t >= 0.0f && t <= 1.0f));
        }
    }
}

TEST_CASE("gradients are zero when nothing changes and large where a light switches off", "[scenelab][vulkan]")
{
    RenderParams p;
    p.width = 48;
    p.height = 48;
    p.truthSpp = 0;
    p.signals = SIGNAL_GRADIENTS;

    p.frameIndex = 0;
    FrameData first = Render(LoadBuiltin("static"), p);
    REQUIRE(first.gradients.width == 16);
    for (float v : first.gradientsRaw.pixels)
        CHECK(v == 0.0f); // no previous frame

    p.frameIndex = 7;
    FrameData still = Render(LoadBuiltin("static"), p);
    uint32_t valid = 0;
    for (size_t i = 0; i < still.gradientsRaw.pixelCount(); i++)
    {
        CHECK(still.gradientsRaw.pixels[i * 4 + 0] == 0.0f);
        CHECK(still.gradientsRaw.pixels[i * 4 + 2] == 0.0f);
        valid += still.gradientsRaw.pixels[i * 4 + 1] > 0.0f ? 1 : 0;
    }
    CHECK(valid > still.gradientsRaw.pixelCount() / 2);

    Scene sw = LoadBuiltin("light_switch");
    auto meanGradient = [&](uint32_t frame) {
        p.frameIndex = frame;
        FrameData f = Render(sw, p);
        double sum = 0.0;
        for (size_t i = 0; i < f.gradients.pixelCount(); i++)
            sum += f.gradients.pixels[i * 2];
        return sum / double(f.gradients.pixelCount());
    };
    double steady = meanGradient(10);
    double switchOff = meanGradient(16);
    double stillOff = meanGradient(20);
    double switchOn = meanGradient(24);
    CHECK(steady == 0.0);
    CHECK(stillOff == 0.0);
    CHECK(switchOff > 0.1); // most of the image was lit by the lamp (direct light)
    CHECK(switchOn > 0.1);

    // A moving light changes the lighting of most surfaces every frame; a moving camera alone
    // does not change diffuse lighting.
    double moving = 0.0;
    {
        p.frameIndex = 9;
        FrameData f = Render(LoadBuiltin("moving_light"), p);
        for (size_t i = 0; i < f.gradients.pixelCount(); i++)
            moving += f.gradients.pixels[i * 2];
        moving /= double(f.gradients.pixelCount());
    }
    CHECK(moving > 0.01);

    // Camera motion alone: the same surface, light sample and random numbers give the same
    // diffuse value (diffuse does not depend on the view), so its gradients are exactly 0.
    p.frameIndex = 20;
    FrameData pan = Render(LoadBuiltin("camera_translation"), p);
    uint32_t reprojected = 0;
    for (size_t i = 0; i < pan.gradientsRaw.pixelCount(); i++)
    {
        CHECK(pan.gradientsRaw.pixels[i * 4 + 0] == 0.0f);
        reprojected += pan.gradientsRaw.pixels[i * 4 + 1] > 0.0f ? 1 : 0;
    }
    CHECK(reprojected > pan.gradientsRaw.pixelCount() / 2);
}

TEST_CASE("bounce count and direct light select different estimators", "[scenelab][vulkan]")
{
    Scene scene = LoadBuiltin("static");
    RenderParams p;
    p.width = 32;
    p.height = 32;
    p.truthSpp = 2;
    p.signals = SIGNAL_DIFFUSE | SIGNAL_SPECULAR;
    FrameData base = Render(scene, p);
    p.bounces = 2;
    FrameData twoBounces = Render(scene, p);
    p.bounces = 1;
    p.directLighting = false;
    FrameData indirectOnly = Render(scene, p);
    for (const FrameData* f : {&base, &twoBounces, &indirectOnly})
    {
        CHECK(AllFinite(f->diffuse));
        CHECK(AllFinite(f->specularTruth));
    }
    CHECK(HashImage(base.diffuse) != HashImage(twoBounces.diffuse));
    CHECK(HashImage(base.diffuse) != HashImage(indirectOnly.diffuse));
    // Direct sunlight makes the lit floor much brighter than its indirect light alone.
    double withDirect = 0.0, without = 0.0;
    for (size_t i = 0; i < base.diffuseTruth.pixelCount(); i++)
    {
        withDirect += base.diffuseTruth.pixels[i * 4];
        without += indirectOnly.diffuseTruth.pixels[i * 4];
    }
    CHECK(withDirect > 1.5 * without);
}

TEST_CASE("the ground truth converges: K spp against many more", "[scenelab][vulkan]")
{
    // relMSE (eps 0.01) of the truth at K spp against an independent 1024 spp reference.
    Scene scene = LoadBuiltin("static");
    RenderParams p;
    p.width = 48;
    p.height = 48;
    p.signals = SIGNAL_SHADOW | SIGNAL_DIFFUSE;
    p.truthChunkSpp = 64;
    p.seed = 11;
    p.truthSpp = 64;
    FrameData k64 = Render(scene, p);
    p.truthSpp = 256;
    FrameData k256 = Render(scene, p);
    p.seed = 12;
    p.truthSpp = 1024;
    FrameData ref = Render(scene, p);

    double shadow64 = RelMSE(k64.shadowTruth, ref.shadowTruth);
    double shadow256 = RelMSE(k256.shadowTruth, ref.shadowTruth);
    double diffuse64 = RelMSE(Channels(k64.diffuseTruth, 0, 3), Channels(ref.diffuseTruth, 0, 3));
    double diffuse256 = RelMSE(Channels(k256.diffuseTruth, 0, 3), Channels(ref.diffuseTruth, 0, 3));
    double shadowNoisy = RelMSE(k64.shadowVisibility, ref.shadowTruth);
    double diffuseNoisy = RelMSE(Channels(k64.diffuse, 0, 3), Channels(ref.diffuseTruth, 0, 3));
    std::printf("truth convergence (static, 48x48, relMSE vs 1024 spp): shadow 1 spp %.5f, 64 spp %.5f, "
                "256 spp %.5f; diffuse 1 spp %.5f, 64 spp %.5f, 256 spp %.5f\n",
                shadowNoisy, shadow64, shadow256, diffuseNoisy, diffuse64, diffuse256);
    CHECK(shadow64 < 0.01);
    CHECK(shadow256 < 0.003);
    CHECK(diffuse256 < 0.01);
    CHECK(shadow256 < shadow64);
    CHECK(diffuse256 < diffuse64);
    CHECK(shadow64 < shadowNoisy / 20);
    CHECK(diffuse64 < diffuseNoisy / 20);
}

TEST_CASE("rendered frames are cached on disk and shared", "[scenelab][vulkan]")
{
    std::string dir = (std::filesystem::temp_directory_path() / "nrdlab-cache-test").string();
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    Scene scene = LoadBuiltin("static");
    RenderParams p;
    p.width = 32;
    p.height = 24;
    p.truthSpp = 4;
    p.signals = SIGNAL_SHADOW | SIGNAL_SPECULAR;
    Lab().SetCacheDirectory(dir);
    FrameData a, b, c;
    std::string error;
    REQUIRE(Lab().Render(scene, p, a, error));
    CHECK_FALSE(a.noisyFromCache);
    CHECK_FALSE(a.truthFromCache);
    REQUIRE(Lab().Render(scene, p, b, error));
    CHECK(b.noisyFromCache);
    CHECK(b.truthFromCache);
    CHECK(HashFrame(a) == HashFrame(b));
    // A method needing only the shadow shares the entries.
    p.signals = SIGNAL_SHADOW;
    REQUIRE(Lab().Render(scene, p, c, error));
    CHECK(c.noisyFromCache);
    CHECK(HashImage(c.shadowTruth) == HashImage(a.shadowTruth));
    CHECK(c.shadowHitMask == a.shadowHitMask);
    Lab().SetCacheDirectory("");
    std::filesystem::remove_all(dir, ec);
}

TEST_CASE("bad render parameters are refused with a message", "[scenelab][vulkan]")
{
    Scene scene = LoadBuiltin("static");
    FrameData f;
    std::string error;
    RenderParams p;
    p.width = 16;
    p.height = 16;
    p.truthSpp = 0;
    p.lightIndex = 3;
    CHECK_FALSE(Lab().Render(scene, p, f, error));
    CHECK(error.find("lightIndex") != std::string::npos);
    p.lightIndex = 0;
    p.bounces = 3;
    CHECK_FALSE(Lab().Render(scene, p, f, error));
    p.bounces = 1;
    p.width = 0;
    CHECK_FALSE(Lab().Render(scene, p, f, error));
    p.width = 16;
    CHECK(Lab().Render(scene, p, f, error));
}

TEST_CASE("the lab is clean under the validation layer", "[scenelab][vulkan]")
{
    nrd::lab::VulkanContext vk;
    nrd::lab::VulkanContextDesc desc;
    desc.enableValidation = true;
    desc.quiet = true;
    REQUIRE(vk.Create(desc) == VK_SUCCESS);
    if (!vk.IsValidationEnabled())
    {
        WARN("VK_LAYER_KHRONOS_validation is not installed; skipped");
        return;
    }
    SceneLab lab(vk);
    REQUIRE(lab.IsValid());
    Scene scene = LoadBuiltin("moving_occluder");
    RenderParams p;
    p.width = 20;
    p.height = 12;
    p.frameIndex = 3;
    p.truthSpp = 3;
    p.truthChunkSpp = 2;
    p.signals = SIGNAL_ALL;
    p.useCache = false;
    FrameData f;
    std::string error;
    REQUIRE(lab.Render(scene, p, f, error));
    p.width = 24; // resize
    REQUIRE(lab.Render(scene, p, f, error));
    CHECK(vk.ValidationMessageCount() == 0);
}

TEST_CASE("the truth of the normalized hit distance matches a closed form between two planes", "[scenelab][vulkan]")
{
    // A floor at y = 0 and (second scene) a ceiling at y = h: every cosine-distributed diffuse ray
    // from either plane hits the other at t = h / cos(theta). With a = h / f (f: the normalization at
    // the pixel's viewZ, roughness 1), the mean of min(t / f, 1) over cos(theta) = sqrt(u), u uniform,
    // is a^2 + 2a(1 - a) = 2a - a^2 for a < 1. Without the ceiling every ray is a miss: exactly 1.
    const float h = 2.0f;
    auto sceneText = [&](bool ceiling) {
        std::string s = R"({"name": "planes", "frames": 1, "seed": 3,
            "camera": {"position": [0.0, 1.0, 0.0], "target": [0.0, 0.2, -1.0], "fov": 60},
            "materials": {"grey": {"albedo": 0.5, "roughness": 1.0}},
            "objects": [{"name": "floor", "type": "plane", "material": "grey"})";
        if (ceiling)
            s += R"(, {"name": "ceiling", "type": "plane", "position": [0.0, 2.0, 0.0], "material": "grey"})";
        s += R"(], "lights": [{"name": "sun", "type": "sun", "direction": [0.3, 1.0, 0.2], "intensity": [1, 1, 1]}]})";
        return s;
    };
    RenderParams p;
    p.width = 32;
    p.height = 32;
    p.truthSpp = 256;
    p.signals = SIGNAL_DIFFUSE | SIGNAL_SPECULAR;
    p.useCache = false;
    const nrd::HitDistanceParameters hd = p.hitDistanceParameters;

    for (bool ceiling : {false, true})
    {
        INFO((ceiling ? "ceiling" : "open sky"));
        Scene scene;
        std::string error;
        REQUIRE(LoadScene(sceneText(ceiling), scene, error));
        FrameData f;
        REQUIRE(Lab().Render(scene, p, f, error));
        double sumError = 0.0, worst = 0.0;
        size_t surfaces = 0;
        for (size_t i = 0; i < f.diffuseTruth.pixelCount(); i++)
        {
            const float z = f.viewZ.pixels[i];
            for (const Image* image : {&f.diffuse, &f.diffuseTruth, &f.specular, &f.specularTruth})
            {
                const float w = image->pixels[i * 4 + 3];
                CHECK((w >= 0.0f && w <= 1.0f));
            }
            if (z >= kSkyViewZ)
            {
                CHECK(f.diffuseTruth.pixels[i * 4 + 3] == 1.0f);
                continue;
            }
            surfaces++;
            double expected = 1.0;
            if (ceiling)
            {
                double norm = (double(hd.A) + std::fabs(double(z)) * double(hd.B)) *
                              (1.0 + (double(hd.C) - 1.0) * std::exp2(double(hd.D)));
                double a = std::min(double(h) / norm, 1.0);
                expected = 2.0 * a - a * a;
            }
            double e = double(f.diffuseTruth.pixels[i * 4 + 3]) - expected;
            sumError += e;
            worst = std::max(worst, std::fabs(e));
            if (!ceiling)
            {
                CHECK(f.diffuse.pixels[i * 4 + 3] == 1.0f); // The noisy input misses too.
                CHECK(f.specular.pixels[i * 4 + 3] == 1.0f);
            }
        }
        REQUIRE(surfaces > 100);
        // 256 samples of a quantity in [0, 1] with a standard deviation below 0.3: per pixel within
        // 0.1 (5 sigma); the mean over the pixels within 0.01 (no bias).
        CHECK(worst < 0.1);
        CHECK(std::fabs(sumError / double(surfaces)) < 0.01);
    }
}
// ------------------------------------------------------------------------------------------------
// Triangle meshes

namespace
{

// A scratch folder for model files written by a test.
std::string MeshScratch()
{
    std::filesystem::path dir = std::filesystem::temp_directory_path() / "nrd_scenelab_mesh_tests";
    std::filesystem::create_directories(dir);
    return dir.string();
}

std::string WriteFile(const std::string& name, const std::string& content)
{
    std::string path = MeshScratch() + "/" + name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
}

std::string MeshSceneText(const std::string& meshObject, const std::string& extra = "")
{
    return R"({ "camera": { "position": [2.0, 1.6, 3.0], "target": [0, 0.2, 0] },
        "lights": [ { "type": "sun", "direction": [0.3, 1, 0.2], "intensity": [2, 2, 2] } ],
        "objects": [ { "type": "plane", "position": [0, -0.5, 0] }, )" +
           meshObject + extra + " ] }";
}

std::string MeshLoadError(const std::string& file)
{
    Scene scene;
    std::string error;
    CHECK_FALSE(LoadScene(MeshSceneText(R"({ "type": "mesh", "file": ")" + file + R"(" })"), scene, error));
    return error;
}

// The unit cube as an OBJ with one normal per face (flat shading, as the procedural box).
const char* kCubeObj = R"(v -0.5 -0.5 -0.5
v 0.5 -0.5 -0.5
v 0.5 0.5 -0.5
v -0.5 0.5 -0.5
v -0.5 -0.5 0.5
v 0.5 -0.5 0.5
v 0.5 0.5 0.5
v -0.5 0.5 0.5
vn 1 0 0
vn -1 0 0
vn 0 1 0
vn 0 -1 0
vn 0 0 1
vn 0 0 -1
f 2//1 3//1 7//1 6//1
f 1//2 5//2 8//2 4//2
f 4//3 8//3 7//3 3//3
f 1//4 2//4 6//4 5//4
f 5//5 6//5 7//5 8//5
f 1//6 4//6 3//6 2//6
)";

const std::string kEngine = "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

// Rays from a sphere around the model towards random points inside its bounds (most hit), every
// 4th one short (tMax inside the model). Deterministic.
std::vector<SceneLab::MeshRay> RandomMeshRays(const MeshData& mesh, int rayNum)
{
    const glm::vec3 centre = 0.5f * (mesh.boundsMin + mesh.boundsMax);
    const float radius = glm::length(mesh.boundsMax - mesh.boundsMin);
    uint32_t rng = 12345u;
    auto next = [&]()
    {
        rng = rng * 1664525u + 1013904223u;
        return float(rng >> 8) / 16777216.0f;
    };
    std::vector<SceneLab::MeshRay> rays(static_cast<size_t>(rayNum));
    for (int r = 0; r < rayNum; r++)
    {
        glm::vec3 dir = glm::normalize(glm::vec3(next() - 0.5f, next() - 0.5f, next() - 0.5f) + 1e-6f);
        rays[size_t(r)].origin = centre - dir * radius;
        glm::vec3 target = mesh.boundsMin + (mesh.boundsMax - mesh.boundsMin) * glm::vec3(next(), next(), next());
        rays[size_t(r)].direction = glm::normalize(target - rays[size_t(r)].origin);
        rays[size_t(r)].tMax = r % 4 == 3 ? radius * next() * 1.5f : 1e30f;
    }
    return rays;
}

} // namespace

TEST_CASE("bad model files give an error naming the file, never a crash", "[scenelab][mesh]")
{
    std::string error = MeshLoadError("no/such/model.glb");
    CHECK(error.find("objects[1].file") != std::string::npos);
    CHECK(error.find("model.glb") != std::string::npos);
    CHECK(error.find("no such file") != std::string::npos);

    // Truncated: the first half of a valid binary glTF.
    std::string engine = ReadText(GetModelsDirectory() + "/" + kEngine);
    REQUIRE(engine.size() > 1000);
    std::string truncated = WriteFile("truncated.glb", engine.substr(0, engine.size() / 2));
    error = MeshLoadError(truncated);
    CHECK(error.find(truncated) != std::string::npos);
    CHECK(error.find("not a readable model") != std::string::npos);

    // Not a model at all.
    std::string garbage;
    for (int i = 0; i < 4096; i++)
        garbage += char((i * 7919 + 13) & 0xff);
    std::string notModel = WriteFile("random.glb", garbage);
    error = MeshLoadError(notModel);
    CHECK(error.find(notModel) != std::string::npos);
    CHECK(error.find("not a readable model") != std::string::npos);

    // Points and lines only.
    std::string lines = WriteFile("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\np 1\n");
    error = MeshLoadError(lines);
    CHECK(error.find(lines) != std::string::npos);
    CHECK(error.find("no triangles") != std::string::npos);

    // Non-finite positions: written here, and the package's own test model with infinities.
    std::string nan = WriteFile("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    error = MeshLoadError(nan);
    CHECK(error.find(nan) != std::string::npos);
    CHECK(error.find("non-finite vertex") != std::string::npos);
    error = MeshLoadError("glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb");
    CHECK(error.find("BoxWithInfinites.glb") != std::string::npos);
    CHECK(error.find("non-finite vertex") != std::string::npos);

    // Schema errors of mesh objects.
    error = LoadError(MeshSceneText(R"({ "type": "mesh" })"));
    CHECK(error.find("objects[1]: missing key \"file\"") != std::string::npos);
    error = LoadError(MeshSceneText(R"({ "type": "mesh", "file": ")" + kEngine + R"(", "scale": -1 })"));
    CHECK(error.find("objects[1].scale") != std::string::npos);
    error = LoadError(MeshSceneText(R"({ "type": "box", "size": 1, "file": "x.obj" })"));
    CHECK(error.find("objects[1].file: not a parameter of a box") != std::string::npos);
}

TEST_CASE("BVH traversal equals brute-force intersection on random rays over a loaded model", "[scenelab][mesh]")
{
    for (const std::string& file : {kEngine, std::string("OBJ/spider.obj")})
    {
        MeshData mesh;
        std::string error;
        INFO(file << ": " << error);
        REQUIRE(LoadMesh(GetModelsDirectory() + "/" + file, glm::vec3(1.0f), mesh, error));
        REQUIRE(mesh.triangles.size() > 1000);
        CHECK(mesh.depth <= kMaxBvhDepth);
        // Every triangle in exactly one leaf, leaves inside their parents' bounds.
        std::vector<int> seen(mesh.triangles.size(), 0);
        for (const BvhNode& n : mesh.nodes)
            for (uint32_t i = n.first; n.count > 0 && i < n.first + n.count; i++)
                seen[i]++;
        CHECK(std::count(seen.begin(), seen.end(), 1) == ptrdiff_t(seen.size()));

        uint32_t hits = 0;
        const int rayNum = 3000;
        const std::vector<SceneLab::MeshRay> rays = RandomMeshRays(mesh, rayNum);
        for (int r = 0; r < rayNum; r++)
        {
            const SceneLab::MeshRay& ray = rays[size_t(r)];
            MeshHit bvh = IntersectMesh(mesh, ray.origin, ray.direction, 0.0f, ray.tMax, true);
            MeshHit brute = IntersectMesh(mesh, ray.origin, ray.direction, 0.0f, ray.tMax, false);
            INFO("ray " << r);
            REQUIRE(bvh.triangle == brute.triangle);
            if (brute.triangle >= 0)
            {
                hits++;
                CHECK(bvh.t == brute.t);
            }
        }
        CHECK(hits > rayNum / 4);
    }
}

TEST_CASE("the GPU BVH traversal hits the triangle a CPU brute force hits on random rays over a real model",
          "[scenelab][mesh][vulkan]")
{
    Scene scene = LoadBuiltin("mesh_engine");
    uint32_t engine = 0;
    while (engine < scene.objects.size() && scene.objects[engine].type != PrimitiveType::MESH)
        engine++;
    REQUIRE(engine < scene.objects.size());
    const MeshData& mesh = *scene.objects[engine].mesh;
    REQUIRE(mesh.triangles.size() > 100000);

    // Closest-hit rays, and every 8th one any-hit (what shadow rays ask).
    const int rayNum = 2048;
    std::vector<SceneLab::MeshRay> rays = RandomMeshRays(mesh, rayNum);
    for (int r = 5; r < rayNum; r += 8)
        rays[size_t(r)].anyHit = true;
    std::vector<MeshHit> gpu;
    std::string error;
    INFO(error);
    REQUIRE(Lab().TraceMeshRays(scene, engine, rays, gpu, error));
    REQUIRE(gpu.size() == rays.size());

    uint32_t hits = 0, anyHits = 0;
    for (int r = 0; r < rayNum; r++)
    {
        const SceneLab::MeshRay& ray = rays[size_t(r)];
        const MeshHit& g = gpu[size_t(r)];
        const MeshHit brute = IntersectMesh(mesh, ray.origin, ray.direction, 0.0f, ray.tMax, false);
        INFO("ray " << r << (ray.anyHit ? " (any hit)" : "") << ": GPU triangle " << g.triangle << " t " << g.t
                    << ", CPU triangle " << brute.triangle << " t " << brute.t);
        REQUIRE((g.triangle >= 0) == (brute.triangle >= 0));
        if (brute.triangle < 0)
            continue;
        REQUIRE(size_t(g.triangle) < mesh.triangles.size());
        if (ray.anyHit)
        {
            // Any triangle on the ray before tMax will do: the one reported must be hit at its t.
            MeshData one;
            one.triangles = {mesh.triangles[size_t(g.triangle)]};
            const MeshHit check = IntersectMesh(one, ray.origin, ray.direction, 0.0f, ray.tMax, false);
            REQUIRE(check.triangle == 0);
            CHECK(std::fabs(g.t - check.t) <= 1e-5f * check.t);
            anyHits++;
            continue;
        }
        // The same triangle, t and barycentrics to float rounding (the device may fuse multiply-adds).
        REQUIRE(g.triangle == brute.triangle);
        CHECK(std::fabs(g.t - brute.t) <= 1e-5f * brute.t);
        CHECK(std::fabs(g.u - brute.u) <= 1e-4f);
        CHECK(std::fabs(g.v - brute.v) <= 1e-4f);
        hits++;
    }
    CHECK(hits > uint32_t(rayNum) / 4);
    CHECK(anyHits > uint32_t(rayNum) / 32);

    // Not a mesh: refused with a message.
    CHECK_FALSE(Lab().TraceMeshRays(scene, engine == 0 ? 1 : 0, rays, gpu, error));
    CHECK(error.find("is not a mesh") != std::string::npos);
}

TEST_CASE("a mesh and the equivalent procedural box render the same G-buffer", "[scenelab][mesh][vulkan]")
{
    // The same unit cube, spinning and moving, as a box and as a mesh; a floor under both.
    const std::string motion = R"(, "position": [0, 0.1, 0], "rotation": [10, 20, 0], "material": { "albedo": 0.6 },
        "keyframes": [ { "frame": 0, "position": [-0.3, 0.1, 0], "rotation": [10, 0, 5] },
                       { "frame": 20, "position": [0.3, 0.2, 0.1], "rotation": [30, 80, 10] } ] })";
    const std::string cube = WriteFile("cube.obj", kCubeObj);
    Scene boxScene, meshScene;
    std::string error;
    INFO(error);
    REQUIRE(LoadScene(MeshSceneText(R"({ "type": "box", "size": 1)" + motion), boxScene, error));
    REQUIRE(LoadScene(MeshSceneText(R"({ "type": "mesh", "file": ")" + cube + "\"" + motion), meshScene, error));
    RenderParams p;
    p.width = 64;
    p.height = 64;
    p.frameIndex = 12;
    p.truthSpp = 0;
    p.signals = SIGNAL_SHADOW;
    FrameData box = Render(boxScene, p);
    FrameData mesh = Render(meshScene, p);

    // Triangle edges and box edges are computed differently: a pixel centre within a rounding
    // error of an edge may fall on either side. Everything else must agree to float precision.
    uint32_t differ = 0, cubePixels = 0;
    for (uint32_t y = 0; y < p.height; y++)
        for (uint32_t x = 0; x < p.width; x++)
        {
            cubePixels += box.objectIndex.at(x, y, 0) == 1.0f ? 1 : 0;
            bool same = box.objectIndex.at(x, y, 0) == mesh.objectIndex.at(x, y, 0) &&
                        std::fabs(box.viewZ.at(x, y, 0) - mesh.viewZ.at(x, y, 0)) <= 1e-4f * box.viewZ.at(x, y, 0) &&
                        box.shadowVisibility.at(x, y, 0) == mesh.shadowVisibility.at(x, y, 0);
            for (uint32_t c = 0; c < 4 && same; c++)
                same = std::fabs(box.normalRoughness.at(x, y, c) - mesh.normalRoughness.at(x, y, c)) <= 1e-4f;
            for (uint32_t c = 0; c < 3 && same; c++)
                same = std::fabs(box.motion3d.at(x, y, c) - mesh.motion3d.at(x, y, c)) <= 1e-4f &&
                       std::fabs(box.albedo.at(x, y, c) - mesh.albedo.at(x, y, c)) <= 1e-6f;
            for (uint32_t c = 0; c < 2 && same; c++)
                same = std::fabs(box.motion2d.at(x, y, c) - mesh.motion2d.at(x, y, c)) <= 1e-4f;
            differ += same ? 0 : 1;
        }
    CHECK(cubePixels > 300);
    CHECK(differ <= 3);
}

TEST_CASE("the GPU traversal sees what the CPU brute force sees through every pixel", "[scenelab][mesh][vulkan]")
{
    Scene scene = LoadBuiltin("mesh_engine");
    int engine = -1;
    for (size_t i = 0; i < scene.objects.size(); i++)
        if (scene.objects[i].type == PrimitiveType::MESH)
            engine = int(i);
    REQUIRE(engine >= 0);
    const Object& o = scene.objects[size_t(engine)];
    REQUIRE(o.mesh->triangles.size() > 100000);
    RenderParams p;
    p.width = 48;
    p.height = 48;
    p.frameIndex = 5;
    p.truthSpp = 0;
    p.signals = 0;
    FrameData f = Render(scene, p);
    SceneState state = EvaluateScene(scene, p.frameIndex);
    const ObjectState& os = state.objects[size_t(engine)];
    const float* V = f.camera.worldToView;
    const float* P = f.camera.viewToClip;
    uint32_t enginePixels = 0, agree = 0;
    for (uint32_t y = 0; y < p.height; y++)
        for (uint32_t x = 0; x < p.width; x++)
        {
            // The primary ray of LabScene.glsl PrimaryRay, in the engine's object space.
            float ndcX = (x + 0.5f) / p.width * 2.0f - 1.0f, ndcY = (y + 0.5f) / p.height * 2.0f - 1.0f;
            glm::vec3 dv(ndcX / P[0], ndcY / P[5], 1.0f);
            glm::vec3 dir = glm::normalize(glm::vec3(V[0], V[4], V[8]) * dv.x + glm::vec3(V[1], V[5], V[9]) * dv.y +
                                           glm::vec3(V[2], V[6], V[10]) * dv.z);
            glm::vec3 origin(f.camera.position[0], f.camera.position[1], f.camera.position[2]);
            const glm::mat3 localFromWorld = glm::transpose(os.rotation); // a rotation's inverse
            glm::vec3 lo = localFromWorld * (origin - os.position);
            glm::vec3 ld = localFromWorld * dir;
            MeshHit hit = IntersectMesh(*o.mesh, lo, ld, 0.0f, 1e30f, false);
            bool gpuEngine = f.objectIndex.at(x, y, 0) == float(engine);
            if (!gpuEngine && hit.triangle < 0)
                continue;
            // Where the GPU saw the engine, the CPU finds it at the same depth; where the CPU finds it
            // and the GPU saw something else, that must be nearer (the floor does not occlude here).
            enginePixels++;
            float viewZ = hit.triangle >= 0 ? hit.t * glm::dot(dir, glm::vec3(V[2], V[6], V[10])) : -1.0f;
            if (gpuEngine && hit.triangle >= 0 && std::fabs(viewZ - f.viewZ.at(x, y, 0)) <= 1e-3f * viewZ)
                agree++;
        }
    CHECK(enginePixels > p.width * p.height / 8);
    CHECK(agree >= enginePixels - 2);
}

TEST_CASE("surface ids carry the depth each pixel's surface point had on the previous frame", "[scenelab][vulkan]")
{
    Scene scene = LoadBuiltin("camera_translation");
    RenderParams p;
    p.width = 64;
    p.height = 48;
    p.truthSpp = 0;
    p.signals = 0;
    p.frameIndex = 9;
    FrameData prev = Render(scene, p);
    p.frameIndex = 10;
    FrameData cur = Render(scene, p);
    Image ids = SurfaceIds(cur);
    REQUIRE(ids.channels == 3);
    uint32_t checked = 0, close = 0;
    for (uint32_t y = 0; y < p.height; y++)
        for (uint32_t x = 0; x < p.width; x++)
        {
            CHECK(ids.at(x, y, 0) == cur.objectIndex.at(x, y, 0));
            CHECK(ids.at(x, y, 1) == cur.viewZ.at(x, y, 0));
            if (cur.viewZ.at(x, y, 0) >= kSkyViewZ)
                continue;
            // The previous frame's viewZ at the nearest texel of the reprojected position.
            float px = (x + 0.5f + cur.motion2d.at(x, y, 0) * p.width), py = (y + 0.5f + cur.motion2d.at(x, y, 1) * p.height);
            if (px < 1.0f || py < 1.0f || px > p.width - 1.0f || py > p.height - 1.0f)
                continue;
            checked++;
            float zPrev = prev.viewZ.at(uint32_t(px), uint32_t(py), 0);
            close += std::fabs(ids.at(x, y, 2) - zPrev) <= 0.03f * zPrev ? 1 : 0;
        }
    // Away from silhouettes (a nearest texel across an edge) the depths agree.
    CHECK(checked > p.width * p.height / 2);
    CHECK(close >= checked * 9 / 10);
}
