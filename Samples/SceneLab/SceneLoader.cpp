// SceneLoader.cpp - strict JSON scene loading (schema: Samples/Scenes/README.md).
//
// Every error names the JSON path of the offending value; unknown keys are errors (with a
// "did you mean" hint for typos). nlohmann::json exceptions never leave this file.
#include "Scene.h"

#include "Mesh.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#ifndef NRDLAB_SCENES_DIR
#  define NRDLAB_SCENES_DIR "Samples/Scenes"
#endif

namespace nrdlab
{

using json = nlohmann::json;

namespace
{

// Short printable form of a JSON value for messages.
std::string Describe(const json& j)
{
    std::string s = j.dump();
    if (s.size() > 40)
        s = s.substr(0, 37) + "...";
    return s;
}

size_t EditDistance(const std::string& a, const std::string& b)
{
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); j++)
        row[j] = j;
    for (size_t i = 1; i <= a.size(); i++)
    {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); j++)
        {
            size_t up = row[j];
            size_t cost = std::tolower((unsigned char)a[i - 1]) == std::tolower((unsigned char)b[j - 1]) ? 0 : 1;
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + cost});
            diag = up;
        }
    }
    return row[b.size()];
}

// Walks a parsed document, recording the first error. Every Read* returns false after an error.
class Reader
{
public:
    std::string error;
    std::string sceneDirectory; // Of the scene file ("" for JSON text): relative model paths start here.

    bool Fail(const std::string& path, const std::string& message)
    {
        if (error.empty())
            error = path + ": " + message;
        return false;
    }

    // 'obj' must be an object whose keys are all in 'allowed'.
    bool CheckObject(const json& obj, const std::string& path, std::initializer_list<const char*> allowed)
    {
        if (!obj.is_object())
            return Fail(path, "expected an object, got " + Describe(obj));
        for (auto it = obj.begin(); it != obj.end(); ++it)
        {
            const std::string& key = it.key();
            bool known = key == "comment";
            for (const char* a : allowed)
                known = known || key == a;
            if (known)
                continue;
            std::string best;
            size_t bestDistance = 3;
            std::string list;
            for (const char* a : allowed)
            {
                size_t d = EditDistance(key, a);
                if (d < bestDistance)
                {
                    bestDistance = d;
                    best = a;
                }
                list += list.empty() ? a : std::string(", ") + a;
            }
            std::string message = "unknown key";
            if (!best.empty())
                message += " (did you mean \"" + best + "\"?)";
            else
                message += " (expected one of: " + list + ")";
            return Fail(Join(path, key), message);
        }
        if (obj.contains("comment") && !obj["comment"].is_string())
            return Fail(Join(path, "comment"), "expected a string, got " + Describe(obj["comment"]));
        return true;
    }

    static std::string Join(const std::string& path, const std::string& key)
    {
        return path.empty() ? key : path + "." + key;
    }

    static std::string Index(const std::string& path, size_t i)
    {
        return path + "[" + std::to_string(i) + "]";
    }

    bool Number(const json& j, const std::string& path, float lo, float hi, float& out, bool exclusiveLo = false)
    {
        std::ostringstream s;
        s << "number ";
        if (std::isinf(hi))
            s << (exclusiveLo ? "> " : ">= ") << lo;
        else
            s << "in " << (exclusiveLo ? "(" : "[") << lo << ", " << hi << "]";
        std::string expect = s.str();
        if (!j.is_number())
            return Fail(path, "expected " + expect + ", got " + Describe(j));
        double v = j.get<double>();
        if (!std::isfinite(v) || v < lo || v > hi || (exclusiveLo && v <= lo))
            return Fail(path, "expected " + expect + ", got " + Describe(j));
        out = float(v);
        return true;
    }

