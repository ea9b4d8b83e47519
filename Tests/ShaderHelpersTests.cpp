// The public shader helpers in two languages: Shaders/Include/NRD.glsl and NRD.hlsli must offer the
// same functions and macros and compute the same results. The list of functions is read from
// NRD.glsl itself (every definition whose name does not start with '_'), so a helper added there
// without its HLSL twin fails here. For each helper, one GLSL and one HLSL compute shader (generated
// below, compiled by glslangValidator, HLSL through its front end) evaluate it on the same inputs,
// ordinary and out-of-contract (NaN, Inf, negatives, huge, denormal), on the default Vulkan
// device; the outputs must agree.
#include <catch2/catch.hpp>

#include "RHIVulkan.h"
#include "VulkanTestUtils.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace nrd
{
namespace
{

struct Parameter
{
    std::string qualifier; // "in", "out" or "inout".
    std::string type;      // As written in the source language.
};

struct Function
{
    std::string returnType;
    std::string name;
    std::vector<Parameter> parameters;
};

std::string ReadText(const std::string& path)
{
    std::ifstream file(path, std::ios::binary);
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
}

// Comments and preprocessor lines removed (macros are read separately).
std::string StripCommentsAndDirectives(const std::string& text)
{
    std::string out;
    for (size_t i = 0; i < text.size();)
    {
        if (text.compare(i, 2, "//") == 0)
            i = text.find('\n', i) == std::string::npos ? text.size() : text.find('\n', i);
        else if (text.compare(i, 2, "/*") == 0)
            i = text.find("*/", i) == std::string::npos ? text.size() : text.find("*/", i) + 2;
        else
            out += text[i++];
    }
    std::stringstream lines(out);
    std::string line, result;
    while (std::getline(lines, line))
    {
        size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] != '#')
            result += line;
        result += '\n';
    }
    return result;
}

bool IsIdentifierChar(char c)
{
    return std::isalnum((unsigned char)c) || c == '_';
}

std::vector<std::string> Words(const std::string& text)
{
    std::vector<std::string> words;
    std::string word;
    for (char c : text + " ")
    {
        if (IsIdentifierChar(c))
            word += c;
        else if (!word.empty())
        {
            words.push_back(word);
            word.clear();
        }
    }
    return words;
}

// Public function definitions at file scope, in source order (overloads are separate entries).
std::vector<Function> ParsePublicFunctions(const std::string& source)
{
    std::string text = StripCommentsAndDirectives(source);
    std::vector<Function> functions;
    int depth = 0;
    size_t statementStart = 0;
    for (size_t i = 0; i < text.size(); i++)
    {
        char c = text[i];
        if (c == '{')
            depth++;
        else if (c == '}')
        {
            depth--;
            statementStart = i + 1;
        }
        else if (c == ';' && depth == 0)
            statementStart = i + 1;
        if (c != '(' || depth != 0)
            continue;

        // "<type> <name>(": the last two words before the parenthesis.
        std::vector<std::string> head = Words(text.substr(statementStart, i - statementStart));
        size_t close = text.find(')', i);
        size_t body = text.find_first_not_of(" \t\r\n", close + 1);
        if (head.size() < 2 || close == std::string::npos || body == std::string::npos || text[body] != '{')
            continue;
        Function function;
        function.returnType = head[head.size() - 2];
        function.name = head.back();
        std::stringstream list(text.substr(i + 1, close - i - 1));
        std::string parameter;
        while (std::getline(list, parameter, ','))
        {
            std::vector<std::string> words = Words(parameter);
            if (words.empty() || (words.size() == 1 && words[0] == "void"))
                continue;
            Parameter p;
            p.qualifier = "in";
            size_t w = 0;
            for (; w + 2 < words.size() || (w + 1 < words.size() && words[w] == "const"); w++)
            {
                if (words[w] == "out" || words[w] == "inout")
                    p.qualifier = words[w];
            }
            p.type = words.size() >= 2 ? words[words.size() - 2] : words[0];
            function.parameters.push_back(p);
        }
        if (function.name[0] != '_')
            functions.push_back(function);
        i = close;
    }
    return functions;
}

