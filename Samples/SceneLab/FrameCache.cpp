// FrameCache.cpp - raw float dumps keyed by a hash of everything that determines their content.
#include "FrameCache.h"

#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

namespace nrdlab
{

namespace
{

constexpr char kMagic[8] = {'N', 'R', 'D', 'L', 'A', 'B', '0', '1'};

template <class T>
void Put(std::ofstream& f, const T& v)
{
    f.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
bool Get(std::ifstream& f, T& v)
{
    return bool(f.read(reinterpret_cast<char*>(&v), sizeof(T)));
}

} // namespace

uint64_t Fnv1a64(const void* data, size_t size, uint64_t hash)
{
    const uint8_t* p = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < size; i++)
    {
        hash ^= p[i];
        hash *= 0x100000001b3ull;
    }
    return hash;
}

std::string FrameCache::GetPath(const std::string& readablePrefix, const std::string& key) const
{
    char hex[17];
    std::snprintf(hex, sizeof(hex), "%016llx", (unsigned long long)Fnv1a64(key.data(), key.size()));
    std::string prefix;
    for (char ch : readablePrefix)
        prefix += (std::isalnum((unsigned char)ch) || ch == '-' || ch == '_') ? ch : '_';
    return m_Directory + "/" + prefix + "-" + hex + ".bin";
}

bool FrameCache::Load(const std::string& path, std::vector<CachedImage>& out) const
{
    if (!IsEnabled())
        return false;
    std::ifstream f(path, std::ios::binary);
    if (!f)
        return false;
    char magic[8] = {};
    uint32_t count = 0;
    if (!f.read(magic, 8) || std::memcmp(magic, kMagic, 8) != 0 || !Get(f, count) || count > 64)
        return false;
    std::vector<CachedImage> images(count);
    for (CachedImage& ci : images)
    {
        uint32_t nameLength = 0, w = 0, h = 0, ch = 0;
        if (!Get(f, nameLength) || nameLength > 256)
            return false;
        ci.name.resize(nameLength);
        if (!f.read(&ci.name[0], nameLength) || !Get(f, w) || !Get(f, h) || !Get(f, ch))
            return false;
        if (w > 65536 || h > 65536 || ch > 4)
            return false;
        ci.image = Image(w, h, ch);
        size_t bytes = ci.image.pixels.size() * sizeof(float);
        if (bytes && !f.read(reinterpret_cast<char*>(ci.image.pixels.data()), std::streamsize(bytes)))
            return false;
    }
    out = std::move(images);
    return true;
}

void FrameCache::Store(const std::string& path, const std::vector<CachedImage>& images) const
{
    if (!IsEnabled())
        return;
    std::error_code ec;
    std::filesystem::create_directories(m_Directory, ec);
    std::random_device rd;
    std::string tmp = path + ".tmp" + std::to_string(rd());
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f)
            return;
        f.write(kMagic, 8);
        Put(f, uint32_t(images.size()));
        for (const CachedImage& ci : images)
        {
            Put(f, uint32_t(ci.name.size()));
            f.write(ci.name.data(), std::streamsize(ci.name.size()));
            Put(f, ci.image.width);
            Put(f, ci.image.height);
            Put(f, ci.image.channels);
            f.write(reinterpret_cast<const char*>(ci.image.pixels.data()),
                    std::streamsize(ci.image.pixels.size() * sizeof(float)));
        }
        if (!f)
        {
            f.close();
            std::filesystem::remove(tmp, ec);
            return;
        }
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec)
        std::filesystem::remove(tmp, ec);
}

} // namespace nrdlab