    bool Uint(const json& j, const std::string& path, uint32_t lo, uint32_t hi, uint32_t& out)
    {
        std::string expect = "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        if (!j.is_number_integer() && !(j.is_number_float() && std::floor(j.get<double>()) == j.get<double>()))
            return Fail(path, "expected " + expect + ", got " + Describe(j));
        double v = j.get<double>();
        if (v < lo || v > hi)
            return Fail(path, "expected " + expect + ", got " + Describe(j));
        out = uint32_t(v);
        return true;
    }

    bool Bool(const json& j, const std::string& path, bool& out)
    {
        if (!j.is_boolean())
            return Fail(path, "expected true or false, got " + Describe(j));
        out = j.get<bool>();
        return true;
    }

    bool String(const json& j, const std::string& path, std::string& out)
    {
        if (!j.is_string())
            return Fail(path, "expected a string, got " + Describe(j));
        out = j.get<std::string>();
        return true;
    }

    // [x, y, z] with each component in [lo, hi]; a single number means (v, v, v) if 'allowScalar'.
    bool Vec3(const json& j, const std::string& path, float lo, float hi, bool allowScalar, glm::vec3& out)
    {
        const char* what = allowScalar ? "an array of 3 numbers or a number" : "an array of 3 numbers";
        if (allowScalar && j.is_number())
        {
            float v = 0.0f;
            if (!Number(j, path, lo, hi, v))
                return false;
            out = {v, v, v};
            return true;
        }
        if (!j.is_array() || j.size() != 3)
            return Fail(path, std::string("expected ") + what + ", got " + Describe(j));
        float v[3] = {};
        for (size_t i = 0; i < 3; i++)
            if (!Number(j[i], Index(path, i), lo, hi, v[i]))
                return false;
        out = {v[0], v[1], v[2]};
        return true;
    }

    bool NonZero(const glm::vec3& v, const std::string& path)
    {
        if (v.x * v.x + v.y * v.y + v.z * v.z < 1e-12f)
            return Fail(path, "expected a non-zero vector");
        return true;
    }
};

constexpr float kInf = INFINITY;
constexpr float kBig = 1e6f; // Positions and sizes beyond this are typos, not scenes.

bool ReadMaterial(Reader& r, const json& j, const std::string& path, Material& m)
{
    if (!r.CheckObject(j, path, {"albedo", "roughness", "metalness", "emission"}))
        return false;
    if (j.contains("albedo") && !r.Vec3(j["albedo"], Reader::Join(path, "albedo"), 0.0f, 1.0f, true, m.albedo))
        return false;
    if (j.contains("roughness") && !r.Number(j["roughness"], Reader::Join(path, "roughness"), 0.0f, 1.0f, m.roughness))
        return false;
    if (j.contains("metalness") && !r.Number(j["metalness"], Reader::Join(path, "metalness"), 0.0f, 1.0f, m.metalness))
        return false;
    if (j.contains("emission") && !r.Vec3(j["emission"], Reader::Join(path, "emission"), 0.0f, kBig, true, m.emission))
        return false;
    return true;
}

// Reads the "keyframes" array: checks each entry's keys, 'frame' and ordering, and hands each entry
// to 'readEntry(entry, path, frame)'.
template <class F>
bool ReadKeyframes(Reader& r, const json& parent, const std::string& parentPath,
                   std::initializer_list<const char*> allowed, F readEntry)
{
    if (!parent.contains("keyframes"))
        return true;
    const json& keys = parent["keyframes"];
    std::string path = Reader::Join(parentPath, "keyframes");
    if (!keys.is_array())
        return r.Fail(path, "expected an array of keyframes, got " + Describe(keys));
    int64_t lastFrame = -1;
    for (size_t i = 0; i < keys.size(); i++)
    {
        std::string p = Reader::Index(path, i);
        std::vector<const char*> all(allowed);
        all.push_back("frame");
        const json& k = keys[i];
        if (!k.is_object())
            return r.Fail(p, "expected an object, got " + Describe(k));
        // CheckObject takes an initializer list; emulate with a manual pass.
        for (auto it = k.begin(); it != k.end(); ++it)
        {
            bool known = it.key() == "comment";
            for (const char* a : all)
                known = known || it.key() == a;
            if (!known)
            {
                std::string list;
                for (const char* a : all)
                    list += list.empty() ? a : std::string(", ") + a;
                return r.Fail(Reader::Join(p, it.key()), "unknown key (expected one of: " + list + ")");
            }
        }
        if (!k.contains("frame"))
            return r.Fail(p, "missing key \"frame\"");
        uint32_t frame = 0;
        if (!r.Uint(k["frame"], Reader::Join(p, "frame"), 0, 1000000, frame))
            return false;
        if (int64_t(frame) <= lastFrame)
            return r.Fail(Reader::Join(p, "frame"), "keyframes must have increasing frames, got " +
                                                        std::to_string(frame) + " after " + std::to_string(lastFrame));
        lastFrame = frame;
        if (!readEntry(k, p, frame))
            return false;
    }
    return true;
}