// Public object-like macros with a value ("#define NAME value", NAME not starting with '_').
std::vector<std::string> ParsePublicMacros(const std::string& source)
{
    std::vector<std::string> macros;
    std::stringstream lines(source);
    std::string line;
    while (std::getline(lines, line))
    {
        std::stringstream words(line);
        std::string directive, name, value;
        words >> directive >> name >> value;
        if (directive == "#define" && !value.empty() && name[0] != '_' && name.find('(') == std::string::npos)
            macros.push_back(name);
    }
    return macros;
}

// A GLSL type in HLSL spelling: vecN -> floatN, matCxR -> floatCxR (m[c] is a vector of R in both).
std::string ToHlslType(const std::string& glsl)
{
    static const std::map<std::string, std::string> vectorBases = {
        {"vec", "float"}, {"ivec", "int"}, {"uvec", "uint"}, {"bvec", "bool"}};
    for (const auto& base : vectorBases)
    {
        if (glsl.size() == base.first.size() + 1 && glsl.compare(0, base.first.size(), base.first) == 0)
            return base.second + glsl.back();
    }
    if (glsl.compare(0, 3, "mat") == 0)
        return glsl.size() == 4 ? "float" + std::string(1, glsl[3]) + "x" + glsl[3] : "float" + glsl.substr(3);
    return glsl;
}

struct TypeShape
{
    char base = 'f';      // 'f' float, 'i' int, 'u' uint, 'b' bool.
    uint32_t columns = 1; // Matrices: m[c][r]; vectors: 1 x rows.
    uint32_t rows = 1;
    bool isMatrix = false;
    bool isVector = false;
    uint32_t Components() const { return columns * rows; }
};

bool ShapeOf(const std::string& glsl, TypeShape& shape)
{
    shape = {};
    if (glsl == "float" || glsl == "int" || glsl == "uint" || glsl == "bool")
    {
        shape.base = glsl[0];
        return true;
    }
    if (glsl.compare(0, 3, "mat") == 0 && (glsl.size() == 4 || glsl.size() == 6))
    {
        shape.isMatrix = true;
        shape.columns = glsl[3] - '0';
        shape.rows = glsl.size() == 4 ? shape.columns : glsl[5] - '0';
        return shape.columns >= 2 && shape.columns <= 4 && shape.rows >= 2 && shape.rows <= 4;
    }
    size_t v = glsl.find("vec");
    if (v != std::string::npos && glsl.size() == v + 4)
    {
        shape.base = v == 0 ? 'f' : glsl[0] == 'b' ? 'b' : glsl[0] == 'i' ? 'i' : 'u';
        shape.isVector = true;
        shape.rows = glsl.back() - '0';
        return shape.rows >= 2 && shape.rows <= 4;
    }
    return false;
}

std::string Signature(const Function& f)
{
    std::string s = f.returnType + " " + f.name + "(";
    for (size_t p = 0; p < f.parameters.size(); p++)
        s += (p ? ", " : "") + (f.parameters[p].qualifier == "in" ? "" : f.parameters[p].qualifier + " ") +
             f.parameters[p].type;
    return s + ")";
}

// The GLSL functions (and macros) that have no twin of the same HLSL signature, one line each.
std::vector<std::string> MissingInHlsl(const std::string& glsl, const std::string& hlsl)
{
    std::vector<std::string> missing;
    std::vector<Function> hlslFunctions = ParsePublicFunctions(hlsl);
    for (const Function& f : ParsePublicFunctions(glsl))
    {
        Function expected = f;
        expected.returnType = ToHlslType(f.returnType);
        for (Parameter& p : expected.parameters)
            p.type = ToHlslType(p.type);
        bool found = false;
        for (const Function& h : hlslFunctions)
            found = found || Signature(h) == Signature(expected);
        if (!found)
            missing.push_back("function " + Signature(expected));
    }
    std::vector<std::string> hlslMacros = ParsePublicMacros(hlsl);
    for (const std::string& m : ParsePublicMacros(glsl))
    {
        if (std::find(hlslMacros.begin(), hlslMacros.end(), m) == hlslMacros.end())
            missing.push_back("macro " + m);
    }
    return missing;
}

