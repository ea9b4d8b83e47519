// FrameCache.h - the scene lab's on-disk frame cache (private to the lab).
//
// One file per (scene, size, seed, frame, part, part parameters): a few named float images in a
// raw little-endian dump. Files are written to a temporary name and renamed, so concurrent
// processes sharing a cache never read a partial file.
#pragma once

#include "Image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace nrdlab
{

struct CachedImage
{
    std::string name;
    Image image;
};

// FNV-1a 64.
uint64_t Fnv1a64(const void* data, size_t size, uint64_t hash = 0xcbf29ce484222325ull);

class FrameCache
{
public:
    void SetDirectory(const std::string& directory) { m_Directory = directory; }
    bool IsEnabled() const { return !m_Directory.empty(); }

    // Path of the entry for 'key' (a readable prefix + hash of the key).
    std::string GetPath(const std::string& readablePrefix, const std::string& key) const;

    // Loads every image of an entry. False if it does not exist or is damaged (then ignored).
    bool Load(const std::string& path, std::vector<CachedImage>& out) const;

    // Best effort: failures (read-only disk, ...) only mean the next call renders again.
    void Store(const std::string& path, const std::vector<CachedImage>& images) const;

private:
    std::string m_Directory;
};

} // namespace nrdlab