template <class T>
void AddKey(Track<T>& track, uint32_t frame, const T& value)
{
    track.keys.push_back({frame, value});
}

bool ReadSky(Reader& r, const json& j, Sky& sky)
{
    const std::string path = "sky";
    if (j.is_number() || j.is_array())
    {
        glm::vec3 c;
        if (!r.Vec3(j, path, 0.0f, kBig, true, c))
            return false;
        sky.zenith = sky.horizon = sky.ground = c;
        return true;
    }
    if (!r.CheckObject(j, path, {"zenith", "horizon", "ground"}))
        return false;
    if (!j.contains("horizon"))
        return r.Fail(path, "missing key \"horizon\" (or give one colour: \"sky\": [r, g, b])");
    if (!r.Vec3(j["horizon"], "sky.horizon", 0.0f, kBig, true, sky.horizon))
        return false;
    sky.zenith = sky.ground = sky.horizon;
    if (j.contains("zenith") && !r.Vec3(j["zenith"], "sky.zenith", 0.0f, kBig, true, sky.zenith))
        return false;
    if (j.contains("ground") && !r.Vec3(j["ground"], "sky.ground", 0.0f, kBig, true, sky.ground))
        return false;
    return true;
}

bool ReadCamera(Reader& r, const json& j, CameraDesc& cam)
{
    const std::string path = "camera";
    if (!r.CheckObject(j, path, {"position", "target", "up", "fov", "near", "keyframes"}))
        return false;
    for (const char* key : {"position", "target"})
        if (!j.contains(key))
            return r.Fail(path, std::string("missing key \"") + key + "\"");
    cam.up.value = {0, 1, 0};
    cam.fovDeg.value = 60.0f;
    if (!r.Vec3(j["position"], "camera.position", -kBig, kBig, false, cam.position.value) ||
        !r.Vec3(j["target"], "camera.target", -kBig, kBig, false, cam.target.value))
        return false;
    if (j.contains("up") && (!r.Vec3(j["up"], "camera.up", -kBig, kBig, false, cam.up.value) ||
                             !r.NonZero(cam.up.value, "camera.up")))
        return false;
    if (j.contains("fov") && !r.Number(j["fov"], "camera.fov", 0.0f, 179.0f, cam.fovDeg.value, true))
        return false;
    if (j.contains("near") && !r.Number(j["near"], "camera.near", 0.0f, 100.0f, cam.nearZ, true))
        return false;
    return ReadKeyframes(r, j, path, {"position", "target", "up", "fov"},
                         [&](const json& k, const std::string& p, uint32_t frame) {
                             glm::vec3 v;
                             float f = 0.0f;
                             if (k.contains("position"))
                             {
                                 if (!r.Vec3(k["position"], Reader::Join(p, "position"), -kBig, kBig, false, v))
                                     return false;
                                 AddKey(cam.position, frame, v);
                             }
                             if (k.contains("target"))
                             {
                                 if (!r.Vec3(k["target"], Reader::Join(p, "target"), -kBig, kBig, false, v))
                                     return false;
                                 AddKey(cam.target, frame, v);
                             }
                             if (k.contains("up"))
                             {
                                 if (!r.Vec3(k["up"], Reader::Join(p, "up"), -kBig, kBig, false, v) ||
                                     !r.NonZero(v, Reader::Join(p, "up")))
                                     return false;
                                 AddKey(cam.up, frame, v);
                             }
                             if (k.contains("fov"))
                             {
                                 if (!r.Number(k["fov"], Reader::Join(p, "fov"), 0.0f, 179.0f, f, true))
                                     return false;
                                 AddKey(cam.fovDeg, frame, f);
                             }
                             return true;
                         });
}