constexpr uint32_t kSamples = 64; // Inputs per function = threads of the one workgroup.

// One evaluated helper: where its inputs and outputs live in the buffers.
struct Case
{
    std::string label; // Signature, or "macro NAME".
    const Function* function = nullptr;
    std::vector<TypeShape> parameterShapes;
    TypeShape returnShape;
    bool returns = false;
    uint32_t inputBase = 0, inputStride = 0;
    uint32_t outputBase = 0, outputStride = 0;
};

// Ordinary and out-of-contract values; integers and booleans get small integers.
float InputValue(const TypeShape& shape, uint32_t sample, uint32_t component, std::mt19937& rng)
{
    if (shape.base == 'b')
        return float((sample + component) % 2);
    if (shape.base != 'f')
        return float((sample * 3 + component) % 8);
    static const float special[] = {std::numeric_limits<float>::quiet_NaN(),
                                    INFINITY,
                                    -INFINITY,
                                    0.0f,
                                    -0.0f,
                                    1.0f,
                                    -1.0f,
                                    0.5f,
                                    1e-7f,
                                    65504.0f,
                                    1e5f,
                                    1e30f,
                                    -1e30f,
                                    2.0f,
                                    1e-40f,
                                    0.25f};
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    float pick = unit(rng);
    if (pick < 0.2f)
        return special[rng() % (sizeof(special) / sizeof(special[0]))];
    if (pick < 0.4f)
        return unit(rng) * 100.0f; // Distances, depths.
    return unit(rng) * 5.0f - 2.0f;
}

// "a[c][r]" / "a[r]" / "a" for component k of a value of 'shape'.
std::string ComponentOf(const std::string& name, const TypeShape& shape, uint32_t k)
{
    if (shape.isMatrix)
        return name + "[" + std::to_string(k / shape.rows) + "][" + std::to_string(k % shape.rows) + "]";
    if (shape.isVector)
        return name + "[" + std::to_string(k) + "]";
    return name;
}

// The body of main(), identical in both languages but for type names.
std::string GenerateBody(const std::vector<Case>& cases, bool isHlsl)
{
    auto typeName = [&](const std::string& glsl) { return isHlsl ? ToHlslType(glsl) : glsl; };
    std::string s;
    for (const Case& c : cases)
    {
        s += "    {\n        uint i = " + std::to_string(c.inputBase) + "u + t * " + std::to_string(c.inputStride) +
             "u;\n        uint o = " + std::to_string(c.outputBase) + "u + t * " + std::to_string(c.outputStride) +
             "u;\n";
        if (!c.function) // A macro: up to 4 float components through _Widen.
        {
            s += "        " + typeName("vec4") + " r = _Widen(" + c.label.substr(6) + ");\n";
            for (uint32_t k = 0; k < 4; k++)
                s += "        gOut[o + " + std::to_string(k) + "u] = r[" + std::to_string(k) + "];\n";
            s += "    }\n";
            continue;
        }
        uint32_t in = 0;
        std::string call = c.function->name + "(";
        for (size_t p = 0; p < c.function->parameters.size(); p++)
        {
            const Parameter& parameter = c.function->parameters[p];
            const TypeShape& shape = c.parameterShapes[p];
            std::string name = "a" + std::to_string(p);
            s += "        " + typeName(parameter.type) + " " + name + ";\n";
            for (uint32_t k = 0; k < shape.Components(); k++)
            {
                std::string value = parameter.qualifier == "out" ? "0.0" : "gIn[i + " + std::to_string(in++) + "u]";
                std::string scalar = shape.base == 'f' ? value
                                     : shape.base == 'b'
                                         ? "(" + value + " > 0.5)"
                                         : std::string(shape.base == 'i' ? "int" : "uint") + "(" + value + ")";
                s += "        " + ComponentOf(name, shape, k) + " = " + scalar + ";\n";
            }
            call += (p ? ", " : "") + name;
        }
        call += ")";
        s += c.returns ? "        " + typeName(c.function->returnType) + " r = " + call + ";\n"
                       : "        " + call + ";\n";

        uint32_t out = 0;
        auto store = [&](const std::string& name, const TypeShape& shape)
        {
            for (uint32_t k = 0; k < shape.Components(); k++)
            {
                std::string value = ComponentOf(name, shape, k);
                value = shape.base == 'b' ? "(" + value + " ? 1.0 : 0.0)" : "float(" + value + ")";
                s += "        gOut[o + " + std::to_string(out++) + "u] = " + value + ";\n";
            }
        };
        if (c.returns)
            store("r", c.returnShape);
        for (size_t p = 0; p < c.function->parameters.size(); p++)
        {
            if (c.function->parameters[p].qualifier != "in")
                store("a" + std::to_string(p), c.parameterShapes[p]);
        }
        s += "    }\n";
    }
    return s;
}

