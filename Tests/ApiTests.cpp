// Core API: descriptions are consistent with themselves and with the SPIR-V; bad input is rejected.
#include <catch2/catch.hpp>

#include "NRD.h"
#include "SpirvReflect.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace
{

struct LogCapture
{
    std::vector<std::string> messages;
    static void Callback(void* user, nrd::LogSeverity, const char* message)
    {
        static_cast<LogCapture*>(user)->messages.push_back(message);
    }
};

// Vulkan-style perspective (y down, clip w = +viewZ) and an identity view.
void FillCamera(nrd::CommonSettings& s)
{
    const float f = 1.0f / std::tan(0.5f * 1.0f), n = 0.1f;
    float p[16] = {};
    p[0] = f;
    p[5] = -f;
    p[10] = 0.0f;
    p[11] = 1.0f;
    p[14] = n;
    float v[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    memcpy(s.viewToClipMatrix, p, sizeof(p));
    memcpy(s.viewToClipMatrixPrev, p, sizeof(p));
    memcpy(s.worldToViewMatrix, v, sizeof(v));
    memcpy(s.worldToViewMatrixPrev, v, sizeof(v));
}

struct Instance
{
    nrd::Denoiser* denoiser = nullptr;
    LogCapture log;
    nrd::Result result = nrd::Result::FAILURE;

    Instance(std::vector<nrd::MethodDesc> methods, uint16_t w = 64, uint16_t h = 48)
    {
        nrd::DenoiserCreationDesc desc;
        desc.methods = methods.data();
        desc.methodsNum = uint32_t(methods.size());
        desc.renderWidth = w;
        desc.renderHeight = h;
        desc.logCallback = LogCapture::Callback;
        desc.logUserArg = &log;
        result = nrd::CreateDenoiser(desc, denoiser);
    }
    ~Instance() { nrd::DestroyDenoiser(denoiser); }
};

std::vector<std::vector<nrd::MethodDesc>> MethodSets()
{
    std::vector<std::vector<nrd::MethodDesc>> sets;
    const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
    std::vector<nrd::MethodDesc> all;
    for (uint32_t i = 0; i < lib.supportedMethodsNum; i++)
    {
        sets.push_back({{7u, lib.supportedMethods[i]}});
        all.push_back({100u + i, lib.supportedMethods[i]});
    }
    // A mix with two instances of the same method (two lights).
    all.push_back({200u, lib.supportedMethods[0]});
    sets.push_back(all);
    return sets;
}

uint32_t RangeDescriptorCount(const nrd::PipelineDesc& p)
{
    uint32_t n = 0;
    for (uint32_t r = 0; r < p.resourceRangesNum; r++)
        n += p.resourceRanges[r].descriptorsNum;
    return n;
}

nrd::DescriptorType RangeTypeOfBinding(const nrd::PipelineDesc& p, uint32_t binding)
{
    for (uint32_t r = 0; r < p.resourceRangesNum; r++)
    {
        const nrd::ResourceRangeDesc& range = p.resourceRanges[r];
        if (binding >= range.baseBinding && binding < range.baseBinding + range.descriptorsNum)
            return range.descriptorType;
    }
    return nrd::DescriptorType::MAX_NUM;
}

std::vector<std::string> DispatchNames(nrd::Denoiser& d, uint32_t frameIndex)
{
    nrd::CommonSettings s;
    FillCamera(s);
    s.frameIndex = frameIndex;
    REQUIRE(nrd::SetCommonSettings(d, s) == nrd::Result::SUCCESS);
    const nrd::DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    REQUIRE(nrd::GetComputeDispatches(d, nullptr, 0, dispatches, num) == nrd::Result::SUCCESS);
    std::vector<std::string> names;
    for (uint32_t i = 0; i < num; i++)
        names.push_back(dispatches[i].name);
    return names;
}

} // namespace

TEST_CASE("Library desc lists every method once and names round-trip", "[api]")
{
    const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
    REQUIRE(lib.supportedMethodsNum == uint32_t(nrd::Method::MAX_NUM));
    CHECK(lib.versionMajor == NRD_VERSION_MAJOR);
    CHECK(lib.versionMinor == NRD_VERSION_MINOR);
    for (uint32_t i = 0; i < lib.supportedMethodsNum; i++)
    {
        nrd::Method m;
        REQUIRE(nrd::GetMethodFromString(nrd::GetMethodString(lib.supportedMethods[i]), m));
        CHECK(m == lib.supportedMethods[i]);
    }
    nrd::Method m;
    CHECK_FALSE(nrd::GetMethodFromString("NOT_A_METHOD", m));
    CHECK_FALSE(nrd::GetMethodFromString(nullptr, m));
    CHECK(std::string(nrd::GetMethodString(nrd::Method(999))) == "UNKNOWN");
    CHECK(std::string(nrd::GetResultString(nrd::Result::NON_UNIQUE_IDENTIFIER)) == "NON_UNIQUE_IDENTIFIER");
    CHECK(nrd::GetFormatBytesPerPixel(nrd::Format::RGBA16_SFLOAT) == 8);
}

TEST_CASE("Pipelines agree with their SPIR-V bindings, block sizes and group sizes", "[api]")
{
    for (const auto& methods : MethodSets())
    {
        Instance inst(methods);
        REQUIRE(inst.result == nrd::Result::SUCCESS);
        const nrd::DenoiserDesc& desc = nrd::GetDenoiserDesc(*inst.denoiser);
        const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
        REQUIRE(desc.pipelinesNum > 0);
        for (uint32_t i = 0; i < desc.pipelinesNum; i++)
        {
            const nrd::PipelineDesc& p = desc.pipelines[i];
            INFO("pipeline " << p.shaderIdentifier);
            REQUIRE(p.spirv.bytecode != nullptr);
            REQUIRE(p.spirv.size % 4 == 0);
            nrdtest::SpirvModule module;
            std::string error;
            REQUIRE(nrdtest::ReflectSpirv(static_cast<const uint32_t*>(p.spirv.bytecode), p.spirv.size / 4, module, error));
            CHECK(module.localSize[0] == p.groupSizeX);
            CHECK(module.localSize[1] == p.groupSizeY);

            uint32_t resourceBindings = 0;
            bool sawConstants = false;
            for (const nrdtest::SpirvBinding& b : module.bindings)
            {
                INFO("binding " << b.name << " set " << b.set << " binding " << b.binding);
                if (b.set == lib.spirvBinding.resourcesSetIndex)
                {
                    resourceBindings++;
                    nrd::DescriptorType t = RangeTypeOfBinding(p, b.binding);
                    switch (b.type)
                    {
                    case nrdtest::SpirvDescriptor::SAMPLED_IMAGE: CHECK(t == nrd::DescriptorType::TEXTURE); break;
                    case nrdtest::SpirvDescriptor::STORAGE_IMAGE: CHECK(t == nrd::DescriptorType::STORAGE_TEXTURE); break;
                    case nrdtest::SpirvDescriptor::READONLY_STORAGE_BUFFER: CHECK(t == nrd::DescriptorType::BUFFER); break;
                    case nrdtest::SpirvDescriptor::STORAGE_BUFFER: CHECK(t == nrd::DescriptorType::STORAGE_BUFFER); break;
                    default: FAIL("unexpected descriptor in the resources set");
                    }
                }
                else
                {
                    REQUIRE(b.set == lib.spirvBinding.constantsSetIndex);
                    if (b.type == nrdtest::SpirvDescriptor::UNIFORM_BUFFER)
                    {
                        sawConstants = true;
                        CHECK(b.binding == lib.spirvBinding.constantBufferBinding);
                        CHECK(b.blockSize == p.constantBufferSize);
                    }
                    else
                    {
                        REQUIRE(b.type == nrdtest::SpirvDescriptor::SAMPLER);
                        CHECK(b.binding >= lib.spirvBinding.samplersBaseBinding);
                        CHECK(b.binding < lib.spirvBinding.samplersBaseBinding + desc.samplersNum);
                    }
                }
            }
            CHECK(sawConstants == p.hasConstantData);
            CHECK(resourceBindings == RangeDescriptorCount(p));
        }
    }
}

TEST_CASE("Every dispatch refers to existing pipelines and pool entries with matching types", "[api]")
{
    for (const auto& methods : MethodSets())
    {
        Instance inst(methods, 67, 33);
        REQUIRE(inst.result == nrd::Result::SUCCESS);
        const nrd::DenoiserDesc& desc = nrd::GetDenoiserDesc(*inst.denoiser);
        for (uint32_t frame = 0; frame < 3; frame++)
        {
            nrd::CommonSettings s;
            FillCamera(s);
            s.frameIndex = frame;
            REQUIRE(nrd::SetCommonSettings(*inst.denoiser, s) == nrd::Result::SUCCESS);
            const nrd::DispatchDesc* dispatches = nullptr;
            uint32_t num = 0;
            REQUIRE(nrd::GetComputeDispatches(*inst.denoiser, nullptr, 0, dispatches, num) == nrd::Result::SUCCESS);
            REQUIRE(num >= methods.size());
            for (uint32_t i = 0; i < num; i++)
            {
                const nrd::DispatchDesc& d = dispatches[i];
                INFO("dispatch " << d.name);
                REQUIRE(d.pipelineIndex < desc.pipelinesNum);
                const nrd::PipelineDesc& p = desc.pipelines[d.pipelineIndex];
                REQUIRE(d.resourcesNum == RangeDescriptorCount(p));
                for (uint32_t r = 0; r < d.resourcesNum; r++)
                {
                    const nrd::ResourceDesc& res = d.resources[r];
                    CHECK(res.descriptorType == RangeTypeOfBinding(p, r));
                    if (res.type == nrd::ResourceType::PERMANENT_POOL)
                        CHECK(res.indexInPool < desc.permanentPoolSize);
                    else if (res.type == nrd::ResourceType::TRANSIENT_POOL)
                        CHECK(res.indexInPool < desc.transientPoolSize);
                    else if (res.type == nrd::ResourceType::BUFFER_POOL)
                        CHECK(res.indexInPool < desc.buffersNum);
                    else
                        CHECK(uint32_t(res.type) < uint32_t(nrd::ResourceType::TRANSIENT_POOL));
                }
                CHECK(d.constantBufferDataSize == (p.hasConstantData ? p.constantBufferSize : 0u));
                CHECK(d.constantBufferDataSize <= desc.constantBufferMaxDataSize);
                CHECK((d.constantBufferDataSize == 0) == (d.constantBufferData == nullptr));
                CHECK(d.gridWidth > 0);
                CHECK(d.gridHeight > 0);
                // Direct grids cover the image; indirect ones (a list of tiles) never more threads than it.
                if (d.isIndirect)
                    CHECK(uint64_t(d.gridWidth) * d.gridHeight * p.groupSizeX * p.groupSizeY <= (67u + 8u) * (33u + 8u));
                else
                    CHECK(uint32_t(d.gridWidth) * p.groupSizeX <= 67u + p.groupSizeX * 8u);
                bool known = false;
                for (const nrd::MethodDesc& m : methods)
                    known |= m.identifier == d.identifier;
                CHECK(known);
                if (d.isIndirect)
                    CHECK(d.indirectArgumentsBuffer < desc.buffersNum);
            }
            // The descriptor pool sizes cover one frame.
            uint32_t textures = 0, storage = 0;
            for (uint32_t i = 0; i < num; i++)
                for (uint32_t r = 0; r < dispatches[i].resourcesNum; r++)
                {
                    textures += dispatches[i].resources[r].descriptorType == nrd::DescriptorType::TEXTURE;
                    storage += dispatches[i].resources[r].descriptorType == nrd::DescriptorType::STORAGE_TEXTURE;
                }
            CHECK(desc.descriptorPoolDesc.setsMaxNum >= num);
            CHECK(desc.descriptorPoolDesc.texturesMaxNum >= textures);
            CHECK(desc.descriptorPoolDesc.storageTexturesMaxNum >= storage);
        }
    }
}

TEST_CASE("Pipelines are shared and transient textures aliased between methods", "[api]")
{
    for (nrd::Method method : {nrd::Method::SIGMA_SHADOW, nrd::Method::REFERENCE})
    {
        INFO(nrd::GetMethodString(method));
        Instance one({{1, method}});
        Instance two({{1, method}, {2, method}});
        REQUIRE(one.result == nrd::Result::SUCCESS);
        REQUIRE(two.result == nrd::Result::SUCCESS);
        const nrd::DenoiserDesc& d1 = nrd::GetDenoiserDesc(*one.denoiser);
        const nrd::DenoiserDesc& d2 = nrd::GetDenoiserDesc(*two.denoiser);
        CHECK(d2.pipelinesNum == d1.pipelinesNum);
        CHECK(d2.transientPoolSize == d1.transientPoolSize);
        CHECK(d2.permanentPoolSize == 2 * d1.permanentPoolSize);
        // Each method's dispatches reference its own history.
        auto names1 = DispatchNames(*one.denoiser, 0);
        auto names2 = DispatchNames(*two.denoiser, 0);
        CHECK(names2.size() == 2 * names1.size());
    }
}

TEST_CASE("Golden dispatch sequence of REFERENCE", "[api]")
{
    Instance inst({{1, nrd::Method::REFERENCE}});
    REQUIRE(inst.result == nrd::Result::SUCCESS);
    CHECK(DispatchNames(*inst.denoiser, 0) == std::vector<std::string>{"REFERENCE - Accumulate"});
    CHECK(DispatchNames(*inst.denoiser, 1) == std::vector<std::string>{"REFERENCE - Accumulate"});
    const nrd::DenoiserDesc& desc = nrd::GetDenoiserDesc(*inst.denoiser);
    REQUIRE(desc.permanentPoolSize == 1);
    CHECK(desc.permanentPool[0].format == nrd::Format::RGBA32_SFLOAT);
    CHECK(desc.transientPoolSize == 0);
}

TEST_CASE("REFERENCE weights follow the running mean, cap and reset", "[api]")
{
    Instance inst({{5, nrd::Method::REFERENCE}});
    REQUIRE(inst.result == nrd::Result::SUCCESS);
    nrd::ReferenceSettings rs;
    rs.maxAccumulatedFrameNum = 3;
    REQUIRE(nrd::SetMethodSettings(*inst.denoiser, 5, rs) == nrd::Result::SUCCESS);

    auto weight = [&](uint32_t frameIndex) {
        nrd::CommonSettings s;
        FillCamera(s);
        s.frameIndex = frameIndex;
        REQUIRE(nrd::SetCommonSettings(*inst.denoiser, s) == nrd::Result::SUCCESS);
        const nrd::DispatchDesc* d = nullptr;
        uint32_t n = 0;
        REQUIRE(nrd::GetComputeDispatches(*inst.denoiser, nullptr, 0, d, n) == nrd::Result::SUCCESS);
        REQUIRE(n == 1);
        float w;
        memcpy(&w, d[0].constantBufferData + 8, sizeof(float)); // uvec2 gSize, then gWeight.
        // A second call in the same frame returns the same dispatch without advancing history.
        const nrd::DispatchDesc* again = nullptr;
        uint32_t n2 = 0;
        nrd::Identifier id = 5;
        REQUIRE(nrd::GetComputeDispatches(*inst.denoiser, &id, 1, again, n2) == nrd::Result::SUCCESS);
        float w2;
        memcpy(&w2, again[0].constantBufferData + 8, sizeof(float));
        CHECK(w2 == w);
        return w;
    };
    CHECK(weight(0) == 1.0f);
    CHECK(weight(1) == 0.5f);
    CHECK(weight(2) == Approx(1.0f / 3.0f));
    CHECK(weight(3) == Approx(1.0f / 3.0f)); // Capped.
    CHECK(weight(0) == 1.0f);                 // Reset.
    CHECK(weight(1) == 0.5f);
}

TEST_CASE("Invalid creation descs are rejected with a message", "[api]")
{
    auto expect = [](std::vector<nrd::MethodDesc> methods, uint16_t w, uint16_t h, nrd::Result expected) {
        Instance inst(methods, w, h);
        CHECK(inst.result == expected);
        CHECK(inst.denoiser == nullptr);
        CHECK_FALSE(inst.log.messages.empty());
    };
    expect({{1, nrd::Method::REFERENCE}}, 0, 64, nrd::Result::INVALID_ARGUMENT);
    expect({{1, nrd::Method::REFERENCE}}, 64, 0, nrd::Result::INVALID_ARGUMENT);
    expect({{1, nrd::Method::REFERENCE}}, 16385, 64, nrd::Result::INVALID_ARGUMENT);
    expect({{1, nrd::Method::REFERENCE}}, 64, 65535, nrd::Result::INVALID_ARGUMENT);
    expect({}, 64, 64, nrd::Result::INVALID_ARGUMENT);
    expect({{1, nrd::Method(999)}}, 64, 64, nrd::Result::INVALID_ARGUMENT);
    expect({{1, nrd::Method::MAX_NUM}}, 64, 64, nrd::Result::INVALID_ARGUMENT);
    expect({{3, nrd::Method::REFERENCE}, {3, nrd::Method::SIGMA_SHADOW}}, 64, 64, nrd::Result::NON_UNIQUE_IDENTIFIER);

    nrd::DenoiserCreationDesc desc;
    nrd::MethodDesc m = {1, nrd::Method::REFERENCE};
    desc.methods = &m;
    desc.methodsNum = 1;
    desc.renderWidth = desc.renderHeight = 16;
    desc.allocationCallbacks.Allocate = [](void*, size_t, size_t) -> void* { return nullptr; };
    nrd::Denoiser* d = nullptr;
    CHECK(nrd::CreateDenoiser(desc, d) == nrd::Result::INVALID_ARGUMENT); // Only one of three callbacks.
    CHECK(d == nullptr);
}

TEST_CASE("Invalid common settings are rejected and the previous settings kept", "[api]")
{
    Instance inst({{1, nrd::Method::REFERENCE}}, 32, 32);
    REQUIRE(inst.result == nrd::Result::SUCCESS);
    nrd::Denoiser& d = *inst.denoiser;

    const nrd::DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    CHECK(nrd::GetComputeDispatches(d, nullptr, 0, dispatches, num) == nrd::Result::INVALID_ARGUMENT); // No settings yet.

    nrd::CommonSettings good;
    FillCamera(good);
    REQUIRE(nrd::SetCommonSettings(d, good) == nrd::Result::SUCCESS);

    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<std::pair<const char*, nrd::CommonSettings>> bad;
    auto add = [&](const char* what, auto edit) {
        nrd::CommonSettings s = good;
        edit(s);
        bad.push_back({what, s});
    };
    add("NaN in viewToClip", [&](nrd::CommonSettings& s) { s.viewToClipMatrix[5] = nan; });
    add("Inf in worldToViewPrev", [&](nrd::CommonSettings& s) { s.worldToViewMatrixPrev[12] = inf; });
    add("singular worldToView", [&](nrd::CommonSettings& s) { memset(s.worldToViewMatrix, 0, sizeof(s.worldToViewMatrix)); });
    add("rank-deficient worldToViewPrev", [&](nrd::CommonSettings& s) { s.worldToViewMatrixPrev[0] = 0.0f; });
    add("zero projection", [&](nrd::CommonSettings& s) { memset(s.viewToClipMatrixPrev, 0, sizeof(s.viewToClipMatrixPrev)); });
    add("orthographic projection", [&](nrd::CommonSettings& s) { s.viewToClipMatrix[11] = 0.0f; s.viewToClipMatrix[15] = 1.0f; });
    add("jitter 0.6", [&](nrd::CommonSettings& s) { s.cameraJitter[0] = 0.6f; });
    add("jitter -0.51", [&](nrd::CommonSettings& s) { s.cameraJitterPrev[1] = -0.51f; });
    add("jitter NaN", [&](nrd::CommonSettings& s) { s.cameraJitter[1] = nan; });
    add("resource size larger than creation", [&](nrd::CommonSettings& s) { s.resourceSize[0] = 33; s.resourceSize[1] = 32; });
    add("resource size half zero", [&](nrd::CommonSettings& s) { s.resourceSize[0] = 16; s.resourceSize[1] = 0; });
    add("NaN motion vector scale", [&](nrd::CommonSettings& s) { s.motionVectorScale[2] = nan; });
    add("negative denoising range", [&](nrd::CommonSettings& s) { s.denoisingRange = -1.0f; });
    add("NaN denoising range", [&](nrd::CommonSettings& s) { s.denoisingRange = nan; });
    add("zero disocclusion threshold", [&](nrd::CommonSettings& s) { s.disocclusionThreshold = 0.0f; });
    add("unknown accumulation mode", [&](nrd::CommonSettings& s) { s.accumulationMode = nrd::AccumulationMode(7); });

    for (auto& [what, s] : bad)
    {
        INFO(what);
        size_t before = inst.log.messages.size();
        CHECK(nrd::SetCommonSettings(d, s) == nrd::Result::INVALID_ARGUMENT);
        CHECK(inst.log.messages.size() == before + 1);
    }

    // The last good settings are still in effect.
    CHECK(nrd::GetComputeDispatches(d, nullptr, 0, dispatches, num) == nrd::Result::SUCCESS);
    REQUIRE(num == 1);
    uint32_t size[2];
    memcpy(size, dispatches[0].constantBufferData, sizeof(size));
    CHECK(size[0] == 32);
    CHECK(size[1] == 32);

    // A smaller resource size is fine and changes the grid.
    nrd::CommonSettings smaller = good;
    smaller.resourceSize[0] = 17;
    smaller.resourceSize[1] = 9;
    REQUIRE(nrd::SetCommonSettings(d, smaller) == nrd::Result::SUCCESS);
    REQUIRE(nrd::GetComputeDispatches(d, nullptr, 0, dispatches, num) == nrd::Result::SUCCESS);
    CHECK(dispatches[0].gridWidth == 2);
    CHECK(dispatches[0].gridHeight == 1);
}

TEST_CASE("Invalid method settings and identifiers are rejected", "[api]")
{
    Instance inst({{1, nrd::Method::REFERENCE}, {2, nrd::Method::SIGMA_SHADOW}}, 32, 32);
    REQUIRE(inst.result == nrd::Result::SUCCESS);
    nrd::Denoiser& d = *inst.denoiser;

    CHECK(nrd::SetMethodSettings(d, 1, nrd::SigmaSettings{}) == nrd::Result::INVALID_ARGUMENT); // Wrong type.
    CHECK(nrd::SetMethodSettings(d, 2, nrd::ReferenceSettings{}) == nrd::Result::INVALID_ARGUMENT);
    CHECK(nrd::SetMethodSettings(d, 9, nrd::ReferenceSettings{}) == nrd::Result::INVALID_ARGUMENT); // Unknown id.
    nrd::ReferenceSettings rs;
    rs.maxAccumulatedFrameNum = 0;
    CHECK(nrd::SetMethodSettings(d, 1, rs) == nrd::Result::INVALID_ARGUMENT);
    rs.maxAccumulatedFrameNum = nrd::REFERENCE_MAX_HISTORY_FRAME_NUM + 1;
    CHECK(nrd::SetMethodSettings(d, 1, rs) == nrd::Result::INVALID_ARGUMENT);

    const float nan = std::numeric_limits<float>::quiet_NaN();
    nrd::SigmaSettings ss;
    ss.blurRadiusScale = nan;
    CHECK(nrd::SetMethodSettings(d, 2, ss) == nrd::Result::INVALID_ARGUMENT);
    ss = {};
    ss.blurRadiusScale = -1.0f;
    CHECK(nrd::SetMethodSettings(d, 2, ss) == nrd::Result::INVALID_ARGUMENT);
    ss = {};
    ss.maxStabilizedFrameNum = nrd::SIGMA_MAX_HISTORY_FRAME_NUM + 1;
    CHECK(nrd::SetMethodSettings(d, 2, ss) == nrd::Result::INVALID_ARGUMENT);
    ss = {};
    ss.planeDistanceSensitivity = 0.0f;
    CHECK(nrd::SetMethodSettings(d, 2, ss) == nrd::Result::INVALID_ARGUMENT);
    ss = {};
    ss.lightDirection[1] = nan;
    CHECK(nrd::SetMethodSettings(d, 2, ss) == nrd::Result::INVALID_ARGUMENT);
    CHECK(nrd::SetMethodSettings(d, 2, nrd::SigmaSettings{}) == nrd::Result::SUCCESS);

    nrd::CommonSettings s;
    FillCamera(s);
    REQUIRE(nrd::SetCommonSettings(d, s) == nrd::Result::SUCCESS);
    const nrd::DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    nrd::Identifier unknown = 3;
    CHECK(nrd::GetComputeDispatches(d, &unknown, 1, dispatches, num) == nrd::Result::INVALID_ARGUMENT);
    CHECK(num == 0);
    CHECK(nrd::GetComputeDispatches(d, nullptr, 2, dispatches, num) == nrd::Result::INVALID_ARGUMENT);

    // Limiting to one identifier yields only that method's dispatches.
    nrd::Identifier only = 2;
    REQUIRE(nrd::GetComputeDispatches(d, &only, 1, dispatches, num) == nrd::Result::SUCCESS);
    REQUIRE(num > 0);
    for (uint32_t i = 0; i < num; i++)
        CHECK(dispatches[i].identifier == 2u);
}

TEST_CASE("Allocation callbacks receive every allocation of the instance", "[api]")
{
    struct Counter
    {
        int live = 0;
        int total = 0;
    } counter;
    nrd::DenoiserCreationDesc desc;
    nrd::MethodDesc m[] = {{1, nrd::Method::REFERENCE}, {2, nrd::Method::REFERENCE}};
    desc.methods = m;
    desc.methodsNum = 2;
    desc.renderWidth = desc.renderHeight = 16;
    desc.allocationCallbacks.userArg = &counter;
    desc.allocationCallbacks.Allocate = [](void* user, size_t size, size_t alignment) -> void* {
        auto* c = static_cast<Counter*>(user);
        c->live++;
        c->total++;
        size_t a = alignment < sizeof(void*) ? sizeof(void*) : alignment;
        return aligned_alloc(a, (size + a - 1) / a * a); // The size must be a multiple of the alignment.
    };
    desc.allocationCallbacks.Reallocate = [](void*, void*, size_t, size_t) -> void* { return nullptr; };
    desc.allocationCallbacks.Free = [](void* user, void* memory) {
        if (memory)
            static_cast<Counter*>(user)->live--;
        free(memory);
    };
    nrd::Denoiser* d = nullptr;
    REQUIRE(nrd::CreateDenoiser(desc, d) == nrd::Result::SUCCESS);
    nrd::CommonSettings s;
    FillCamera(s);
    REQUIRE(nrd::SetCommonSettings(*d, s) == nrd::Result::SUCCESS);
    const nrd::DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    REQUIRE(nrd::GetComputeDispatches(*d, nullptr, 0, dispatches, num) == nrd::Result::SUCCESS);
    CHECK(num == 2);
    CHECK(counter.total > 5);
    CHECK(counter.live > 0);
    nrd::DestroyDenoiser(d);
    CHECK(counter.live == 0);
}

// Found by Tests/Fuzz/FuzzCore.cpp: a repeated identifier used to return the method's dispatches
// twice (the method would run twice in one frame, beyond the published descriptor pool sizes).
TEST_CASE("A repeated identifier in GetComputeDispatches is rejected", "[api]")
{
    Instance inst({{1, nrd::Method::REFERENCE}, {2, nrd::Method::REFERENCE}}, 16, 16);
    REQUIRE(inst.result == nrd::Result::SUCCESS);
    nrd::CommonSettings s;
    FillCamera(s);
    REQUIRE(nrd::SetCommonSettings(*inst.denoiser, s) == nrd::Result::SUCCESS);
    const nrd::DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    nrd::Identifier repeated[] = {2, 1, 2};
    size_t before = inst.log.messages.size();
    CHECK(nrd::GetComputeDispatches(*inst.denoiser, repeated, 3, dispatches, num) == nrd::Result::INVALID_ARGUMENT);
    CHECK(num == 0);
    CHECK(inst.log.messages.size() == before + 1);
    nrd::Identifier both[] = {2, 1};
    REQUIRE(nrd::GetComputeDispatches(*inst.denoiser, both, 2, dispatches, num) == nrd::Result::SUCCESS);
    REQUIRE(num == 2);
    CHECK(dispatches[0].identifier == 2u);
    CHECK(dispatches[1].identifier == 1u);
}

TEST_CASE("Golden dispatch sequence and pools of TILED_SHADOW", "[api]")
{
    Instance inst({{3, nrd::Method::TILED_SHADOW}}, 67, 33);
    REQUIRE(inst.result == nrd::Result::SUCCESS);
    nrd::Denoiser& d = *inst.denoiser;
    const std::vector<std::string> atrous = {"TILED_SHADOW - A-trous step 1", "TILED_SHADOW - A-trous step 2"};
    std::vector<std::string> full = {"TILED_SHADOW - Prepare", "TILED_SHADOW - Classify"};
    full.insert(full.end(), atrous.begin(), atrous.end());
    CHECK(DispatchNames(d, 0) == full);
    CHECK(DispatchNames(d, 1) == full);

    nrd::TiledShadowSettings settings;
    settings.isBitmaskInput = true;
    REQUIRE(nrd::SetMethodSettings(d, 3, settings) == nrd::Result::SUCCESS);
    std::vector<std::string> bitmask = {"TILED_SHADOW - Classify"};
    bitmask.insert(bitmask.end(), atrous.begin(), atrous.end());
    CHECK(DispatchNames(d, 2) == bitmask);
    {
        const nrd::DispatchDesc* dispatches = nullptr;
        uint32_t num = 0;
        REQUIRE(nrd::GetComputeDispatches(d, nullptr, 0, dispatches, num) == nrd::Result::SUCCESS);
        CHECK(dispatches[0].resources[0].type == nrd::ResourceType::IN_SHADOW_BITMASK);
        // The counters are the last resource of the classification.
        CHECK(dispatches[0].resources[dispatches[0].resourcesNum - 1].type == nrd::ResourceType::BUFFER_POOL);
        // 16x16-pixel groups over the image, no group outside it.
        CHECK(dispatches[0].gridWidth == 5);
        CHECK(dispatches[0].gridHeight == 3);
    }

    settings.isBitmaskInput = false;
    settings.atrousPassNum = 3;
    REQUIRE(nrd::SetMethodSettings(d, 3, settings) == nrd::Result::SUCCESS);
    CHECK(DispatchNames(d, 3) == std::vector<std::string>{"TILED_SHADOW - Prepare", "TILED_SHADOW - Classify",
                                                          "TILED_SHADOW - A-trous step 1", "TILED_SHADOW - A-trous step 2",
                                                          "TILED_SHADOW - A-trous step 4"});
    settings.atrousPassNum = 1;
    REQUIRE(nrd::SetMethodSettings(d, 3, settings) == nrd::Result::SUCCESS);
    CHECK(DispatchNames(d, 3) == std::vector<std::string>{"TILED_SHADOW - Prepare", "TILED_SHADOW - Classify",
                                                          "TILED_SHADOW - A-trous step 1"});
    settings.debugView = nrd::TiledShadowDebug::LOCAL_MEAN;
    REQUIRE(nrd::SetMethodSettings(d, 3, settings) == nrd::Result::SUCCESS);
    CHECK(DispatchNames(d, 4) == std::vector<std::string>{"TILED_SHADOW - Prepare", "TILED_SHADOW - Classify",
                                                          "TILED_SHADOW - A-trous step 1"});

    const nrd::DenoiserDesc& desc = nrd::GetDenoiserDesc(d);
    REQUIRE(desc.permanentPoolSize == 1);
    CHECK(desc.permanentPool[0].format == nrd::Format::RG32_UINT);
    // Bitmasks and tile classes at 1/8 x 1/4, shadow + variance ping-pong, packed moments.
    REQUIRE(desc.transientPoolSize == 5);
    uint32_t tileTextures = 0, shadowTextures = 0, momentTextures = 0;
    for (uint32_t i = 0; i < desc.transientPoolSize; i++)
    {
        const nrd::TextureDesc& t = desc.transientPool[i];
        bool isFull = t.downsampleX == 1 && t.downsampleY == 1;
        tileTextures += t.format == nrd::Format::R32_UINT && t.downsampleX == 8 && t.downsampleY == 4;
        shadowTextures += t.format == nrd::Format::RG16_SFLOAT && isFull;
        momentTextures += t.format == nrd::Format::R32_UINT && isFull;
    }
    CHECK(tileTextures == 2);
    CHECK(shadowTextures == 2);
    CHECK(momentTextures == 1);
    REQUIRE(desc.buffersNum == 1);
    CHECK(desc.buffers[0].isPermanent);
    CHECK(desc.buffers[0].size == 2 * nrd::TILED_SHADOW_COUNTERS_SLOT_SIZE * sizeof(uint32_t));
}

TEST_CASE("TILED_SHADOW settings outside their ranges are rejected", "[api]")
{
    Instance inst({{3, nrd::Method::TILED_SHADOW}}, 32, 32);
    REQUIRE(inst.result == nrd::Result::SUCCESS);
    nrd::Denoiser& d = *inst.denoiser;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<std::pair<const char*, nrd::TiledShadowSettings>> bad;
    auto add = [&](const char* what, auto edit) {
        nrd::TiledShadowSettings s;
        edit(s);
        bad.push_back({what, s});
    };
    add("radius 0", [](nrd::TiledShadowSettings& s) { s.neighborhoodRadius = 0; });
    add("radius 9", [](nrd::TiledShadowSettings& s) { s.neighborhoodRadius = 9; });
    add("clamp sigma 0", [](nrd::TiledShadowSettings& s) { s.historyClampSigma = 0.0f; });
    add("clamp sigma NaN", [&](nrd::TiledShadowSettings& s) { s.historyClampSigma = nan; });
    add("grazing threshold 2", [](nrd::TiledShadowSettings& s) { s.disocclusionThresholdGrazing = 2.0f; });
    add("plane distance NaN", [&](nrd::TiledShadowSettings& s) { s.planeDistanceSensitivity = nan; });
    add("normal power -1", [](nrd::TiledShadowSettings& s) { s.normalPower = -1.0f; });
    add("0 a-trous passes", [](nrd::TiledShadowSettings& s) { s.atrousPassNum = 0; });
    add("4 a-trous passes", [](nrd::TiledShadowSettings& s) { s.atrousPassNum = 4; });
    add("history 0", [](nrd::TiledShadowSettings& s) { s.maxHistoryFrameNum = 0; });
    add("history 64", [](nrd::TiledShadowSettings& s) { s.maxHistoryFrameNum = nrd::TILED_SHADOW_MAX_HISTORY_FRAME_NUM + 1; });
    add("unknown debug view", [](nrd::TiledShadowSettings& s) { s.debugView = nrd::TiledShadowDebug::MAX_NUM; });
    for (auto& [what, s] : bad)
    {
        INFO(what);
        size_t before = inst.log.messages.size();
        CHECK(nrd::SetMethodSettings(d, 3, s) == nrd::Result::INVALID_ARGUMENT);
        CHECK(inst.log.messages.size() == before + 1);
    }
    CHECK(nrd::SetMethodSettings(d, 3, nrd::SigmaSettings{}) == nrd::Result::INVALID_ARGUMENT);
    CHECK(nrd::SetMethodSettings(d, 3, nrd::TiledShadowSettings{}) == nrd::Result::SUCCESS);
}

TEST_CASE("A camera far from the origin is accepted and reprojects to itself", "[api]")
{
    Instance inst({{3, nrd::Method::TILED_SHADOW}}, 32, 32);
    REQUIRE(inst.result == nrd::Result::SUCCESS);
    nrd::CommonSettings s;
    FillCamera(s);
    // A rotated camera 100 km away, still: clip -> previous clip must be the identity, which float
    // products of the world matrices would not give.
    const float c = 0.6f, sn = 0.8f;
    float view[16] = {c, 0, -sn, 0, 0, 1, 0, 0, sn, 0, c, 0, -1.0e5f, 2.5e4f, 3.0e4f, 1};
    memcpy(s.worldToViewMatrix, view, sizeof(view));
    memcpy(s.worldToViewMatrixPrev, view, sizeof(view));
    s.frameIndex = 1;
    REQUIRE(nrd::SetCommonSettings(*inst.denoiser, s) == nrd::Result::SUCCESS);
    const nrd::DispatchDesc* dispatches = nullptr;
    uint32_t num = 0;
    REQUIRE(nrd::GetComputeDispatches(*inst.denoiser, nullptr, 0, dispatches, num) == nrd::Result::SUCCESS);
    REQUIRE(num > 1);
    REQUIRE(std::string(dispatches[1].name) == "TILED_SHADOW - Classify");
    // The classification's block: NRD_COMMON_CONSTANTS (336 bytes), then gClipToClipPrev.
    float m[16];
    memcpy(m, dispatches[1].constantBufferData + 336, sizeof(m));
    for (int i = 0; i < 16; i++)
        CHECK(m[i] == Approx(i % 5 == 0 ? 1.0f : 0.0f).margin(1e-6));
}

// Found by the sanitizer job (ASan initialization-order check): the embedded shader table was
// initialized dynamically, so a denoiser created by another translation unit's static initializer
// could find no SPIR-V. Every method is created here before main().
static const bool g_CreatedBeforeMain = [] {
    bool ok = true;
    const nrd::LibraryDesc& lib = nrd::GetLibraryDesc();
    for (uint32_t i = 0; i < lib.supportedMethodsNum; i++)
    {
        nrd::MethodDesc method = {1, lib.supportedMethods[i]};
        nrd::DenoiserCreationDesc desc;
        desc.methods = &method;
        desc.methodsNum = 1;
        desc.renderWidth = desc.renderHeight = 8;
        nrd::Denoiser* denoiser = nullptr;
        ok = ok && nrd::CreateDenoiser(desc, denoiser) == nrd::Result::SUCCESS;
        nrd::DestroyDenoiser(denoiser);
    }
    return ok;
}();

TEST_CASE("Denoisers can be created from static initializers", "[api]")
{
    CHECK(g_CreatedBeforeMain);
}

TEST_CASE("Hit distance parameters are validated field by field", "[api]")
{
    LogCapture log;
    nrd::HitDistanceParameters p;
    CHECK(p.A == 3.0f);
    CHECK(p.B == 0.1f);
    CHECK(p.C == 20.0f);
    CHECK(p.D == -25.0f);
    CHECK(nrd::ValidateHitDistanceParameters(p, LogCapture::Callback, &log) == nrd::Result::SUCCESS);
    CHECK(log.messages.empty());

    // The limits themselves are valid (B = 0, C = 1, D = 0: a range independent of depth and roughness).
    p.B = 0.0f;
    p.C = 1.0f;
    p.D = 0.0f;
    CHECK(nrd::ValidateHitDistanceParameters(p) == nrd::Result::SUCCESS);

    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    struct Bad
    {
        const char* field;
        float nrd::HitDistanceParameters::*member;
        float value;
    };
    const Bad bad[] = {
        {"A", &nrd::HitDistanceParameters::A, 0.0f},  {"A", &nrd::HitDistanceParameters::A, -1.0f},
        {"A", &nrd::HitDistanceParameters::A, nan},   {"A", &nrd::HitDistanceParameters::A, inf},
        {"B", &nrd::HitDistanceParameters::B, -0.1f}, {"B", &nrd::HitDistanceParameters::B, inf},
        {"C", &nrd::HitDistanceParameters::C, 0.99f}, {"C", &nrd::HitDistanceParameters::C, nan},
        {"D", &nrd::HitDistanceParameters::D, 0.5f},  {"D", &nrd::HitDistanceParameters::D, -inf},
    };
    for (const Bad& b : bad)
    {
        INFO(b.field << " = " << b.value);
        nrd::HitDistanceParameters q;
        q.*b.member = b.value;
        log.messages.clear();
        CHECK(nrd::ValidateHitDistanceParameters(q, LogCapture::Callback, &log) == nrd::Result::INVALID_ARGUMENT);
        REQUIRE(log.messages.size() == 1);
        CHECK(log.messages[0].find(std::string("HitDistanceParameters::") + b.field) != std::string::npos);
    }
}

TEST_CASE("Radiance and hit distance resource types have names and are application textures", "[api]")
{
    using R = nrd::ResourceType;
    const std::pair<R, const char*> types[] = {
        {R::IN_DIFF_RADIANCE_HITDIST, "IN_DIFF_RADIANCE_HITDIST"}, {R::IN_SPEC_RADIANCE_HITDIST, "IN_SPEC_RADIANCE_HITDIST"},
        {R::IN_DIFF_HITDIST, "IN_DIFF_HITDIST"},                   {R::IN_SPEC_HITDIST, "IN_SPEC_HITDIST"},
        {R::IN_DIFF_CONFIDENCE, "IN_DIFF_CONFIDENCE"},             {R::IN_SPEC_CONFIDENCE, "IN_SPEC_CONFIDENCE"},
        {R::OUT_DIFF_RADIANCE_HITDIST, "OUT_DIFF_RADIANCE_HITDIST"}, {R::OUT_SPEC_RADIANCE_HITDIST, "OUT_SPEC_RADIANCE_HITDIST"},
        {R::OUT_DIFF_HITDIST, "OUT_DIFF_HITDIST"},                 {R::OUT_SPEC_HITDIST, "OUT_SPEC_HITDIST"},
    };
    for (const auto& t : types)
    {
        CHECK(std::string(nrd::GetResourceTypeString(t.first)) == t.second);
        CHECK(uint32_t(t.first) < uint32_t(R::TRANSIENT_POOL)); // Bound by the application, not a pool.
    }
}