// A model path as written in a scene -> the file to load (see LoadScene in Scene.h).
std::string ResolveModelPath(const std::string& sceneDirectory, const std::string& file)
{
    std::error_code ec;
    std::filesystem::path p(file);
    if (p.is_absolute())
        return file;
    std::filesystem::path local = sceneDirectory.empty() ? p : std::filesystem::path(sceneDirectory) / p;
    if (std::filesystem::exists(local, ec))
        return local.string();
    std::filesystem::path shared = std::filesystem::path(GetModelsDirectory()) / p;
    if (std::filesystem::exists(shared, ec))
        return shared.string();
    return local.string(); // Missing everywhere: the error names the first place looked at.
}

bool ReadMesh(Reader& r, const json& j, const std::string& path, Object& o)
{
    if (!j.contains("file"))
        return r.Fail(path, "missing key \"file\" (a glTF, OBJ or other model file)");
    if (!r.String(j["file"], Reader::Join(path, "file"), o.file))
        return false;
    if (o.file.empty())
        return r.Fail(Reader::Join(path, "file"), "empty path");
    if (j.contains("scale"))
    {
        if (!r.Vec3(j["scale"], Reader::Join(path, "scale"), 0.0f, 1e6f, true, o.scale))
            return false;
        if (o.scale.x <= 0.0f || o.scale.y <= 0.0f || o.scale.z <= 0.0f)
            return r.Fail(Reader::Join(path, "scale"), "expected positive scale factors, got " + Describe(j["scale"]));
    }
    std::string error;
    o.mesh = LoadMeshShared(ResolveModelPath(r.sceneDirectory, o.file), glm::vec3(o.scale.x, o.scale.y, o.scale.z),
                            error);
    if (!o.mesh)
        return r.Fail(Reader::Join(path, "file"), error);
    return true;
}

