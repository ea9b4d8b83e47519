// libFuzzer target over the core API: CreateDenoiser / SetCommonSettings / SetMethodSettings (every
// settings struct) / GetComputeDispatches / DestroyDenoiser driven by arbitrary bytes.
//
// The input decodes into a creation desc (methods, identifiers, size, optional allocation callbacks
// that run out of memory after N allocations) and a sequence of calls whose arguments are either a
// valid baseline with a few fields replaced by interesting values or raw bytes. After every call the
// results are checked against the header's contract: allowed Result values, a log line for every
// rejection, and every returned description is internally consistent (pipeline, pool and buffer
// indices in range, descriptor types matching the pipeline's ranges, readable names and constants).
// A violation aborts (libFuzzer reports it as a crash); ASan / UBSan / LSan catch the rest.
//
// Build: cmake -DCMAKE_CXX_COMPILER=clang++ -DNRD_BUILD_FUZZER=ON (see README.md, "Fuzzing").
#include "NRD.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace
{

#define FUZZ_CHECK(condition)                                                                           \
    do                                                                                                  \
    {                                                                                                   \
        if (!(condition))                                                                               \
        {                                                                                               \
            std::fprintf(stderr, "FuzzCore: contract violated: %s (%s:%d)\n", #condition, __FILE__, __LINE__); \
            std::abort();                                                                               \
        }                                                                                               \
    } while (0)

// Counts log lines; touches every byte of each so ASan sees an unterminated message.
struct LogCounter
{
    uint32_t lines = 0;
    static void Callback(void* userArg, nrd::LogSeverity severity, const char* message)
    {
        FUZZ_CHECK(message != nullptr);
        FUZZ_CHECK(uint32_t(severity) <= uint32_t(nrd::LogSeverity::ERROR));
        FUZZ_CHECK(std::strlen(message) > 0);
        static_cast<LogCounter*>(userArg)->lines++;
    }
};

// Application allocation callbacks that fail once 'budget' allocations were made; tracks live blocks
// so that DestroyDenoiser (or a failed CreateDenoiser) provably returns everything.
struct FailingAllocator
{
    uint32_t budget = 0;
    uint32_t made = 0;
    int64_t live = 0;

    static void* Allocate(void* userArg, size_t size, size_t alignment)
    {
        auto* self = static_cast<FailingAllocator*>(userArg);
        FUZZ_CHECK(alignment != 0 && (alignment & (alignment - 1)) == 0);
        if (self->made >= self->budget)
            return nullptr;
        self->made++;
        void* memory = nullptr;
        if (posix_memalign(&memory, alignment < sizeof(void*) ? sizeof(void*) : alignment, size ? size : 1) != 0)
            return nullptr;
        self->live++;
        return memory;
    }
    static void* Reallocate(void*, void*, size_t, size_t)
    {
        return nullptr; // The core does not reallocate; failing here keeps it honest if it starts to.
    }
    static void Free(void* userArg, void* memory)
    {
        if (!memory)
            return;
        static_cast<FailingAllocator*>(userArg)->live--;
        free(memory);
    }
};

// Values that sit on the edges of the documented ranges, or far outside them.
float InterestingFloat(FuzzedDataProvider& in)
{
    static const float kValues[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, 0.50001f, -0.50001f, 1e-6f, 1e-4f,
                                    1e-38f, 1e-45f, 1e7f, 1e30f, -1e30f, 65504.0f, 65520.0f, 8.0f, 8.0001f, 500000.0f,
                                    std::numeric_limits<float>::max(), std::numeric_limits<float>::lowest(),
                                    std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                                    std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN()};
    if (in.ConsumeBool())
        return in.PickValueInArray(kValues);
    uint32_t bits = in.ConsumeIntegral<uint32_t>();
    float f;
    std::memcpy(&f, &bits, sizeof(f));
    return f;
}

uint32_t InterestingUint(FuzzedDataProvider& in)
{
    static const uint32_t kValues[] = {0u, 1u, 2u, 5u, 31u, 32u, 1023u, 65535u, 65536u, 0x7fffffffu, 0xffffffffu};
    return in.ConsumeBool() ? in.PickValueInArray(kValues) : in.ConsumeIntegral<uint32_t>();
}

void FillCamera(nrd::CommonSettings& s)
{
    const float f = 1.0f / std::tan(0.5f), n = 0.1f;
    const float projection[16] = {f, 0, 0, 0, 0, -f, 0, 0, 0, 0, 0, 1, 0, 0, n, 0};
    const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    std::memcpy(s.viewToClipMatrix, projection, sizeof(projection));
    std::memcpy(s.viewToClipMatrixPrev, projection, sizeof(projection));
    std::memcpy(s.worldToViewMatrix, identity, sizeof(identity));
    std::memcpy(s.worldToViewMatrixPrev, identity, sizeof(identity));
}

nrd::CommonSettings DecodeCommonSettings(FuzzedDataProvider& in, uint32_t frame)
{
    nrd::CommonSettings s;
    if (in.ConsumeIntegralInRange<uint8_t>(0, 7) == 0)
    {
        // Raw bytes for everything but the bool (a bool other than 0 / 1 is the caller's UB).
        std::vector<uint8_t> raw = in.ConsumeBytes<uint8_t>(sizeof(s));
        raw.resize(sizeof(s), 0);
        std::memcpy(&s, raw.data(), sizeof(s));
        s.isMotionVectorInWorldSpace = (raw[sizeof(s) - 1] & 1) != 0;
        return s;
    }
    FillCamera(s);
    s.frameIndex = frame;
    uint32_t edits = in.ConsumeIntegralInRange<uint32_t>(0, 4);
    for (uint32_t e = 0; e < edits; e++)
    {
        switch (in.ConsumeIntegralInRange<uint8_t>(0, 14))
        {
        case 0: s.viewToClipMatrix[in.ConsumeIntegralInRange<uint8_t>(0, 15)] = InterestingFloat(in); break;
        case 1: s.viewToClipMatrixPrev[in.ConsumeIntegralInRange<uint8_t>(0, 15)] = InterestingFloat(in); break;
        case 2: s.worldToViewMatrix[in.ConsumeIntegralInRange<uint8_t>(0, 15)] = InterestingFloat(in); break;
        case 3: s.worldToViewMatrixPrev[in.ConsumeIntegralInRange<uint8_t>(0, 15)] = InterestingFloat(in); break;
        case 4: s.motionVectorScale[in.ConsumeIntegralInRange<uint8_t>(0, 2)] = InterestingFloat(in); break;
        case 5: s.cameraJitter[in.ConsumeIntegralInRange<uint8_t>(0, 1)] = InterestingFloat(in); break;
        case 6: s.cameraJitterPrev[in.ConsumeIntegralInRange<uint8_t>(0, 1)] = InterestingFloat(in); break;
        case 7: s.resourceSize[0] = in.ConsumeIntegral<uint16_t>(); break;
        case 8: s.resourceSize[1] = in.ConsumeIntegral<uint16_t>(); break;
        case 9: s.denoisingRange = InterestingFloat(in); break;
        case 10: s.disocclusionThreshold = InterestingFloat(in); break;
        case 11: s.frameIndex = InterestingUint(in); break;
        case 12: s.accumulationMode = nrd::AccumulationMode(in.ConsumeIntegral<uint8_t>()); break;
        default: s.isMotionVectorInWorldSpace = in.ConsumeBool(); break;
        }
    }
    return s;
}

// Every settings struct, decoded as defaults with a few edited fields or as raw bytes. A new
// settings struct gets its own Decode overload and an entry in CallSetMethodSettings.
template <class T>
T DecodeRaw(FuzzedDataProvider& in)
{
    T s;
    std::vector<uint8_t> raw = in.ConsumeBytes<uint8_t>(sizeof(T));
    raw.resize(sizeof(T), 0);
    std::memcpy(&s, raw.data(), sizeof(T));
    return s;
}

nrd::SigmaSettings DecodeSigma(FuzzedDataProvider& in)
{
    if (in.ConsumeIntegralInRange<uint8_t>(0, 7) == 0)
        return DecodeRaw<nrd::SigmaSettings>(in);
    nrd::SigmaSettings s;
    uint32_t edits = in.ConsumeIntegralInRange<uint32_t>(0, 3);
    for (uint32_t e = 0; e < edits; e++)
    {
        switch (in.ConsumeIntegralInRange<uint8_t>(0, 6))
        {
        case 0: s.lightDirection[in.ConsumeIntegralInRange<uint8_t>(0, 2)] = InterestingFloat(in); break;
        case 1: s.planeDistanceSensitivity = InterestingFloat(in); break;
        case 2: s.blurRadiusScale = InterestingFloat(in); break;
        case 3: s.tanOfLightAngularRadius = InterestingFloat(in); break;
        case 4: s.lightPosition[in.ConsumeIntegralInRange<uint8_t>(0, 2)] = InterestingFloat(in); break;
        case 5: s.lightRadius = InterestingFloat(in); break;
        default: s.maxStabilizedFrameNum = InterestingUint(in); break;
        }
    }
    return s;
}

nrd::ReferenceSettings DecodeReference(FuzzedDataProvider& in)
{
    if (in.ConsumeIntegralInRange<uint8_t>(0, 7) == 0)
        return DecodeRaw<nrd::ReferenceSettings>(in);
    nrd::ReferenceSettings s;
    if (in.ConsumeBool())
        s.maxAccumulatedFrameNum = InterestingUint(in);
    return s;
}

nrd::TiledShadowSettings DecodeTiledShadow(FuzzedDataProvider& in)
{
    nrd::TiledShadowSettings s;
    if (in.ConsumeIntegralInRange<uint8_t>(0, 7) == 0)
    {
        s = DecodeRaw<nrd::TiledShadowSettings>(in);
        s.isBitmaskInput = in.ConsumeBool(); // A bool other than 0 / 1 is the caller's UB.
        s.enableTileSkipping = in.ConsumeBool();
        s.isShadowDataInput = in.ConsumeBool();
        return s;
    }
    uint32_t edits = in.ConsumeIntegralInRange<uint32_t>(0, 4);
    for (uint32_t e = 0; e < edits; e++)
    {
        switch (in.ConsumeIntegralInRange<uint8_t>(0, 14))
        {
        case 0: s.isBitmaskInput = in.ConsumeBool(); break;
        case 9: s.isShadowDataInput = in.ConsumeBool(); break;
        case 10: s.lightDirection[in.ConsumeIntegralInRange<uint8_t>(0, 2)] = InterestingFloat(in); break;
        case 11: s.tanOfLightAngularRadius = InterestingFloat(in); break;
        case 12: s.lightPosition[in.ConsumeIntegralInRange<uint8_t>(0, 2)] = InterestingFloat(in); break;
        case 13: s.lightRadius = InterestingFloat(in); break;
        case 1: s.enableTileSkipping = in.ConsumeBool(); break;
        case 2: s.neighborhoodRadius = InterestingUint(in); break;
        case 3: s.historyClampSigma = InterestingFloat(in); break;
        case 4: s.disocclusionThresholdGrazing = InterestingFloat(in); break;
        case 5: s.planeDistanceSensitivity = InterestingFloat(in); break;
        case 6: s.normalPower = InterestingFloat(in); break;
        case 7: s.atrousPassNum = InterestingUint(in); break;
        case 8: s.maxHistoryFrameNum = InterestingUint(in); break;
        default: s.debugView = nrd::TiledShadowDebug(in.ConsumeIntegral<uint8_t>()); break;
        }
    }
    return s;
}

nrd::ConfidenceSettings DecodeConfidence(FuzzedDataProvider& in)
{
    if (in.ConsumeIntegralInRange<uint8_t>(0, 7) == 0)
        return DecodeRaw<nrd::ConfidenceSettings>(in);
    nrd::ConfidenceSettings s;
    uint32_t edits = in.ConsumeIntegralInRange<uint32_t>(0, 3);
    for (uint32_t e = 0; e < edits; e++)
    {
        switch (in.ConsumeIntegralInRange<uint8_t>(0, 6))
        {
        case 0: s.gradientThreshold = InterestingFloat(in); break;
        case 1: s.gradientSensitivity = InterestingFloat(in); break;
        case 2: s.fallHistoryWeight = InterestingFloat(in); break;
        case 3: s.riseHistoryWeight = InterestingFloat(in); break;
        case 4: s.atrousPassNum = InterestingUint(in); break;
        case 5: s.depthThreshold = InterestingFloat(in); break;
        default: s.normalPower = InterestingFloat(in); break;
        }
    }
    return s;
}

nrd::ReflectionSettings DecodeReflection(FuzzedDataProvider& in)
{
    nrd::ReflectionSettings s;
    if (in.ConsumeIntegralInRange<uint8_t>(0, 7) == 0)
    {
        s = DecodeRaw<nrd::ReflectionSettings>(in);
        s.enableTemporalVarianceGuidedTracing = in.ConsumeBool(); // A bool other than 0 / 1 is the caller's UB.
        s.enableSpatial = in.ConsumeBool();
        s.enableBlur = in.ConsumeBool();
        return s;
    }
    uint32_t edits = in.ConsumeIntegralInRange<uint32_t>(0, 4);
    for (uint32_t e = 0; e < edits; e++)
    {
        switch (in.ConsumeIntegralInRange<uint8_t>(0, 9))
        {
        case 0: s.roughnessThreshold = InterestingFloat(in); break;
        case 1: s.mirrorRoughness = InterestingFloat(in); break;
        case 2: s.raysPerQuad = InterestingUint(in); break;
        case 3: s.temporalVarianceThreshold = InterestingFloat(in); break;
        case 4: s.maxHistoryFrameNum = InterestingUint(in); break;
        case 5: s.hitReprojectionRoughness = InterestingFloat(in); break;
        case 6: s.historyClipSigma = InterestingFloat(in); break;
        case 7: s.historyClipLeeway = InterestingFloat(in); break;
        case 8: s.normalSigma = InterestingFloat(in); break;
        default: s.hitDistanceParameters.A = InterestingFloat(in); break;
        }
    }
    return s;
}

nrd::RelaxSettings DecodeRelax(FuzzedDataProvider& in)
{
    nrd::RelaxSettings s;
    if (in.ConsumeIntegralInRange<uint8_t>(0, 7) == 0)
    {
        s = DecodeRaw<nrd::RelaxSettings>(in);
        s.enableAntiFirefly = in.ConsumeBool(); // A bool other than 0 / 1 is the caller's UB.
        s.enableRoughnessEdgeStopping = in.ConsumeBool();
        s.useConfidenceInputs = in.ConsumeBool();
        return s;
    }
    uint32_t edits = in.ConsumeIntegralInRange<uint32_t>(0, 4);
    for (uint32_t e = 0; e < edits; e++)
    {
        switch (in.ConsumeIntegralInRange<uint8_t>(0, 11))
        {
        case 0: s.diffuseMaxAccumulatedFrameNum = InterestingUint(in); break;
        case 1: s.specularMaxFastAccumulatedFrameNum = InterestingUint(in); break;
        case 2: s.historyFixFrameNum = InterestingUint(in); break;
        case 3: s.historyFixStride = InterestingFloat(in); break;
        case 4: (in.ConsumeBool() ? s.diffuseHistoryClampingColorBoxSigmaScale : s.specularHistoryClampingColorBoxSigmaScale) = InterestingFloat(in); break;
        case 5: s.antilagSigmaScale = InterestingFloat(in); break;
        case 6: s.atrousIterationNum = InterestingUint(in); break;
        case 7: s.diffusePhiLuminance = InterestingFloat(in); break;
        case 8: s.specularLobeAngleSlack = InterestingFloat(in); break;
        case 9: s.depthThreshold = InterestingFloat(in); break;
        case 10: s.hitDistanceParameters.A = InterestingFloat(in); break;
        default: s.checkerboardMode = nrd::CheckerboardMode(in.ConsumeIntegral<uint8_t>()); break;
        }
    }
    return s;
}

nrd::Result CallSetMethodSettings(FuzzedDataProvider& in, nrd::Denoiser& denoiser, nrd::Identifier identifier)
{
    switch (in.ConsumeIntegralInRange<uint8_t>(0, 5))
    {
    case 0: return nrd::SetMethodSettings(denoiser, identifier, DecodeSigma(in));
    case 1: return nrd::SetMethodSettings(denoiser, identifier, DecodeReference(in));
    case 2: return nrd::SetMethodSettings(denoiser, identifier, DecodeConfidence(in));
    case 3: return nrd::SetMethodSettings(denoiser, identifier, DecodeReflection(in));
    case 4: return nrd::SetMethodSettings(denoiser, identifier, DecodeRelax(in));
    default: return nrd::SetMethodSettings(denoiser, identifier, DecodeTiledShadow(in));
    }
}

bool IsPoolOrBuffer(nrd::ResourceType type)
{
    return type == nrd::ResourceType::TRANSIENT_POOL || type == nrd::ResourceType::PERMANENT_POOL ||
           type == nrd::ResourceType::BUFFER_POOL;
}

// Reads every byte so that ASan flags a dangling or short pointer.
uint32_t Touch(const void* data, size_t size)
{
    uint32_t sum = 0;
    const volatile uint8_t* bytes = static_cast<const volatile uint8_t*>(data);
    for (size_t i = 0; i < size; i++)
        sum += bytes[i];
    return sum;
}

void ValidateDenoiserDesc(const nrd::DenoiserDesc& d, uint16_t width, uint16_t height)
{
    FUZZ_CHECK(d.renderWidth == width && d.renderHeight == height);
    FUZZ_CHECK(d.pipelinesNum > 0 && d.pipelines != nullptr);
    for (uint32_t i = 0; i < d.pipelinesNum; i++)
    {
        const nrd::PipelineDesc& p = d.pipelines[i];
        FUZZ_CHECK(p.spirv.bytecode != nullptr && p.spirv.size >= 20 && p.spirv.size % 4 == 0);
        FUZZ_CHECK(static_cast<const uint32_t*>(p.spirv.bytecode)[0] == 0x07230203u);
        Touch(p.spirv.bytecode, size_t(p.spirv.size));
        FUZZ_CHECK(p.entryPointName != nullptr && p.shaderIdentifier != nullptr);
        FUZZ_CHECK(std::strlen(p.entryPointName) > 0 && std::strlen(p.shaderIdentifier) > 0);
        FUZZ_CHECK(p.groupSizeX > 0 && p.groupSizeY > 0);
        FUZZ_CHECK(p.hasConstantData == (p.constantBufferSize > 0));
        FUZZ_CHECK(p.constantBufferSize <= d.constantBufferMaxDataSize);
        FUZZ_CHECK(p.resourceRangesNum == 0 || p.resourceRanges != nullptr);
        uint32_t next = 0;
        for (uint32_t r = 0; r < p.resourceRangesNum; r++)
        {
            FUZZ_CHECK(uint32_t(p.resourceRanges[r].descriptorType) < uint32_t(nrd::DescriptorType::MAX_NUM));
            FUZZ_CHECK(p.resourceRanges[r].baseBinding == next); // Contiguous, in binding order.
            FUZZ_CHECK(p.resourceRanges[r].descriptorsNum > 0);
            next += p.resourceRanges[r].descriptorsNum;
        }
    }
    FUZZ_CHECK(d.samplersNum == 0 || d.samplers != nullptr);
    for (uint32_t i = 0; i < d.samplersNum; i++)
        FUZZ_CHECK(uint32_t(d.samplers[i]) < uint32_t(nrd::Sampler::MAX_NUM));
    const nrd::TextureDesc* pools[] = {d.permanentPool, d.transientPool};
    uint32_t poolSizes[] = {d.permanentPoolSize, d.transientPoolSize};
    for (int k = 0; k < 2; k++)
    {
        FUZZ_CHECK(poolSizes[k] == 0 || pools[k] != nullptr);
        for (uint32_t i = 0; i < poolSizes[k]; i++)
        {
            FUZZ_CHECK(uint32_t(pools[k][i].format) < uint32_t(nrd::Format::MAX_NUM));
            FUZZ_CHECK(pools[k][i].downsampleX > 0 && pools[k][i].downsampleY > 0);
        }
    }
    FUZZ_CHECK(d.buffersNum == 0 || d.buffers != nullptr);
    for (uint32_t i = 0; i < d.buffersNum; i++)
        FUZZ_CHECK(d.buffers[i].size > 0);
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

void ValidateDispatches(const nrd::DenoiserDesc& d, const nrd::DispatchDesc* dispatches, uint32_t num,
                        const std::vector<nrd::Identifier>& allowed)
{
    FUZZ_CHECK(num == 0 || dispatches != nullptr);
    uint32_t sets = 0, textures = 0, storageTextures = 0, buffers = 0, constantBuffers = 0;
    for (uint32_t i = 0; i < num; i++)
    {
        const nrd::DispatchDesc& x = dispatches[i];
        FUZZ_CHECK(x.name != nullptr && std::strlen(x.name) > 0);
        bool known = false;
        for (nrd::Identifier id : allowed)
            known |= id == x.identifier;
        FUZZ_CHECK(known);
        FUZZ_CHECK(x.pipelineIndex < d.pipelinesNum);
        const nrd::PipelineDesc& p = d.pipelines[x.pipelineIndex];
        uint32_t bindings = 0;
        for (uint32_t r = 0; r < p.resourceRangesNum; r++)
            bindings += p.resourceRanges[r].descriptorsNum;
        FUZZ_CHECK(x.resourcesNum == bindings);
        FUZZ_CHECK(x.resourcesNum == 0 || x.resources != nullptr);
        for (uint32_t r = 0; r < x.resourcesNum; r++)
        {
            const nrd::ResourceDesc& res = x.resources[r];
            FUZZ_CHECK(res.descriptorType == RangeTypeOfBinding(p, r));
            FUZZ_CHECK(uint32_t(res.type) < uint32_t(nrd::ResourceType::MAX_NUM));
            bool isBuffer = res.descriptorType == nrd::DescriptorType::BUFFER ||
                            res.descriptorType == nrd::DescriptorType::STORAGE_BUFFER;
            if (res.type == nrd::ResourceType::PERMANENT_POOL)
                FUZZ_CHECK(!isBuffer && res.indexInPool < d.permanentPoolSize);
            else if (res.type == nrd::ResourceType::TRANSIENT_POOL)
                FUZZ_CHECK(!isBuffer && res.indexInPool < d.transientPoolSize);
            else if (res.type == nrd::ResourceType::BUFFER_POOL)
                FUZZ_CHECK(isBuffer && res.indexInPool < d.buffersNum);
            else
                FUZZ_CHECK(!isBuffer && !IsPoolOrBuffer(res.type) && res.indexInPool == 0);
            textures += res.descriptorType == nrd::DescriptorType::TEXTURE;
            storageTextures += res.descriptorType == nrd::DescriptorType::STORAGE_TEXTURE;
            buffers += isBuffer;
        }
        FUZZ_CHECK(x.constantBufferDataSize == (p.hasConstantData ? p.constantBufferSize : 0u));
        FUZZ_CHECK((x.constantBufferDataSize == 0) == (x.constantBufferData == nullptr));
        Touch(x.constantBufferData, x.constantBufferDataSize);
        FUZZ_CHECK(x.gridWidth > 0 && x.gridHeight > 0);
        // Frames never exceed the creation size: at most one group per pixel of it (per axis; an
        // indirect dispatch over a list of tiles is a 1D grid of at most one group per pixel in all).
        if (x.isIndirect)
            FUZZ_CHECK(uint64_t(x.gridWidth) * x.gridHeight <= uint64_t(d.renderWidth) * d.renderHeight);
        else
            FUZZ_CHECK(x.gridWidth <= d.renderWidth && x.gridHeight <= d.renderHeight);
        if (x.isIndirect)
        {
            FUZZ_CHECK(x.indirectArgumentsBuffer < d.buffersNum);
            const nrd::BufferDesc& b = d.buffers[x.indirectArgumentsBuffer];
            FUZZ_CHECK(b.isIndirectArguments);
            FUZZ_CHECK(x.indirectArgumentsOffset % 4 == 0 && uint64_t(x.indirectArgumentsOffset) + 12 <= b.size);
        }
        sets++;
        constantBuffers += p.hasConstantData;
    }
    // One frame of all methods fits the published descriptor pool sizes.
    const nrd::DescriptorPoolDesc& pool = d.descriptorPoolDesc;
    FUZZ_CHECK(sets <= pool.setsMaxNum);
    FUZZ_CHECK(textures <= pool.texturesMaxNum);
    FUZZ_CHECK(storageTextures <= pool.storageTexturesMaxNum);
    FUZZ_CHECK(buffers <= pool.buffersMaxNum);
    FUZZ_CHECK(constantBuffers <= pool.constantBuffersMaxNum);
}

// One denoiser's life: creation, then up to 64 calls decoded from the input.
void RunSession(FuzzedDataProvider& in)
{
    const nrd::LibraryDesc& library = nrd::GetLibraryDesc();

    uint32_t methodsNum = in.ConsumeIntegralInRange<uint32_t>(0, 5);
    std::vector<nrd::MethodDesc> methods(methodsNum);
    for (nrd::MethodDesc& m : methods)
    {
        m.identifier = in.ConsumeBool() ? in.ConsumeIntegralInRange<uint32_t>(0, 7) : in.ConsumeIntegral<uint32_t>();
        if (in.ConsumeIntegralInRange<uint8_t>(0, 15) != 0 && library.supportedMethodsNum != 0)
            m.method = library.supportedMethods[in.ConsumeIntegralInRange<uint32_t>(0, library.supportedMethodsNum - 1)];
        else
            m.method = nrd::Method(in.ConsumeIntegral<uint32_t>());
    }
    uint16_t width = in.ConsumeBool() ? in.ConsumeIntegralInRange<uint16_t>(0, 300) : in.ConsumeIntegral<uint16_t>();
    uint16_t height = in.ConsumeBool() ? in.ConsumeIntegralInRange<uint16_t>(0, 300) : in.ConsumeIntegral<uint16_t>();

    LogCounter log;
    FailingAllocator allocator;
    nrd::DenoiserCreationDesc desc;
    desc.methods = (methodsNum || in.ConsumeBool()) ? methods.data() : nullptr;
    desc.methodsNum = methodsNum;
    desc.renderWidth = width;
    desc.renderHeight = height;
    desc.logCallback = in.ConsumeIntegralInRange<uint8_t>(0, 7) ? LogCounter::Callback : nullptr;
    desc.logUserArg = &log;
    bool limitedMemory = false;
    switch (in.ConsumeIntegralInRange<uint8_t>(0, 7))
    {
    case 0: // Out of memory after a decoded number of allocations.
        limitedMemory = true;
        allocator.budget = in.ConsumeIntegralInRange<uint32_t>(0, 400);
        desc.allocationCallbacks = {FailingAllocator::Allocate, FailingAllocator::Reallocate, FailingAllocator::Free,
                                    &allocator};
        break;
    case 1: // Only some callbacks: must be rejected.
        desc.allocationCallbacks.Allocate = FailingAllocator::Allocate;
        desc.allocationCallbacks.userArg = &allocator;
        break;
    default: break;
    }

    bool valid = desc.methods && methodsNum && width && height && width <= 16384 && height <= 16384 &&
                 desc.allocationCallbacks.Free == (desc.allocationCallbacks.Allocate ? FailingAllocator::Free : nullptr);
    bool unique = true;
    for (uint32_t i = 0; i < methodsNum; i++)
    {
        valid &= uint32_t(methods[i].method) < uint32_t(nrd::Method::MAX_NUM);
        for (uint32_t j = 0; j < i; j++)
            unique &= methods[i].identifier != methods[j].identifier;
    }

    nrd::Denoiser* denoiser = reinterpret_cast<nrd::Denoiser*>(uintptr_t(1)); // Must be overwritten.
    uint32_t linesBefore = log.lines;
    nrd::Result created = nrd::CreateDenoiser(desc, denoiser);
    if (created != nrd::Result::SUCCESS)
    {
        FUZZ_CHECK(denoiser == nullptr);
        FUZZ_CHECK(!desc.logCallback || created == nrd::Result::FAILURE || log.lines > linesBefore);
        FUZZ_CHECK(created != nrd::Result::FAILURE || limitedMemory);
        FUZZ_CHECK(valid || created == nrd::Result::INVALID_ARGUMENT || created == nrd::Result::NON_UNIQUE_IDENTIFIER ||
                   created == nrd::Result::FAILURE);
        FUZZ_CHECK(allocator.live == 0);
        return;
    }
    FUZZ_CHECK(denoiser != nullptr);
    FUZZ_CHECK(valid && unique);

    std::vector<nrd::Identifier> identifiers;
    for (const nrd::MethodDesc& m : methods)
        identifiers.push_back(m.identifier);

    const nrd::DenoiserDesc& denoiserDesc = nrd::GetDenoiserDesc(*denoiser);
    ValidateDenoiserDesc(denoiserDesc, width, height);

    bool haveCommon = false;
    uint32_t frame = 0;
    for (uint32_t call = 0; call < 64 && in.remaining_bytes() > 0; call++)
    {
        linesBefore = log.lines;
        nrd::Result result = nrd::Result::SUCCESS;
        switch (in.ConsumeIntegralInRange<uint8_t>(0, 3))
        {
        case 0:
        {
            nrd::CommonSettings s = DecodeCommonSettings(in, frame++);
            result = nrd::SetCommonSettings(*denoiser, s);
            haveCommon |= result == nrd::Result::SUCCESS;
            break;
        }
        case 1:
        {
            nrd::Identifier id = in.ConsumeBool() && !identifiers.empty()
                                     ? identifiers[in.ConsumeIntegralInRange<size_t>(0, identifiers.size() - 1)]
                                     : in.ConsumeIntegral<uint32_t>();
            result = CallSetMethodSettings(in, *denoiser, id);
            break;
        }
        default:
        {
            // All methods, a subset (possibly with repeats or unknown identifiers), or a null list.
            std::vector<nrd::Identifier> subset;
            uint32_t count = in.ConsumeIntegralInRange<uint32_t>(0, 6);
            for (uint32_t k = 0; k < count; k++)
                subset.push_back(in.ConsumeIntegralInRange<uint8_t>(0, 7) != 0
                                     ? identifiers[in.ConsumeIntegralInRange<size_t>(0, identifiers.size() - 1)]
                                     : in.ConsumeIntegral<uint32_t>());
            bool nullList = count > 0 && in.ConsumeIntegralInRange<uint8_t>(0, 15) == 0;
            const nrd::DispatchDesc* dispatches = reinterpret_cast<const nrd::DispatchDesc*>(uintptr_t(1));
            uint32_t num = 0xdeadbeefu;
            result = nrd::GetComputeDispatches(*denoiser, nullList ? nullptr : subset.data(), count, dispatches, num);
            if (result == nrd::Result::SUCCESS)
            {
                FUZZ_CHECK(haveCommon && !nullList);
                ValidateDispatches(denoiserDesc, dispatches, num, count ? subset : identifiers);
            }
            else
            {
                FUZZ_CHECK(dispatches == nullptr && num == 0);
                FUZZ_CHECK(result != nrd::Result::INVALID_ARGUMENT || !haveCommon || nullList || count > 0);
            }
            break;
        }
        }
        FUZZ_CHECK(result == nrd::Result::SUCCESS || result == nrd::Result::INVALID_ARGUMENT ||
                   (result == nrd::Result::FAILURE && limitedMemory));
        if (result == nrd::Result::INVALID_ARGUMENT && desc.logCallback)
            FUZZ_CHECK(log.lines > linesBefore); // Every rejection says why.
        // The creation-time description is immutable.
        FUZZ_CHECK(&nrd::GetDenoiserDesc(*denoiser) == &denoiserDesc);
    }
    ValidateDenoiserDesc(denoiserDesc, width, height);

    nrd::DestroyDenoiser(denoiser);
    FUZZ_CHECK(allocator.live == 0);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    FuzzedDataProvider in(data, size);
    // Up to two denoisers in sequence, so state that leaks from one to the next shows up.
    for (int session = 0; session < 2 && in.remaining_bytes() > 0; session++)
        RunSession(in);
    nrd::DestroyDenoiser(nullptr);
    return 0;
}