std::string GenerateGlsl(const std::vector<Case>& cases)
{
    return "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"NRD.glsl\"\n"
           "layout(local_size_x = " +
           std::to_string(kSamples) +
           ") in;\n"
           "layout(set = 0, binding = 0) readonly buffer Inputs { float gIn[]; };\n"
           "layout(set = 0, binding = 1) buffer Outputs { float gOut[]; };\n"
           "vec4 _Widen(float v) { return vec4(v, 0.0, 0.0, 0.0); }\n"
           "vec4 _Widen(vec2 v) { return vec4(v, 0.0, 0.0); }\n"
           "vec4 _Widen(vec3 v) { return vec4(v, 0.0); }\n"
           "vec4 _Widen(vec4 v) { return v; }\n"
           "void main()\n{\n    uint t = gl_GlobalInvocationID.x;\n" +
           GenerateBody(cases, false) + "}\n";
}

std::string GenerateHlsl(const std::vector<Case>& cases)
{
    return "#include \"NRD.hlsli\"\n"
           "[[vk::binding(0, 0)]] StructuredBuffer<float> gIn;\n"
           "[[vk::binding(1, 0)]] RWStructuredBuffer<float> gOut;\n"
           "float4 _Widen(float v) { return float4(v, 0.0, 0.0, 0.0); }\n"
           "float4 _Widen(float2 v) { return float4(v, 0.0, 0.0); }\n"
           "float4 _Widen(float3 v) { return float4(v, 0.0); }\n"
           "float4 _Widen(float4 v) { return v; }\n"
           "[numthreads(" +
           std::to_string(kSamples) +
           ", 1, 1)]\nvoid main(uint3 id : SV_DispatchThreadID)\n{\n"
           "    uint t = id.x;\n" +
           GenerateBody(cases, true) + "}\n";
}

// Compiles 'source' (written to 'path') to SPIR-V words; 'log' receives glslang's output on failure.
bool Compile(const std::string& path, const std::string& source, bool isHlsl, std::vector<uint32_t>& words,
             std::string& log)
{
    std::ofstream(path, std::ios::binary) << source;
    std::string spv = path + ".spv", output = path + ".log";
    std::string command = std::string("\"") + NRD_GLSLANG + "\" -V --target-env vulkan1.1 -S comp " +
                          (isHlsl ? "-D -e main " : "") + "-I\"" + NRD_SOURCE_DIR + "/Shaders/Include\" -o \"" + spv +
                          "\" \"" + path + "\" > \"" + output + "\" 2>&1";
    // glslang and the shell run without the sanitizer runtime a sanitized test build preloads.
    unsetenv("LD_PRELOAD");
    int rc = std::system(command.c_str());
    log = ReadText(output);
    std::string bytes = ReadText(spv);
    if (rc != 0 || bytes.size() < 20 || bytes.size() % 4 != 0)
        return false;
    words.resize(bytes.size() / 4);
    std::memcpy(words.data(), bytes.data(), bytes.size());
    return true;
}

