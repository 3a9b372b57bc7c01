// TileCache: the streamed distance field's tiles on disk (tile_cache.h).
#include "tile_cache.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/map/lidar_map.h>
#include <sstream>
#include <thread>

namespace quasiloc::map::detail
{
namespace
{
constexpr char kMagic[4] = {'Q', 'L', 'F', 'T'};
constexpr uint32_t kVersion = 1;

/** Word-wise FNV-1a: fast enough for 10^8 points (a multiply per 4 bytes). */
uint64_t mix(uint64_t h, const void* data, size_t bytes)
{
    const auto* p = static_cast<const unsigned char*>(data);
    size_t i = 0;
    for (; i + 4 <= bytes; i += 4)
    {
        uint32_t w;
        std::memcpy(&w, p + i, 4);
        h = (h ^ w) * 0x100000001b3ull;
    }
    for (; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}
constexpr uint64_t kSeed = 0xcbf29ce484222325ull;

std::string readAll(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string headerText(const TileGrid& g, uint64_t map_hash, size_t map_points)
{
    char text[512];
    std::snprintf(text, sizeof(text),
                  "quasiloc distance field tiles %u\nmap_points %zu\nmap_hash %016llx\nvoxel_m %.9g\n"
                  "max_distance_m %.9g\norigin %.9g %.9g %.9g\nvoxels %d %d %d\ntile_bricks %d\nbrick_voxels %d\n",
                  kVersion, map_points, static_cast<unsigned long long>(map_hash), double(g.voxel),
                  double(g.max_distance), double(g.origin.x()), double(g.origin.y()), double(g.origin.z()),
                  g.voxels.x(), g.voxels.y(), g.voxels.z(), kTile, kBrick);
    return text;
}

/** The first line where a and b differ, as "cache: <a line>, now: <b line>". */
std::string firstDifference(const std::string& a, const std::string& b)
{
    std::istringstream sa(a), sb(b);
    std::string la, lb;
    while (true)
    {
        const bool ga = bool(std::getline(sa, la)), gb = bool(std::getline(sb, lb));
        if (!ga && !gb) return "";
        if (la != lb || ga != gb) return "the cache has \"" + la + "\", this map and these options \"" + lb + "\"";
    }
}
}  // namespace

uint64_t hashMapPoints(const LidarMap& map)
{
    // Three arrays hashed on their own threads, then combined.
    uint64_t h[3] = {kSeed, kSeed, kSeed};
    const float* arrays[3] = {map.xs(), map.ys(), map.zs()};
    const size_t bytes = map.size() * sizeof(float);
    std::thread a([&] { h[0] = mix(h[0], arrays[0], bytes); });
    std::thread b([&] { h[1] = mix(h[1], arrays[1], bytes); });
    h[2] = mix(h[2], arrays[2], bytes);
    a.join();
    b.join();
    const uint64_t n = map.size();
    return mix(mix(kSeed, &n, sizeof(n)), h, sizeof(h));
}

TileCache::TileCache(const std::string& folder, const TileGrid& grid, uint64_t map_hash, size_t map_points)
    : folder_(folder), header_path_(folder + "/header.txt"), tiles_(grid.tiles())
{
    header_text_ = headerText(grid, map_hash, map_points);
    header_hash_ = mix(kSeed, header_text_.data(), header_text_.size());
    std::error_code ec;
    std::filesystem::create_directories(folder_, ec);
    core::require(!ec && std::filesystem::is_directory(folder_), folder_,
                  "cannot create the distance field's tile cache folder");
    if (!std::filesystem::exists(header_path_))
    {
        core::writeTextFileAtomically(header_path_, header_text_);
        return;
    }
    const std::string found = readAll(header_path_);
    if (found != header_text_)
        throw core::InputError(header_path_, "a distance field tile cache of another map or other field options (" +
                                                 firstDifference(found, header_text_) +
                                                 "): delete the folder, or give another tile cache folder");
    const std::string list_path = folder_ + "/nonempty.bin";
    if (!std::filesystem::exists(list_path)) return;
    const std::string list = readAll(list_path);
    const size_t n = size_t(tiles_.prod());
    uint64_t stored = 0;
    if (list.size() == n + 16) std::memcpy(&stored, list.data() + n + 8, 8);
    core::require(list.size() == n + 16 && std::memcmp(list.data() + n, &header_hash_, 8) == 0 &&
                      stored == mix(header_hash_, list.data(), n),
                  list_path, "corrupt (its size, header hash or checksum is wrong): delete it to rebuild the tiles");
    nonempty_.assign(list.begin(), list.begin() + std::ptrdiff_t(n));
    complete_ = true;
}

std::string TileCache::tilePath(const Eigen::Vector3i& t) const
{
    return folder_ + "/t_" + std::to_string(t.x()) + "_" + std::to_string(t.y()) + "_" + std::to_string(t.z()) + ".bin";
}

void TileCache::write(const Eigen::Vector3i& tile, const TileBricks& bricks) const
{
    std::string blob(kMagic, 4);
    const auto put = [&](const void* p, size_t n) { blob.append(static_cast<const char*>(p), n); };
    const uint32_t count = uint32_t(bricks.size());
    const int32_t t[3] = {tile.x(), tile.y(), tile.z()};
    put(&kVersion, 4);
    put(&header_hash_, 8);
    put(t, sizeof(t));
    put(&count, 4);
    for (const auto& [in_tile, values] : bricks)
    {
        const uint16_t index = uint16_t(in_tile);
        put(&index, 2);
    }
    for (const auto& [in_tile, values] : bricks) put(values.data(), values.size() * sizeof(uint16_t));
    const uint64_t checksum = mix(kSeed, blob.data(), blob.size());
    put(&checksum, 8);
    const std::string path = tilePath(tile);
    const std::string tmp = path + ".tmp" + std::to_string(std::hash<std::thread::id>()(std::this_thread::get_id()));
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(blob.data(), std::streamsize(blob.size()));
        core::require(bool(out), tmp, "cannot write a distance field tile");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    core::require(!ec, path, "cannot rename the tile written to " + tmp + ": " + ec.message());
}

TileCache::Read TileCache::read(const Eigen::Vector3i& tile, TileBricks& out, std::string& why) const
{
    out.clear();
    std::ifstream in(tilePath(tile), std::ios::binary);
    if (!in) return Read::Absent;
    const std::string blob((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t head = 4 + 4 + 8 + 12 + 4;
    if (blob.size() < head + 8)
    {
        why = "shorter than a tile's header";
        return Read::Corrupt;
    }
    uint32_t version, count;
    uint64_t header_hash, checksum;
    int32_t t[3];
    std::memcpy(&version, blob.data() + 4, 4);
    std::memcpy(&header_hash, blob.data() + 8, 8);
    std::memcpy(t, blob.data() + 16, 12);
    std::memcpy(&count, blob.data() + 28, 4);
    std::memcpy(&checksum, blob.data() + blob.size() - 8, 8);
    if (std::memcmp(blob.data(), kMagic, 4) != 0 || version != kVersion)
        why = "not a distance field tile of this version";
    else if (header_hash != header_hash_)
        why = "written for another header (another map or other options)";
    else if (t[0] != tile.x() || t[1] != tile.y() || t[2] != tile.z())
        why = "holds another tile";
    else if (count > size_t(kTileBricks) || blob.size() != head + size_t(count) * (2 + 2 * size_t(kBrickVoxels)) + 8)
        why = "its size does not match its brick count";
    else if (checksum != mix(kSeed, blob.data(), blob.size() - 8))
        why = "its checksum does not match";
    if (!why.empty()) return Read::Corrupt;
    const char* indices = blob.data() + head;
    const char* values = indices + 2 * size_t(count);
    out.resize(count);
    for (uint32_t b = 0; b < count; ++b)
    {
        uint16_t index;
        std::memcpy(&index, indices + 2 * b, 2);
        out[b].first = index;
        out[b].second.resize(size_t(kBrickVoxels));
        std::memcpy(out[b].second.data(), values + size_t(b) * kBrickVoxels * 2, size_t(kBrickVoxels) * 2);
        if (index >= kTileBricks)
        {
            why = "a brick index beyond the tile";
            return Read::Corrupt;
        }
    }
    return Read::Ok;
}

void TileCache::markComplete(const std::vector<char>& nonempty)
{
    std::string list(nonempty.begin(), nonempty.end());
    list.append(reinterpret_cast<const char*>(&header_hash_), 8);
    const uint64_t checksum = mix(header_hash_, nonempty.data(), nonempty.size());
    list.append(reinterpret_cast<const char*>(&checksum), 8);
    core::writeTextFileAtomically(folder_ + "/nonempty.bin", list);
    nonempty_ = nonempty;
    complete_ = true;
}

}  // namespace quasiloc::map::detail
