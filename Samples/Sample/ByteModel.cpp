#include "ByteModel.h"

namespace nrdlab
{

namespace
{

uint64_t DivideUp(uint64_t x, uint64_t y)
{
    return y ? (x + y - 1) / y : 0;
}

uint64_t PoolTextureBytes(const nrd::TextureDesc& texture, uint32_t width, uint32_t height)
{
    return DivideUp(width, texture.downsampleX) * DivideUp(height, texture.downsampleY) *
           nrd::GetFormatBytesPerPixel(texture.format);
}

} // namespace

DispatchBytes CountDispatchBytes(const nrd::ResourceDesc* resources, uint32_t resourcesNum,
                                 const nrd::DenoiserDesc& desc, uint32_t width, uint32_t height,
                                 const UserBytesPerPixel& userBytesPerPixel)
{
    DispatchBytes bytes;
    for (uint32_t r = 0; r < resourcesNum; r++)
    {
        const nrd::ResourceDesc& resource = resources[r];
        uint64_t size = 0;
        switch (resource.type)
        {
        case nrd::ResourceType::PERMANENT_POOL:
            if (resource.indexInPool < desc.permanentPoolSize)
                size = PoolTextureBytes(desc.permanentPool[resource.indexInPool], width, height);
            break;
        case nrd::ResourceType::TRANSIENT_POOL:
            if (resource.indexInPool < desc.transientPoolSize)
                size = PoolTextureBytes(desc.transientPool[resource.indexInPool], width, height);
            break;
        case nrd::ResourceType::BUFFER_POOL:
            if (resource.indexInPool < desc.buffersNum)
                size = desc.buffers[resource.indexInPool].size;
            break;
        default:
            if (resource.type < nrd::ResourceType::TRANSIENT_POOL && userBytesPerPixel)
                size = uint64_t(width) * height * userBytesPerPixel(resource.type);
            break;
        }
        bool writes = resource.descriptorType == nrd::DescriptorType::STORAGE_TEXTURE ||
                      resource.descriptorType == nrd::DescriptorType::STORAGE_BUFFER;
        (writes ? bytes.written : bytes.read) += size;
    }
    return bytes;
}

} // namespace nrdlab