// Runs one shader (set 0: binding 0 inputs, binding 1 outputs) as one workgroup, through the
// shared buffer-shader runner (one case: a single group).
std::vector<float> Run(lab::VulkanContext& context, const std::vector<uint32_t>& spirv,
                       const std::vector<float>& inputs, uint32_t outputsNum)
{
    return nrd::test::RunBufferShader(context, spirv.data(), spirv.size() * sizeof(uint32_t), "shader helpers", inputs, outputsNum, 1);
}

bool Agree(float a, float b)
{
    if (std::isnan(a) || std::isnan(b))
        return std::isnan(a) && std::isnan(b);
    if (std::isinf(a) || std::isinf(b))
        return a == b;
    return std::fabs(a - b) <= 1e-6f + 1e-6f * std::fmax(std::fabs(a), std::fabs(b));
}

const std::string kGlslPath = std::string(NRD_SOURCE_DIR) + "/Shaders/Include/NRD.glsl";
const std::string kHlslPath = std::string(NRD_SOURCE_DIR) + "/Shaders/Include/NRD.hlsli";

} // namespace

TEST_CASE("The public helper list is read from NRD.glsl's definitions", "[shaders]")
{
    std::vector<Function> functions = ParsePublicFunctions(ReadText(kGlslPath));
    std::vector<std::string> signatures;
    for (const Function& f : functions)
        signatures.push_back(Signature(f));
    // Helpers the input conventions of the README name; private ones ('_') are not listed.
    CHECK(std::count(signatures.begin(), signatures.end(), "vec4 NRD_FrontEnd_PackNormalAndRoughness(vec3, float)") ==
          1);
    CHECK(std::count(signatures.begin(), signatures.end(), "vec2 SIGMA_FrontEnd_PackShadow(float, float, float)") == 1);
    CHECK(std::count(signatures.begin(), signatures.end(),
                     "vec2 SIGMA_FrontEnd_PackShadow(float, float, float, vec3, out vec4)") == 1);
    CHECK(std::count(signatures.begin(), signatures.end(),
                     "void SIGMA_FrontEnd_MultiLightUpdate(vec3, float, float, float, inout mat2x3)") == 1);
    for (const Function& f : functions)
        CHECK(f.name[0] != '_');
    std::vector<std::string> macros = ParsePublicMacros(ReadText(kGlslPath));
    CHECK(std::count(macros.begin(), macros.end(), "NRD_FP16_MAX") == 1);
    CHECK(std::count(macros.begin(), macros.end(), "NRD_GLSL") == 0); // Include guard: no value.
}

TEST_CASE("A helper missing from NRD.hlsli, or with another signature, is reported", "[shaders]")
{
    const std::string glsl = "#define NRD_X 1.0\nfloat _P(float a) { return a; }\n"
                             "vec2 NRD_A(float a, vec3 b, out vec4 c) { c = vec4(0.0); return b.xy * a; }\n"
                             "void NRD_B(inout mat2x3 m) { m[0] += 1.0; }\n";
    const std::string complete =
        "#define NRD_X 1.0\nfloat2 NRD_A(float a, float3 b, out float4 c) { c = 0; return b.xy * a; }\n"
        "void NRD_B(inout float2x3 m)\n{\n    m[0] += 1.0;\n}\n";
    CHECK(MissingInHlsl(glsl, complete).empty());
    std::vector<std::string> missing = MissingInHlsl(glsl, "float2 NRD_A(float a, float3 b, float4 c) { return 0; }\n");
    REQUIRE(missing.size() == 3);
    CHECK(missing[0] == "function float2 NRD_A(float, float3, out float4)");
    CHECK(missing[1] == "function void NRD_B(inout float2x3)");
    CHECK(missing[2] == "macro NRD_X");
}

TEST_CASE("NRD.hlsli has every public helper and macro of NRD.glsl", "[shaders]")
{
    std::vector<std::string> missing = MissingInHlsl(ReadText(kGlslPath), ReadText(kHlslPath));
    for (const std::string& m : missing)
        UNSCOPED_INFO("NRD.hlsli lacks " << m);
    CHECK(missing.empty());
}

