// The core alone, without any graphics API: a tiny executor that maps the descriptions onto a
// pretend renderer, the way an engine maps them onto its own RHI (INTEGRATION.md, "Through your
// engine's RHI"). Its "GPU objects" are records; every step checks what the engine would rely on:
//   - pipelines: SPIR-V present (magic number), resource ranges contiguous from binding 0;
//   - pools: known formats, downsample factors >= 1;
//   - dispatches: the resources match the pipeline's ranges in binding order, pool indices exist,
//     constants are exactly the pipeline's block, the grid covers at least one group;
//   - barriers: one per hazard (read after write, write after read, write after write), counted.
// Every method of the library and a second SIGMA_SHADOW (two lights) in one denoiser; frames of
// all methods, of one identifier, and at a lower dynamic resolution. Exit code 0 when every description is consistent.
#include <NRD.h>

#include <cstdio>
#include <cstring>
#include <vector>

namespace
{

int g_errors = 0;

void Check(bool condition, const char* what, const char* where)
{
    if (!condition && g_errors++ < 20)
        std::fprintf(stderr, "inconsistent: %s (%s)\n", what, where);
}

void Log(void*, nrd::LogSeverity, const char* message)
{
    std::fprintf(stderr, "NRD: %s\n", message);
}

// The pretend renderer's objects.
struct Pipeline
{
    std::vector<nrd::DescriptorType> bindings; // Set 0, binding i.
    uint32_t constantBufferSize = 0;           // Set 1, binding 0 (0 = none).
};

struct TextureState
{
    bool isWritten = false;   // Last access was a write (storage).
    bool isReadSince = false; // Read since that write.
};

struct Executor
{
    const nrd::DenoiserDesc* desc = nullptr;
    std::vector<Pipeline> pipelines;
    std::vector<TextureState> permanent, transient, buffers;
    TextureState user[(size_t)nrd::ResourceType::TRANSIENT_POOL] = {};
    uint32_t barriers = 0;
    uint32_t dispatches = 0;

    // Once, after CreateDenoiser: pipelines (set layouts + SPIR-V), samplers, pools.
    void Create(const nrd::DenoiserDesc& denoiserDesc)
    {
        desc = &denoiserDesc;
        for (uint32_t p = 0; p < denoiserDesc.pipelinesNum; p++)
        {
            const nrd::PipelineDesc& pd = denoiserDesc.pipelines[p];
            const char* name = pd.shaderIdentifier ? pd.shaderIdentifier : "?";
            const uint32_t* words = static_cast<const uint32_t*>(pd.spirv.bytecode);
            Check(words && pd.spirv.size >= 20 && pd.spirv.size % 4 == 0 && words[0] == 0x07230203u, "SPIR-V", name);
            Check(pd.entryPointName && pd.groupSizeX > 0 && pd.groupSizeY > 0, "entry point and group size", name);
            Check(pd.hasConstantData == (pd.constantBufferSize > 0), "constant block size", name);
            Pipeline pipeline;
            for (uint32_t r = 0; r < pd.resourceRangesNum; r++)
            {
                const nrd::ResourceRangeDesc& range = pd.resourceRanges[r];
                Check(range.baseBinding == pipeline.bindings.size(), "ranges contiguous from binding 0", name);
                pipeline.bindings.insert(pipeline.bindings.end(), range.descriptorsNum, range.descriptorType);
            }
            pipeline.constantBufferSize = pd.constantBufferSize;
            pipelines.push_back(pipeline);
        }
        for (uint32_t s = 0; s < denoiserDesc.samplersNum; s++)
            Check(denoiserDesc.samplers[s] < nrd::Sampler::MAX_NUM, "sampler", "samplers");
        auto checkPool = [](const nrd::TextureDesc* pool, uint32_t num, const char* which)
        {
            for (uint32_t i = 0; i < num; i++)
                Check(pool[i].format < nrd::Format::MAX_NUM && pool[i].downsampleX >= 1 && pool[i].downsampleY >= 1,
                      "pool texture", which);
        };
        checkPool(denoiserDesc.permanentPool, denoiserDesc.permanentPoolSize, "permanent pool");
        checkPool(denoiserDesc.transientPool, denoiserDesc.transientPoolSize, "transient pool");
        permanent.resize(denoiserDesc.permanentPoolSize);
        transient.resize(denoiserDesc.transientPoolSize);
        buffers.resize(denoiserDesc.buffersNum);
    }

    TextureState* StateOf(const nrd::ResourceDesc& resource, const char* name)
    {
        std::vector<TextureState>* pool = resource.type == nrd::ResourceType::PERMANENT_POOL   ? &permanent
                                          : resource.type == nrd::ResourceType::TRANSIENT_POOL ? &transient
                                          : resource.type == nrd::ResourceType::BUFFER_POOL    ? &buffers
                                                                                               : nullptr;
        if (!pool)
        {
            bool isUser = resource.type < nrd::ResourceType::TRANSIENT_POOL;
            Check(isUser && resource.indexInPool == 0, "application resource", name);
            return isUser ? &user[(size_t)resource.type] : nullptr;
        }
        Check(resource.indexInPool < pool->size(), "pool index", name);
        return resource.indexInPool < pool->size() ? &(*pool)[resource.indexInPool] : nullptr;
    }

