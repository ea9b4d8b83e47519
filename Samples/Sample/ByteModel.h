// The bandwidth model of the benchmark: the fewest bytes a dispatch must move between memory and
// the GPU, from the footprints of the textures and buffers it binds at the formats used.
//
// Every bound texture is counted once at its full size: a sampled texture as read, a storage
// texture as written (a read-modify-write history is counted once, so the figure stays a lower
// bound); pool buffers likewise by their size. Divided by the device's copy bandwidth it gives a
// lower bound on the dispatch's time when the data does not stay in the caches between passes.
#pragma once

#include "NRD.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace nrdlab
{

struct DispatchBytes
{
    uint64_t read = 0;
    uint64_t written = 0;
    uint64_t Total() const
    {
        return read + written;
    }
};

// Bytes per pixel of an application texture (IN_* / OUT_*) as the application created it.
typedef std::function<uint32_t(nrd::ResourceType)> UserBytesPerPixel;

// Minimal bytes of one dispatch binding 'resources' ('resourcesNum' entries) of a denoiser
// described by 'desc', for frames of 'width' x 'height' pixels. Pool textures take their
// downsample factors; resources the description does not know count 0.
DispatchBytes CountDispatchBytes(const nrd::ResourceDesc* resources, uint32_t resourcesNum,
                                 const nrd::DenoiserDesc& desc, uint32_t width, uint32_t height,
                                 const UserBytesPerPixel& userBytesPerPixel);

} // namespace nrdlab