bool ReadObject(Reader& r, const json& j, const std::string& path, const json& materials, Object& o)
{
    if (!r.CheckObject(j, path, {"name", "type", "material", "position", "rotation", "normal", "radius", "size",
                                 "file", "scale", "keyframes"}))
        return false;
    if (j.contains("name") && !r.String(j["name"], Reader::Join(path, "name"), o.name))
        return false;
    if (!j.contains("type"))
        return r.Fail(path, "missing key \"type\" (sphere, box, plane, quad or mesh)");
    std::string type;
    if (!r.String(j["type"], Reader::Join(path, "type"), type))
        return false;
    if (type == "sphere")
        o.type = PrimitiveType::SPHERE;
    else if (type == "box")
        o.type = PrimitiveType::BOX;
    else if (type == "plane")
        o.type = PrimitiveType::PLANE;
    else if (type == "quad")
        o.type = PrimitiveType::QUAD;
    else if (type == "mesh")
        o.type = PrimitiveType::MESH;
    else
        return r.Fail(Reader::Join(path, "type"),
                      "expected \"sphere\", \"box\", \"plane\", \"quad\" or \"mesh\", got " + Describe(j["type"]));

    // Shape parameters: only the ones of this type are accepted.
    auto unexpected = [&](const char* key) {
        return r.Fail(Reader::Join(path, key), std::string("not a parameter of a ") + type);
    };
    if (o.type == PrimitiveType::MESH)
    {
        if (j.contains("size"))
            return unexpected("size");
        if (!ReadMesh(r, j, path, o))
            return false;
    }
    else if (j.contains("file") || j.contains("scale"))
        return unexpected(j.contains("file") ? "file" : "scale");
    if (o.type == PrimitiveType::SPHERE)
    {
        if (j.contains("size"))
            return unexpected("size");
        if (!j.contains("radius"))
            return r.Fail(path, "missing key \"radius\"");
        if (!r.Number(j["radius"], Reader::Join(path, "radius"), 0.0f, kBig, o.radius, true))
            return false;
    }
    else if (j.contains("radius"))
        return unexpected("radius");
    if (o.type == PrimitiveType::BOX)
    {
        if (!j.contains("size"))
            return r.Fail(path, "missing key \"size\"");
        if (!r.Vec3(j["size"], Reader::Join(path, "size"), 0.0f, kBig, true, o.size))
            return false;
        if (o.size.x <= 0.0f || o.size.y <= 0.0f || o.size.z <= 0.0f)
            return r.Fail(Reader::Join(path, "size"), "expected positive extents, got " + Describe(j["size"]));
    }
    if (o.type == PrimitiveType::QUAD)
    {
        const json& s = j.contains("size") ? j["size"] : json();
        if (!j.contains("size"))
            return r.Fail(path, "missing key \"size\"");
        if (!s.is_array() || s.size() != 2)
            return r.Fail(Reader::Join(path, "size"), "expected [width, depth] (2 numbers), got " + Describe(s));
        if (!r.Number(s[0], Reader::Index(Reader::Join(path, "size"), 0), 0.0f, kBig, o.size.x, true) ||
            !r.Number(s[1], Reader::Index(Reader::Join(path, "size"), 1), 0.0f, kBig, o.size.z, true))
            return false;
        o.size.y = 0.0f;
    }
    if (o.type == PrimitiveType::PLANE && j.contains("size"))
        return unexpected("size");
    if (j.contains("normal"))
    {
        if (o.type != PrimitiveType::PLANE && o.type != PrimitiveType::QUAD)
            return unexpected("normal");
        if (j.contains("rotation"))
            return r.Fail(Reader::Join(path, "normal"), "give either \"normal\" or \"rotation\", not both");
    }

    // Material: inline, or the name of an entry of the top-level "materials".
    if (j.contains("material"))
    {
        const json& m = j["material"];
        std::string mp = Reader::Join(path, "material");
        if (m.is_string())
        {
            std::string name = m.get<std::string>();
            if (!materials.is_object() || !materials.contains(name))
                return r.Fail(mp, "no material named " + Describe(m) + " in \"materials\"");
            if (!ReadMaterial(r, materials[name], "materials." + name, o.material))
                return false;
        }
        else if (!ReadMaterial(r, m, mp, o.material))
            return false;
    }

    if (j.contains("position") &&
        !r.Vec3(j["position"], Reader::Join(path, "position"), -kBig, kBig, false, o.position.value))
        return false;
    if (j.contains("rotation") &&
        !r.Vec3(j["rotation"], Reader::Join(path, "rotation"), -36000.0f, 36000.0f, false, o.rotation.value))
        return false;
    if (j.contains("normal"))
    {
        glm::vec3 n;
        if (!r.Vec3(j["normal"], Reader::Join(path, "normal"), -kBig, kBig, false, n) ||
            !r.NonZero(n, Reader::Join(path, "normal")))
            return false;
        // Euler angles (X then Y then Z) that turn +Y into n: tilt about X, then swing about Y.
        float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
        n = {n.x / len, n.y / len, n.z / len};
        const float toDeg = 57.29577951308232f;
        float ax = std::acos(std::max(-1.0f, std::min(1.0f, n.y))) * toDeg; // +Y -> (0, cos, sin) about X
        float ay = std::atan2(n.x, n.z) * toDeg;                             // then swing about Y
        o.rotation.value = {ax, ay, 0.0f};
    }
    return ReadKeyframes(r, j, path, {"position", "rotation"}, [&](const json& k, const std::string& p, uint32_t f) {
        glm::vec3 v;
        if (k.contains("position"))
        {
            if (!r.Vec3(k["position"], Reader::Join(p, "position"), -kBig, kBig, false, v))
                return false;
            AddKey(o.position, f, v);
        }
        if (k.contains("rotation"))
        {
            if (!r.Vec3(k["rotation"], Reader::Join(p, "rotation"), -36000.0f, 36000.0f, false, v))
                return false;
            AddKey(o.rotation, f, v);
        }
        return true;
    });
}