    // Per dispatch: barriers, descriptor set 0 in binding order, constants into set 1, dispatch.
    void Record(const nrd::DispatchDesc& dispatch)
    {
        const char* name = dispatch.name ? dispatch.name : "?";
        Check(dispatch.pipelineIndex < pipelines.size(), "pipeline index", name);
        if (dispatch.pipelineIndex >= pipelines.size())
            return;
        const Pipeline& pipeline = pipelines[dispatch.pipelineIndex];
        Check(dispatch.resourcesNum == pipeline.bindings.size(), "resource count", name);
        for (uint32_t r = 0; r < dispatch.resourcesNum && r < pipeline.bindings.size(); r++)
        {
            const nrd::ResourceDesc& resource = dispatch.resources[r];
            Check(resource.descriptorType == pipeline.bindings[r], "descriptor type at its binding", name);
            TextureState* state = StateOf(resource, name);
            if (!state)
                continue;
            bool isWrite = resource.descriptorType == nrd::DescriptorType::STORAGE_TEXTURE ||
                           resource.descriptorType == nrd::DescriptorType::STORAGE_BUFFER;
            // RAW: written before, read now. WAW / WAR: written now after a write or reads.
            if ((state->isWritten && !state->isReadSince) || (isWrite && (state->isWritten || state->isReadSince)))
                barriers++;
            if (isWrite)
                *state = {true, false};
            else
                state->isReadSince = true;
        }
        Check(dispatch.constantBufferDataSize == pipeline.constantBufferSize, "constant bytes", name);
        Check(dispatch.constantBufferDataSize == 0 || dispatch.constantBufferData, "constant data", name);
        Check(dispatch.constantBufferDataSize <= desc->constantBufferMaxDataSize, "largest constant block", name);
        if (dispatch.isIndirect)
            Check(dispatch.indirectArgumentsBuffer < buffers.size() && dispatch.indirectArgumentsOffset % 4 == 0,
                  "indirect arguments", name);
        Check(dispatch.gridWidth > 0 && dispatch.gridHeight > 0, "grid", name);
        dispatches++;
    }
};

nrd::CommonSettings CommonSettingsFor(uint32_t frameIndex, uint16_t width, uint16_t height)
{
    nrd::CommonSettings settings = {};
    const float projection[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0.1f, 0};
    const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    std::memcpy(settings.viewToClipMatrix, projection, sizeof(projection));
    std::memcpy(settings.viewToClipMatrixPrev, projection, sizeof(projection));
    std::memcpy(settings.worldToViewMatrix, identity, sizeof(identity));
    std::memcpy(settings.worldToViewMatrixPrev, identity, sizeof(identity));
    settings.resourceSize[0] = width;
    settings.resourceSize[1] = height;
    settings.frameIndex = frameIndex;
    return settings;
}

} // namespace

int main()
{
    const nrd::LibraryDesc& library = nrd::GetLibraryDesc();
    std::printf("NRD %u.%u.%u, %u methods\n", library.versionMajor, library.versionMinor, library.versionBuild,
                library.supportedMethodsNum);
    Check(library.versionMajor == NRD_VERSION_MAJOR && library.versionMinor == NRD_VERSION_MINOR, "version", "library");

    // Every method of the library once (identifier = its enum value), plus a second SIGMA_SHADOW: two lights.
    const nrd::Identifier kLight0 = uint32_t(nrd::Method::SIGMA_SHADOW), kLight1 = 100;
    std::vector<nrd::MethodDesc> methods;
    for (uint32_t m = 0; m < library.supportedMethodsNum; m++)
        methods.push_back({uint32_t(library.supportedMethods[m]), library.supportedMethods[m]});
    methods.push_back({kLight1, nrd::Method::SIGMA_SHADOW});
    nrd::DenoiserCreationDesc creation = {};
    creation.methods = methods.data();
    creation.methodsNum = uint32_t(methods.size());
    creation.renderWidth = 1920;
    creation.renderHeight = 1080;
    creation.logCallback = Log;
    nrd::Denoiser* denoiser = nullptr;
    if (nrd::CreateDenoiser(creation, denoiser) != nrd::Result::SUCCESS)
        return 1;

    Executor executor;
    executor.Create(nrd::GetDenoiserDesc(*denoiser));

    // Frames: all methods; then the first light only; then at a lower dynamic resolution.
    const nrd::Identifier firstLight[] = {kLight0};
    struct
    {
        const nrd::Identifier* identifiers;
        uint32_t identifiersNum;
        uint16_t width, height;
    } frames[] = {{nullptr, 0, 1920, 1080}, {firstLight, 1, 1920, 1080}, {nullptr, 0, 1280, 720}};
    for (uint32_t f = 0; f < 3; f++)
    {
        bool ok = nrd::SetCommonSettings(*denoiser, CommonSettingsFor(f, frames[f].width, frames[f].height)) ==
                  nrd::Result::SUCCESS;
        const nrd::DispatchDesc* dispatches = nullptr;
        uint32_t dispatchesNum = 0;
        ok = ok && nrd::GetComputeDispatches(*denoiser, frames[f].identifiers, frames[f].identifiersNum, dispatches,
                                             dispatchesNum) == nrd::Result::SUCCESS;
        Check(ok && dispatchesNum > 0, "frame produced dispatches", "GetComputeDispatches");
        for (uint32_t d = 0; ok && d < dispatchesNum; d++)
        {
            Check(frames[f].identifiersNum == 0 || dispatches[d].identifier == kLight0, "identifier filter",
                  dispatches[d].name ? dispatches[d].name : "?");
            executor.Record(dispatches[d]);
        }
    }
    std::printf(
        "%u pipelines, %u permanent + %u transient textures, %u buffers; 3 frames: %u dispatches, %u barriers\n",
        executor.desc->pipelinesNum, executor.desc->permanentPoolSize, executor.desc->transientPoolSize,
        executor.desc->buffersNum, executor.dispatches, executor.barriers);
    nrd::DestroyDenoiser(denoiser);

    std::printf("%s\n", g_errors ? "descriptions are INCONSISTENT" : "descriptions are consistent");
    return g_errors ? 1 : 0;
}
