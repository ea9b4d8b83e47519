#include "InstanceImpl.h"
#include "ShaderTable.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>

namespace nrd
{

void Logger::Error(const char* format, ...) const
{
    if (!m_Callback)
        return;
    char buffer[512];
    va_list args;
    va_start(args, format);
    vsnprintf(buffer, sizeof(buffer), format, args);
    va_end(args);
    m_Callback(m_UserArg, LogSeverity::ERROR, buffer);
}

//==================================================================================================
// Double-precision matrix helpers on GLM (column-major, as the API's matrices).
//==================================================================================================

namespace
{

glm::dmat4 ToDouble(const float* f)
{
    return glm::dmat4(glm::make_mat4(f));
}

glsl::mat4 ToFloat(const glm::dmat4& d)
{
    const glm::mat4 f(d);
    glsl::mat4 r;
    std::memcpy(r.m, glm::value_ptr(f), sizeof(r.m));
    return r;
}

// Inverse of 'src', or false if it is singular relative to its scale: |det| against the product
// of the column lengths (which |det| reaches for orthogonal columns), so that a large translation
// (a camera far from the origin) does not make a rigid transform "singular".
bool Invert(const glm::dmat4& src, glm::dmat4& dst)
{
    const double det = glm::determinant(src);
    double scale = 1.0;
    for (int c = 0; c < 4; c++)
        scale *= glm::length(src[c]);
    if (!std::isfinite(det) || !std::isfinite(scale) || scale == 0.0 || std::fabs(det) <= 1e-12 * scale)
        return false;
    dst = glm::inverse(src);
    return true;
}

bool IsFinite(const float* v, int n)
{
    for (int i = 0; i < n; i++)
        if (!std::isfinite(v[i]))
            return false;
    return true;
}

const char* kMatrixNames[] = {"viewToClipMatrix", "viewToClipMatrixPrev", "worldToViewMatrix", "worldToViewMatrixPrev"};

// A perspective projection with clip w = +-viewZ and a non-degenerate x / y scale.
bool IsSupportedProjection(const float* p)
{
    return std::fabs(std::fabs(p[11]) - 1.0f) < 1e-4f && std::fabs(p[3]) < 1e-6f && std::fabs(p[7]) < 1e-6f &&
           std::fabs(p[15]) < 1e-6f && std::fabs(p[0]) > 1e-6f && std::fabs(p[5]) > 1e-6f;
}

} // namespace

//==================================================================================================
// Creation.
//==================================================================================================

InstanceImpl::InstanceImpl(const DenoiserCreationDesc& desc)
    : m_AllocationCallbacks(desc.allocationCallbacks),
      m_Allocator(desc.allocationCallbacks.Allocate && desc.allocationCallbacks.Free && desc.allocationCallbacks.Reallocate
                      ? &m_AllocationCallbacks
                      : nullptr),
      m_Log(desc.logCallback, desc.logUserArg), m_Methods(StdAllocator<MethodData>(m_Allocator)),
      m_Pipelines(StdAllocator<PipelineDesc>(m_Allocator)), m_Ranges(StdAllocator<ResourceRangeDesc>(m_Allocator)),
      m_PipelineRangeFirst(StdAllocator<uint32_t>(m_Allocator)), m_PermanentPool(StdAllocator<TextureDesc>(m_Allocator)),
      m_TransientPool(StdAllocator<TextureDesc>(m_Allocator)), m_Buffers(StdAllocator<BufferDesc>(m_Allocator)),
      m_Samplers(StdAllocator<Sampler>(m_Allocator)), m_Templates(StdAllocator<DispatchTemplate>(m_Allocator)),
      m_Resources(StdAllocator<ResourceDesc>(m_Allocator)), m_Output(StdAllocator<DispatchDesc>(m_Allocator))
{
}

Result InstanceImpl::Create(const DenoiserCreationDesc& desc)
{
    if (!desc.methods || desc.methodsNum == 0)
    {
        m_Log.Error("CreateDenoiser: 'methods' is null or 'methodsNum' is 0");
        return Result::INVALID_ARGUMENT;
    }
    constexpr uint16_t kMaxSize = 16384;
    if (desc.renderWidth == 0 || desc.renderHeight == 0 || desc.renderWidth > kMaxSize || desc.renderHeight > kMaxSize)
    {
        m_Log.Error("CreateDenoiser: render size %ux%u is outside 1..%u", desc.renderWidth, desc.renderHeight, kMaxSize);
        return Result::INVALID_ARGUMENT;
    }
    bool hasAllocate = desc.allocationCallbacks.Allocate != nullptr;
    if (hasAllocate != (desc.allocationCallbacks.Free != nullptr) ||
        hasAllocate != (desc.allocationCallbacks.Reallocate != nullptr))
    {
        m_Log.Error("CreateDenoiser: set all three allocation callbacks or none");
        return Result::INVALID_ARGUMENT;
    }
    for (uint32_t i = 0; i < desc.methodsNum; i++)
    {
        if (uint32_t(desc.methods[i].method) >= uint32_t(Method::MAX_NUM))
        {
            m_Log.Error("CreateDenoiser: methods[%u] has unknown method %u", i, uint32_t(desc.methods[i].method));
            return Result::INVALID_ARGUMENT;
        }
        for (uint32_t j = 0; j < i; j++)
            if (desc.methods[j].identifier == desc.methods[i].identifier)
            {
                m_Log.Error("CreateDenoiser: identifier %u is used by methods[%u] and methods[%u]",
                            desc.methods[i].identifier, j, i);
                return Result::NON_UNIQUE_IDENTIFIER;
            }
    }

    m_Desc.renderWidth = desc.renderWidth;
    m_Desc.renderHeight = desc.renderHeight;
    m_Samplers = {Sampler::NEAREST_CLAMP, Sampler::LINEAR_CLAMP};

    m_Methods.reserve(desc.methodsNum);
    for (uint32_t i = 0; i < desc.methodsNum; i++)
        m_Methods.emplace_back(m_Allocator);
    for (uint32_t i = 0; i < desc.methodsNum; i++)
    {
        MethodData& method = m_Methods[i];
        method.desc = desc.methods[i];
        MethodBuilder builder(*this, i);
        switch (method.desc.method)
        {
        case Method::SIGMA_SHADOW:
        case Method::SIGMA_SHADOW_TRANSLUCENCY:
            method.impl = CreateSigma(builder, method.desc.method);
            break;
        case Method::REFERENCE:
            method.impl = CreateReference(builder, method.desc.method);
            break;
        case Method::TILED_SHADOW:
            method.impl = CreateTiledShadow(builder, method.desc.method);
            break;
        case Method::REBLUR_DIFFUSE:
        case Method::REBLUR_SPECULAR:
        case Method::REBLUR_DIFFUSE_SPECULAR:
        case Method::REBLUR_DIFFUSE_OCCLUSION:
        case Method::REBLUR_SPECULAR_OCCLUSION:
        case Method::REBLUR_DIFFUSE_SPECULAR_OCCLUSION:
            method.impl = CreateReblur(builder, method.desc.method);
            break;
        case Method::CONFIDENCE:
            method.impl = CreateConfidence(builder, method.desc.method);
            break;
        case Method::REFLECTION:
            method.impl = CreateReflection(builder, method.desc.method);
            break;
        case Method::RELAX_DIFFUSE:
        case Method::RELAX_SPECULAR:
        case Method::RELAX_DIFFUSE_SPECULAR:
            method.impl = CreateRelax(builder, method.desc.method);
            break;
        case Method::MAX_NUM:
            break;
        }
        if (!method.impl || m_BuildFailed)
        {
            m_Log.Error("CreateDenoiser: internal error while building %s", GetMethodString(method.desc.method));
            return Result::FAILURE;
        }
    }

    FinalizePools();
    return Result::SUCCESS;
}

ResourceRef MethodBuilder::AddPermanentTexture(Format format, uint16_t downsampleX, uint16_t downsampleY)
{
    m_Instance.m_PermanentPool.push_back({format, downsampleX, downsampleY});
    return {ResourceType::PERMANENT_POOL, uint16_t(m_Instance.m_PermanentPool.size() - 1)};
}

ResourceRef MethodBuilder::AddTransientTexture(Format format, uint16_t downsampleX, uint16_t downsampleY)
{
    auto& transients = m_Instance.m_Methods[m_MethodIndex].transients;
    transients.push_back({format, downsampleX, downsampleY});
    return {ResourceType::TRANSIENT_POOL, uint16_t(transients.size() - 1)};
}

uint32_t MethodBuilder::RenderWidth() const { return m_Instance.m_Desc.renderWidth; }
uint32_t MethodBuilder::RenderHeight() const { return m_Instance.m_Desc.renderHeight; }

ResourceRef MethodBuilder::AddBuffer(const BufferDesc& desc)
{
    m_Instance.m_Buffers.push_back(desc);
    m_Instance.m_Buffers.back().identifier = m_Instance.m_Methods[m_MethodIndex].desc.identifier;
    return {ResourceType::BUFFER_POOL, uint16_t(m_Instance.m_Buffers.size() - 1)};
}

static bool IsCompatible(DescriptorType descriptorType, ResourceType type)
{
    switch (type)
    {
    case ResourceType::TRANSIENT_POOL:
    case ResourceType::PERMANENT_POOL:
        return descriptorType == DescriptorType::TEXTURE || descriptorType == DescriptorType::STORAGE_TEXTURE;
    case ResourceType::BUFFER_POOL:
        return descriptorType == DescriptorType::BUFFER || descriptorType == DescriptorType::STORAGE_BUFFER;
    case ResourceType::OUT_SHADOW_TRANSLUCENCY:
    case ResourceType::OUT_RADIANCE:
    case ResourceType::OUT_DIFF_RADIANCE_HITDIST:
    case ResourceType::OUT_SPEC_RADIANCE_HITDIST:
    case ResourceType::OUT_DIFF_HITDIST:
    case ResourceType::OUT_SPEC_HITDIST:
    case ResourceType::OUT_DIFF_CONFIDENCE:
    case ResourceType::OUT_SPEC_CONFIDENCE:
        return descriptorType == DescriptorType::STORAGE_TEXTURE || descriptorType == DescriptorType::TEXTURE;
    case ResourceType::MAX_NUM:
        return false;
    default:
        return descriptorType == DescriptorType::TEXTURE; // Application inputs are read-only.
    }
}

uint32_t MethodBuilder::AddDispatchImpl(const char* name, const char* shaderName, const BindingDecl* bindings,
                                        uint32_t bindingsNum, bool hasConstants, uint32_t constantsSize, uint16_t groupX,
                                        uint16_t groupY, const ResourceRef* resources, uint32_t resourcesNum)
{
    InstanceImpl& inst = m_Instance;
    if (resourcesNum != bindingsNum)
    {
        inst.m_Log.Error("internal: dispatch '%s' has %u resources, pass %s declares %u", name, resourcesNum, shaderName,
                         bindingsNum);
        inst.m_BuildFailed = true;
    }

    DispatchTemplate t;
    t.name = name;
    t.pipelineIndex = inst.AddPipeline(shaderName, bindings, bindingsNum, hasConstants, constantsSize, groupX, groupY);
    t.firstResource = uint32_t(inst.m_Resources.size());
    t.resourcesNum = resourcesNum;
    t.constantsSize = constantsSize;
    t.groupX = groupX;
    t.groupY = groupY;
    for (uint32_t i = 0; i < resourcesNum && i < bindingsNum; i++)
    {
        if (!IsCompatible(bindings[i].descriptorType, resources[i].type))
        {
            inst.m_Log.Error("internal: dispatch '%s' binds %s to %s (%s)", name,
                             GetResourceTypeString(resources[i].type), bindings[i].name, shaderName);
            inst.m_BuildFailed = true;
        }
        ResourceDesc r;
        r.descriptorType = bindings[i].descriptorType;
        r.type = resources[i].type;
        r.indexInPool = resources[i].index; // Transient indices are remapped in FinalizePools.
        inst.m_Resources.push_back(r);
    }
    inst.m_Templates.push_back(t);
    auto& templates = inst.m_Methods[m_MethodIndex].templates;
    templates.push_back(uint32_t(inst.m_Templates.size() - 1));
    return uint32_t(templates.size() - 1);
}

uint16_t InstanceImpl::AddPipeline(const char* shaderName, const BindingDecl* bindings, uint32_t bindingsNum,
                                   bool hasConstants, uint32_t constantsSize, uint16_t groupX, uint16_t groupY)
{
    // Pipelines are shared between dispatches and methods: one per shader.
    for (size_t i = 0; i < m_Pipelines.size(); i++)
        if (strcmp(m_Pipelines[i].shaderIdentifier, shaderName) == 0)
            return uint16_t(i);

    uint32_t count = 0;
    const ShaderBytecode* table = GetShaderTable(count);
    const ShaderBytecode* shader = nullptr;
    for (uint32_t i = 0; i < count; i++)
        if (strcmp(table[i].name, shaderName) == 0)
            shader = &table[i];
    if (!shader)
    {
        m_Log.Error("internal: no embedded SPIR-V for pass %s", shaderName);
        m_BuildFailed = true;
    }

    PipelineDesc p;
    p.spirv.bytecode = shader ? shader->words : nullptr;
    p.spirv.size = shader ? shader->size : 0;
    p.entryPointName = "main";
    p.shaderIdentifier = shaderName;
    p.hasConstantData = hasConstants;
    p.constantBufferSize = constantsSize;
    p.groupSizeX = groupX;
    p.groupSizeY = groupY;
    m_PipelineRangeFirst.push_back(uint32_t(m_Ranges.size()));
    for (uint32_t i = 0; i < bindingsNum; i++)
    {
        if (i > 0 && m_Ranges.back().descriptorType == bindings[i].descriptorType)
            m_Ranges.back().descriptorsNum++;
        else
            m_Ranges.push_back({bindings[i].descriptorType, i, 1});
    }
    p.resourceRangesNum = uint32_t(m_Ranges.size()) - m_PipelineRangeFirst.back();
    m_Pipelines.push_back(p);
    return uint16_t(m_Pipelines.size() - 1);
}

void InstanceImpl::FinalizePools()
{
    // Transient textures are free between methods: method k's i-th texture of a given shape reuses
    // the shared pool's i-th texture of that shape.
    for (MethodData& method : m_Methods)
    {
        method.transientRemap.resize(method.transients.size());
        for (size_t i = 0; i < method.transients.size(); i++)
        {
            const TextureDesc& t = method.transients[i];
            uint32_t occurrence = 0;
            for (size_t j = 0; j < i; j++)
            {
                const TextureDesc& o = method.transients[j];
                occurrence += (o.format == t.format && o.downsampleX == t.downsampleX && o.downsampleY == t.downsampleY);
            }
            uint32_t found = 0;
            bool mapped = false;
            for (size_t k = 0; k < m_TransientPool.size() && !mapped; k++)
            {
                const TextureDesc& p = m_TransientPool[k];
                if (p.format == t.format && p.downsampleX == t.downsampleX && p.downsampleY == t.downsampleY)
                {
                    if (found == occurrence)
                    {
                        method.transientRemap[i] = uint16_t(k);
                        mapped = true;
                    }
                    found++;
                }
            }
            if (!mapped)
            {
                m_TransientPool.push_back(t);
                method.transientRemap[i] = uint16_t(m_TransientPool.size() - 1);
            }
        }
        for (uint32_t localIndex : method.templates)
        {
            const DispatchTemplate& t = m_Templates[localIndex];
            for (uint32_t r = 0; r < t.resourcesNum; r++)
            {
                ResourceDesc& res = m_Resources[t.firstResource + r];
                if (res.type == ResourceType::TRANSIENT_POOL)
                    res.indexInPool = method.transientRemap[res.indexInPool];
            }
        }
    }

    // Pipelines' range pointers are stable now.
    for (size_t i = 0; i < m_Pipelines.size(); i++)
        m_Pipelines[i].resourceRanges = m_Ranges.data() + m_PipelineRangeFirst[i];

    DescriptorPoolDesc pool = {};
    uint32_t maxConstants = 0;
    for (const DispatchTemplate& t : m_Templates)
    {
        // Each template is dispatched at most once per frame (FrameContext enforces it).
        pool.setsMaxNum++;
        const PipelineDesc& p = m_Pipelines[t.pipelineIndex];
        if (p.hasConstantData)
            pool.constantBuffersMaxNum++;
        pool.samplersMaxNum += uint32_t(m_Samplers.size());
        for (uint32_t r = 0; r < t.resourcesNum; r++)
        {
            switch (m_Resources[t.firstResource + r].descriptorType)
            {
            case DescriptorType::TEXTURE: pool.texturesMaxNum++; break;
            case DescriptorType::STORAGE_TEXTURE: pool.storageTexturesMaxNum++; break;
            default: pool.buffersMaxNum++; break;
            }
        }
        maxConstants = t.constantsSize > maxConstants ? t.constantsSize : maxConstants;
    }

    m_Desc.pipelines = m_Pipelines.data();
    m_Desc.pipelinesNum = uint32_t(m_Pipelines.size());
    m_Desc.samplers = m_Samplers.data();
    m_Desc.samplersNum = uint32_t(m_Samplers.size());
    m_Desc.permanentPool = m_PermanentPool.data();
    m_Desc.permanentPoolSize = uint32_t(m_PermanentPool.size());
    m_Desc.transientPool = m_TransientPool.data();
    m_Desc.transientPoolSize = uint32_t(m_TransientPool.size());
    m_Desc.buffers = m_Buffers.data();
    m_Desc.buffersNum = uint32_t(m_Buffers.size());
    m_Desc.constantBufferMaxDataSize = maxConstants;
    m_Desc.descriptorPoolDesc = pool;
}

//==================================================================================================
// Settings.
//==================================================================================================

Result InstanceImpl::SetCommonSettings(const CommonSettings& s)
{
    const float* matrices[] = {s.viewToClipMatrix, s.viewToClipMatrixPrev, s.worldToViewMatrix, s.worldToViewMatrixPrev};
    for (int i = 0; i < 4; i++)
    {
        if (!IsFinite(matrices[i], 16))
        {
            m_Log.Error("SetCommonSettings: %s has a NaN or Inf element", kMatrixNames[i]);
            return Result::INVALID_ARGUMENT;
        }
    }
    for (int i = 0; i < 2; i++)
    {
        if (!IsSupportedProjection(matrices[i]))
        {
            m_Log.Error("SetCommonSettings: %s must be a perspective projection with clip w = +-viewZ "
                        "(column-major, m[11] = +-1, m[15] = 0)", kMatrixNames[i]);
            return Result::INVALID_ARGUMENT;
        }
    }
    glm::dmat4 viewToWorld, viewToWorldPrev;
    if (!Invert(ToDouble(s.worldToViewMatrix), viewToWorld) || !Invert(ToDouble(s.worldToViewMatrixPrev), viewToWorldPrev))
    {
        m_Log.Error("SetCommonSettings: worldToViewMatrix or worldToViewMatrixPrev is singular");
        return Result::INVALID_ARGUMENT;
    }
    const float* jitters[] = {s.cameraJitter, s.cameraJitterPrev};
    for (const float* j : jitters)
    {
        for (int i = 0; i < 2; i++)
            if (!(j[i] >= -0.5f && j[i] <= 0.5f))
            {
                m_Log.Error("SetCommonSettings: camera jitter %g is outside [-0.5, 0.5]", double(j[i]));
                return Result::INVALID_ARGUMENT;
            }
    }
    if (!IsFinite(s.motionVectorScale, 3))
    {
        m_Log.Error("SetCommonSettings: motionVectorScale has a NaN or Inf element");
        return Result::INVALID_ARGUMENT;
    }
    if (!(s.denoisingRange > 0.0f) || !std::isfinite(s.denoisingRange))
    {
        m_Log.Error("SetCommonSettings: denoisingRange must be finite and > 0 (got %g)", double(s.denoisingRange));
        return Result::INVALID_ARGUMENT;
    }
    if (!(s.disocclusionThreshold > 0.0f && s.disocclusionThreshold <= 1.0f))
    {
        m_Log.Error("SetCommonSettings: disocclusionThreshold must be in (0, 1] (got %g)", double(s.disocclusionThreshold));
        return Result::INVALID_ARGUMENT;
    }
    if (uint32_t(s.accumulationMode) > uint32_t(AccumulationMode::RESTART))
    {
        m_Log.Error("SetCommonSettings: unknown accumulationMode %u", uint32_t(s.accumulationMode));
        return Result::INVALID_ARGUMENT;
    }
    uint32_t width = s.resourceSize[0] ? s.resourceSize[0] : m_Desc.renderWidth;
    uint32_t height = s.resourceSize[1] ? s.resourceSize[1] : m_Desc.renderHeight;
    if (width > m_Desc.renderWidth || height > m_Desc.renderHeight || (s.resourceSize[0] == 0) != (s.resourceSize[1] == 0))
    {
        m_Log.Error("SetCommonSettings: resourceSize %ux%u must be 0x0 or within the creation size %ux%u",
                    s.resourceSize[0], s.resourceSize[1], m_Desc.renderWidth, m_Desc.renderHeight);
        return Result::INVALID_ARGUMENT;
    }

    FrameData& f = m_Frame;
    f.common = s;
    f.width = width;
    f.height = height;
    f.resetHistory = !m_HasPrevFrame || s.frameIndex == 0 || s.accumulationMode == AccumulationMode::RESTART ||
                     width != m_PrevWidth || height != m_PrevHeight;
    const float* p = s.viewToClipMatrix;
    f.viewZSign = p[11] > 0.0f ? 1.0f : -1.0f;
    f.frustum = {1.0f / p[0], -p[8] * f.viewZSign / p[0], 1.0f / p[5], -p[9] * f.viewZSign / p[5]};
    f.projectY = 0.5f * float(height) * std::fabs(p[5]);
    // The passes' world space is camera-relative (the origin at this frame's camera, the axes the
    // world's): a world far from the origin would lose its positions' low bits in float, and a still
    // view would reproject its history a fraction of a pixel off (SIGMA on a still scene 100 km from
    // the origin: 4.7x the relMSE). Only differences of world positions and directions reach the
    // passes, so moving the origin changes nothing else; the products are formed in double.
    glm::dmat4 fromCamera(1.0); // Camera-relative -> world.
    fromCamera[3] = glm::dvec4(glm::dvec3(viewToWorld[3]), 1.0);
    glm::dmat4 viewToCameraRelative = viewToWorld;
    viewToCameraRelative[3] = glm::dvec4(0.0, 0.0, 0.0, 1.0);
    f.viewToWorld = ToFloat(viewToCameraRelative);
    f.viewToClip = ToFloat(ToDouble(s.viewToClipMatrix));
    f.worldToViewPrev = ToFloat(ToDouble(s.worldToViewMatrixPrev) * fromCamera);
    f.worldToClipPrev = ToFloat(ToDouble(s.viewToClipMatrixPrev) * ToDouble(s.worldToViewMatrixPrev) * fromCamera);
    // Clip -> previous clip from double products, so large world coordinates cancel before anything
    // is rounded to float: viewToClipPrev * worldToViewPrev * viewToWorld * inverse(viewToClip).
    glm::dmat4 clipToView;
    f.isClipToClipPrevValid = Invert(ToDouble(s.viewToClipMatrix), clipToView);
    if (f.isClipToClipPrevValid)
    {
        const glm::dmat4 viewToViewPrev = ToDouble(s.worldToViewMatrixPrev) * viewToWorld;
        f.clipToClipPrev = ToFloat(ToDouble(s.viewToClipMatrixPrev) * viewToViewPrev * clipToView);
    }
    else
        f.clipToClipPrev = glsl::mat4{{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};

    m_PrevWidth = width;
    m_PrevHeight = height;
    m_HasPrevFrame = true;
    m_Epoch++;
    return Result::SUCCESS;
}

Result InstanceImpl::SetMethodSettings(Identifier identifier, SettingsKind kind, const void* settings)
{
    for (MethodData& method : m_Methods)
        if (method.desc.identifier == identifier)
            return method.impl->SetSettings(kind, settings, m_Log);
    m_Log.Error("SetMethodSettings: unknown identifier %u", identifier);
    return Result::INVALID_ARGUMENT;
}

//==================================================================================================
// Dispatches.
//==================================================================================================

void FrameContext::PushDispatch(uint32_t templateIndex, const void* constants, uint32_t size, uint32_t threadsX,
                                uint32_t threadsY, const IndirectArgs* indirect)
{
    InstanceImpl::MethodData& method = m_Instance.m_Methods[m_MethodIndex];
    if (templateIndex >= method.templates.size())
    {
        m_Instance.m_Log.Error("internal: dispatch template %u does not exist", templateIndex);
        m_Failed = true;
        return;
    }
    const DispatchTemplate& t = m_Instance.m_Templates[method.templates[templateIndex]];
    // Descriptor pool sizes assume each template runs at most once per frame.
    for (const DispatchDesc& previous : method.dispatches)
        if (previous.name == t.name && previous.resources == m_Instance.m_Resources.data() + t.firstResource)
        {
            m_Instance.m_Log.Error("internal: dispatch '%s' added twice in one frame", t.name);
            m_Failed = true;
            return;
        }

    DispatchDesc d;
    d.name = t.name;
    d.identifier = method.desc.identifier;
    d.pipelineIndex = t.pipelineIndex;
    d.resources = m_Instance.m_Resources.data() + t.firstResource;
    d.resourcesNum = t.resourcesNum;
    d.constantBufferDataSize = t.constantsSize;
    uint32_t gridX = DivideUp(threadsX, t.groupX), gridY = DivideUp(threadsY, t.groupY);
    d.gridWidth = uint16_t(gridX > 65535 ? 65535 : gridX);
    d.gridHeight = uint16_t(gridY > 65535 ? 65535 : gridY);
    if (indirect)
    {
        d.isIndirect = true;
        d.indirectArgumentsBuffer = indirect->buffer.index;
        d.indirectArgumentsOffset = indirect->offset;
    }
    method.constantOffsets.push_back(uint32_t(method.constants.size()));
    if (t.constantsSize)
    {
        const uint8_t* bytes = static_cast<const uint8_t*>(constants);
        uint32_t copied = size < t.constantsSize ? size : t.constantsSize;
        method.constants.insert(method.constants.end(), bytes, bytes + copied);
        method.constants.resize(method.constants.size() + (t.constantsSize - copied), 0);
    }
    method.dispatches.push_back(d);
    method.stages.push_back(m_Stage);
}

bool InstanceImpl::UpdateMethod(uint32_t methodIndex)
{
    MethodData& method = m_Methods[methodIndex];
    method.dispatches.clear();
    method.constants.clear();
    method.constantOffsets.clear();
    method.stages.clear();
    FrameContext context(*this, methodIndex, m_Frame);
    method.impl->Update(context);
    if (context.Failed())
    {
        // Nothing of an incomplete frame is handed out; the next call records it again.
        method.dispatches.clear();
        method.stages.clear();
        return false;
    }
    for (size_t i = 0; i < method.dispatches.size(); i++)
        method.dispatches[i].constantBufferData =
            method.dispatches[i].constantBufferDataSize ? method.constants.data() + method.constantOffsets[i] : nullptr;
    method.updatedEpoch = m_Epoch;
    return true;
}

Result InstanceImpl::GetComputeDispatches(const Identifier* identifiers, uint32_t identifiersNum, DispatchStage stage,
                                          const DispatchDesc*& outDispatches, uint32_t& outDispatchesNum)
{
    outDispatches = nullptr;
    outDispatchesNum = 0;
    if (uint32_t(stage) >= uint32_t(DispatchStage::MAX_NUM))
    {
        m_Log.Error("GetComputeDispatches: unknown stage %u", uint32_t(stage));
        return Result::INVALID_ARGUMENT;
    }
    if (m_Epoch == 0)
    {
        m_Log.Error("GetComputeDispatches: call SetCommonSettings successfully first");
        return Result::INVALID_ARGUMENT;
    }
    if (identifiersNum && !identifiers)
    {
        m_Log.Error("GetComputeDispatches: 'identifiers' is null but 'identifiersNum' is %u", identifiersNum);
        return Result::INVALID_ARGUMENT;
    }

    // Validate everything before touching any state.
    Vector<uint32_t> order{StdAllocator<uint32_t>(m_Allocator)};
    if (identifiersNum == 0)
    {
        for (uint32_t i = 0; i < m_Methods.size(); i++)
            order.push_back(i);
    }
    for (uint32_t k = 0; k < identifiersNum; k++)
    {
        uint32_t found = uint32_t(m_Methods.size());
        for (uint32_t i = 0; i < m_Methods.size(); i++)
            if (m_Methods[i].desc.identifier == identifiers[k])
                found = i;
        if (found == m_Methods.size())
        {
            m_Log.Error("GetComputeDispatches: unknown identifier %u", identifiers[k]);
            return Result::INVALID_ARGUMENT;
        }
        // A repeat would run the method twice in one frame (and overflow the descriptor pool sizes).
        for (uint32_t previous : order)
            if (previous == found)
            {
                m_Log.Error("GetComputeDispatches: identifier %u is listed twice", identifiers[k]);
                return Result::INVALID_ARGUMENT;
            }
        order.push_back(found);
    }

    m_Output.clear();
    for (uint32_t i : order)
    {
        if (m_Methods[i].updatedEpoch != m_Epoch && !UpdateMethod(i))
        {
            m_Output.clear();
            m_Log.Error("GetComputeDispatches: method %u could not record its dispatches (internal error above)",
                        uint32_t(m_Methods[i].desc.method));
            return Result::FAILURE;
        }
        const MethodData& method = m_Methods[i];
        for (size_t d = 0; d < method.dispatches.size(); d++)
            if (stage == DispatchStage::ALL || method.stages[d] == stage)
                m_Output.push_back(method.dispatches[d]);
    }
    outDispatches = m_Output.data();
    outDispatchesNum = uint32_t(m_Output.size());
    return Result::SUCCESS;
}

} // namespace nrd