bool ReadLight(Reader& r, const json& j, const std::string& path, Light& l)
{
    if (!r.CheckObject(j, path, {"name", "type", "direction", "position", "angularRadius", "radius", "intensity",
                                 "enabled", "keyframes"}))
        return false;
    if (j.contains("name") && !r.String(j["name"], Reader::Join(path, "name"), l.name))
        return false;
    if (!j.contains("type"))
        return r.Fail(path, "missing key \"type\" (sun, sphere or point)");
    std::string type;
    if (!r.String(j["type"], Reader::Join(path, "type"), type))
        return false;
    if (type == "sun")
        l.type = LightType::SUN;
    else if (type == "sphere")
        l.type = LightType::SPHERE;
    else if (type == "point")
        l.type = LightType::POINT;
    else
        return r.Fail(Reader::Join(path, "type"), "expected \"sun\", \"sphere\" or \"point\", got " +
                                                      Describe(j["type"]));
    auto unexpected = [&](const char* key) {
        return r.Fail(Reader::Join(path, key), "not a parameter of a " + type + " light");
    };
    bool isSun = l.type == LightType::SUN;
    if (isSun)
    {
        if (j.contains("position"))
            return unexpected("position");
        if (j.contains("radius"))
            return unexpected("radius");
        if (!j.contains("direction"))
            return r.Fail(path, "missing key \"direction\" (towards the sun)");
        if (!r.Vec3(j["direction"], Reader::Join(path, "direction"), -kBig, kBig, false, l.direction.value) ||
            !r.NonZero(l.direction.value, Reader::Join(path, "direction")))
            return false;
        if (j.contains("angularRadius") &&
            !r.Number(j["angularRadius"], Reader::Join(path, "angularRadius"), 0.0f, 30.0f, l.angularRadiusDeg))
            return false;
    }
    else
    {
        if (j.contains("direction"))
            return unexpected("direction");
        if (j.contains("angularRadius"))
            return unexpected("angularRadius");
        if (!j.contains("position"))
            return r.Fail(path, "missing key \"position\"");
        if (!r.Vec3(j["position"], Reader::Join(path, "position"), -kBig, kBig, false, l.position.value))
            return false;
        if (l.type == LightType::SPHERE)
        {
            if (!j.contains("radius"))
                return r.Fail(path, "missing key \"radius\"");
            if (!r.Number(j["radius"], Reader::Join(path, "radius"), 0.0f, kBig, l.radius, true))
                return false;
        }
        else if (j.contains("radius"))
            return unexpected("radius");
    }
    l.intensity.value = {1, 1, 1};
    if (j.contains("intensity") &&
        !r.Vec3(j["intensity"], Reader::Join(path, "intensity"), 0.0f, 1e9f, true, l.intensity.value))
        return false;
    if (j.contains("enabled") && !r.Bool(j["enabled"], Reader::Join(path, "enabled"), l.enabled.value))
        return false;

    std::initializer_list<const char*> sunKeys = {"direction", "intensity", "enabled"};
    std::initializer_list<const char*> localKeys = {"position", "intensity", "enabled"};
    return ReadKeyframes(r, j, path, isSun ? sunKeys : localKeys, [&](const json& k, const std::string& p, uint32_t f) {
        glm::vec3 v;
        if (k.contains("direction"))
        {
            if (!r.Vec3(k["direction"], Reader::Join(p, "direction"), -kBig, kBig, false, v) ||
                !r.NonZero(v, Reader::Join(p, "direction")))
                return false;
            AddKey(l.direction, f, v);
        }
        if (k.contains("position"))
        {
            if (!r.Vec3(k["position"], Reader::Join(p, "position"), -kBig, kBig, false, v))
                return false;
            AddKey(l.position, f, v);
        }
        if (k.contains("intensity"))
        {
            if (!r.Vec3(k["intensity"], Reader::Join(p, "intensity"), 0.0f, 1e9f, true, v))
                return false;
            AddKey(l.intensity, f, v);
        }
        if (k.contains("enabled"))
        {
            bool b = true;
            if (!r.Bool(k["enabled"], Reader::Join(p, "enabled"), b))
                return false;
            l.enabled.keys.push_back({f, b});
        }
        return true;
    });
}