TEST_CASE("NRD.glsl and NRD.hlsli agree on the GPU, ordinary and out-of-contract inputs", "[shaders]")
{
    std::string glslSource = ReadText(kGlslPath);
    std::vector<Function> functions = ParsePublicFunctions(glslSource);
    REQUIRE(!functions.empty());

    // Buffer layout: per helper, kSamples consecutive records of its inputs / outputs.
    std::vector<Case> cases;
    uint32_t inputsNum = 0, outputsNum = 0;
    for (const Function& f : functions)
    {
        Case c;
        c.label = Signature(f);
        c.function = &f;
        c.returns = f.returnType != "void";
        INFO(c.label);
        REQUIRE((!c.returns || ShapeOf(f.returnType, c.returnShape)));
        for (const Parameter& p : f.parameters)
        {
            TypeShape shape;
            REQUIRE(ShapeOf(p.type, shape));
            c.parameterShapes.push_back(shape);
            c.inputStride += p.qualifier == "out" ? 0 : shape.Components();
            c.outputStride += p.qualifier == "in" ? 0 : shape.Components();
        }
        c.outputStride += c.returns ? c.returnShape.Components() : 0;
        c.inputBase = inputsNum;
        c.outputBase = outputsNum;
        inputsNum += c.inputStride * kSamples;
        outputsNum += c.outputStride * kSamples;
        cases.push_back(c);
    }
    for (const std::string& macro : ParsePublicMacros(glslSource))
    {
        Case c;
        c.label = "macro " + macro;
        c.outputStride = 4;
        c.outputBase = outputsNum;
        outputsNum += 4 * kSamples;
        cases.push_back(c);
    }

    std::mt19937 rng(1800);
    std::vector<float> inputs(inputsNum);
    for (const Case& c : cases)
    {
        for (uint32_t s = 0; s < kSamples && c.function; s++)
        {
            uint32_t at = c.inputBase + s * c.inputStride;
            for (size_t p = 0; p < c.function->parameters.size(); p++)
            {
                if (c.function->parameters[p].qualifier == "out")
                    continue;
                for (uint32_t k = 0; k < c.parameterShapes[p].Components(); k++)
                    inputs[at++] = InputValue(c.parameterShapes[p], s, k, rng);
            }
        }
    }

    std::string workDir = NRD_TEST_WORK_DIR;
    std::vector<uint32_t> glslSpirv, hlslSpirv;
    std::string log;
    bool compiled = Compile(workDir + "/NRDHelpers.comp", GenerateGlsl(cases), false, glslSpirv, log);
    INFO("glslangValidator, GLSL:\n" << log);
    REQUIRE(compiled);
    compiled = Compile(workDir + "/NRDHelpers.hlsl", GenerateHlsl(cases), true, hlslSpirv, log);
    INFO("glslangValidator, HLSL (NRD.hlsli must define what NRD.glsl defines):\n" << log);
    REQUIRE(compiled);

    std::unique_ptr<lab::VulkanContext> context = test::CreateValidatedContext();
    REQUIRE(context);
    std::vector<float> glsl = Run(*context, glslSpirv, inputs, outputsNum);
    std::vector<float> hlsl = Run(*context, hlslSpirv, inputs, outputsNum);

    size_t mismatches = 0;
    for (const Case& c : cases)
    {
        for (uint32_t s = 0; s < kSamples; s++)
        {
            for (uint32_t k = 0; k < c.outputStride; k++)
            {
                uint32_t at = c.outputBase + s * c.outputStride + k;
                if (Agree(glsl[at], hlsl[at]))
                    continue;
                if (mismatches++ < 10)
                {
                    std::string args;
                    for (uint32_t a = 0; a < c.inputStride; a++)
                        args += (a ? ", " : "") + std::to_string(inputs[c.inputBase + s * c.inputStride + a]);
                    UNSCOPED_INFO(c.label << ", inputs (" << args << "), output " << k << ": GLSL " << glsl[at]
                                          << ", HLSL " << hlsl[at]);
                }
            }
        }
    }
    CHECK(mismatches == 0);
    CHECK(context->ValidationMessageCount() == 0);
}

} // namespace nrd