bool ReadScene(Reader& r, const json& doc, Scene& s)
{
    if (!r.CheckObject(doc, "(root)", {"name", "description", "frames", "seed", "sky", "camera", "materials",
                                       "objects", "lights"}))
    {
        // Report root-level unknown keys without the "(root)." prefix.
        const std::string prefix = "(root).";
        if (r.error.compare(0, prefix.size(), prefix) == 0)
            r.error = r.error.substr(prefix.size());
        return false;
    }
    if (doc.contains("name") && !r.String(doc["name"], "name", s.name))
        return false;
    if (doc.contains("description") && !r.String(doc["description"], "description", s.description))
        return false;
    if (doc.contains("frames") && !r.Uint(doc["frames"], "frames", 1, 100000, s.frameNum))
        return false;
    if (doc.contains("seed") && !r.Uint(doc["seed"], "seed", 0, 0xFFFFFFFFu, s.seed))
        return false;
    if (doc.contains("sky") && !ReadSky(r, doc["sky"], s.sky))
        return false;
    if (!doc.contains("camera"))
        return r.Fail("camera", "missing (every scene needs a camera)");
    if (!ReadCamera(r, doc["camera"], s.camera))
        return false;

    json materials = json::object();
    if (doc.contains("materials"))
    {
        materials = doc["materials"];
        if (!materials.is_object())
            return r.Fail("materials", "expected an object of named materials, got " + Describe(materials));
        for (auto it = materials.begin(); it != materials.end(); ++it)
        {
            Material unused;
            if (!ReadMaterial(r, it.value(), "materials." + it.key(), unused))
                return false;
        }
    }

    if (!doc.contains("objects"))
        return r.Fail("objects", "missing (an array of objects)");
    const json& objects = doc["objects"];
    if (!objects.is_array())
        return r.Fail("objects", "expected an array, got " + Describe(objects));
    if (objects.size() > kMaxObjects)
        return r.Fail("objects", "at most " + std::to_string(kMaxObjects) + " objects are supported, got " +
                                     std::to_string(objects.size()));
    for (size_t i = 0; i < objects.size(); i++)
    {
        Object o;
        if (!ReadObject(r, objects[i], Reader::Index("objects", i), materials, o))
            return false;
        s.objects.push_back(std::move(o));
    }

    if (doc.contains("lights"))
    {
        const json& lights = doc["lights"];
        if (!lights.is_array())
            return r.Fail("lights", "expected an array, got " + Describe(lights));
        if (lights.size() > kMaxLights)
            return r.Fail("lights", "at most " + std::to_string(kMaxLights) + " lights are supported, got " +
                                        std::to_string(lights.size()));
        for (size_t i = 0; i < lights.size(); i++)
        {
            Light l;
            if (!ReadLight(r, lights[i], Reader::Index("lights", i), l))
                return false;
            s.lights.push_back(std::move(l));
        }
    }
    return true;
}

bool ReadFile(const std::string& path, std::string& text)
{
    std::ifstream f(path, std::ios::binary);
    if (!f)
        return false;
    std::ostringstream ss;
    ss << f.rdbuf();
    text = ss.str();
    return bool(f) || f.eof();
}

} // namespace

std::string GetBuiltinScenesDirectory()
{
    const char* env = std::getenv("NRDLAB_SCENES_DIR");
    return env && *env ? std::string(env) : std::string(NRDLAB_SCENES_DIR);
}

bool IsSceneAnimated(const Scene& scene)
{
    bool animated = !scene.camera.position.keys.empty() || !scene.camera.target.keys.empty() ||
                    !scene.camera.up.keys.empty() || !scene.camera.fovDeg.keys.empty();
    for (const Object& o : scene.objects)
        animated = animated || !o.position.keys.empty() || !o.rotation.keys.empty();
    for (const Light& l : scene.lights)
        animated = animated || !l.direction.keys.empty() || !l.position.keys.empty() || !l.intensity.keys.empty() ||
                   !l.enabled.keys.empty();
    return animated;
}

std::vector<std::string> GetBuiltinSceneNames()
{
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(GetBuiltinScenesDirectory(), ec))
    {
        if (entry.path().extension() == ".json")
            names.push_back(entry.path().stem().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

bool LoadScene(const std::string& pathOrText, Scene& out, std::string& error)
{
    try
    {
        std::string text;
        std::string source; // For messages: the file, or empty for inline text.
        size_t first = pathOrText.find_first_not_of(" \t\r\n");
        if (first != std::string::npos && pathOrText[first] == '{')
            text = pathOrText;
        else
        {
            std::string path = pathOrText;
            std::error_code ec;
            if (!std::filesystem::is_regular_file(path, ec))
            {
                std::string builtin = GetBuiltinScenesDirectory() + "/" + pathOrText + ".json";
                if (pathOrText.find('/') == std::string::npos && std::filesystem::is_regular_file(builtin, ec))
                    path = builtin;
            }
            if (!ReadFile(path, text))
            {
                error = "cannot read scene file '" + pathOrText + "'";
                if (pathOrText.find('/') == std::string::npos && pathOrText.find(".json") == std::string::npos)
                {
                    std::string list;
                    for (const std::string& n : GetBuiltinSceneNames())
                        list += (list.empty() ? "" : ", ") + n;
                    error += " (built-in scenes: " + list + ")";
                }
                return false;
            }
            source = path;
        }

        json doc = json::parse(text, nullptr, false);
        if (doc.is_discarded())
        {
            // Parse again with exceptions for the position of the syntax error.
            try
            {
                json reparsed = json::parse(text);
                (void)reparsed;
            }
            catch (const json::parse_error& e)
            {
                size_t line = 1, column = 1;
                for (size_t i = 0; i + 1 < e.byte && i < text.size(); i++)
                {
                    column++;
                    if (text[i] == '\n')
                    {
                        line++;
                        column = 1;
                    }
                }
                error = (source.empty() ? std::string() : source + ": ") + "JSON syntax error at line " +
                        std::to_string(line) + ", column " + std::to_string(column);
                return false;
            }
            error = "JSON syntax error";
            return false;
        }

        Reader reader;
        if (!source.empty())
            reader.sceneDirectory = std::filesystem::path(source).parent_path().string();
        Scene scene;
        if (!ReadScene(reader, doc, scene))
        {
            error = reader.error;
            return false;
        }
        if (scene.name.empty() && !source.empty())
            scene.name = std::filesystem::path(source).stem().string();
        scene.canonicalJson = doc.dump();
        // A model file edited in place changes the scene: its content is part of the key.
        for (const Object& o : scene.objects)
            if (o.mesh)
                scene.canonicalJson += "|mesh:" + std::to_string(o.mesh->hash);
        out = std::move(scene);
        return true;
    }
    catch (const std::exception& e)
    {
        error = std::string("unexpected error while loading the scene: ") + e.what();
        return false;
    }
}

} // namespace nrdlab
