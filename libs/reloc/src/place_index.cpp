// Places of a map with their descriptors: selection, build in shards, merge, file (place_index.h).
#include <opencv2/core/utility.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/fnv_hash.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/reloc/place_index.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <numeric>
#include <stdexcept>
#include <tuple>

namespace quasiloc::reloc
{
namespace
{
constexpr char kMagic[8] = {'Q', 'L', 'P', 'L', 'A', 'C', 'E', 'S'};
constexpr uint32_t kVersion = 1;
constexpr uint64_t kMaxPlaces = uint64_t(1) << 32;

template <typename T>
void put(std::ostream& out, const T& v)
{
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
T get(std::istream& in, const char* what)
{
    T v{};
    in.read(reinterpret_cast<char*>(&v), sizeof(T));
    if (!in) throw std::runtime_error(std::string("truncated (") + what + ")");
    return v;
}
}  // namespace

MapFingerprint MapFingerprint::of(const map::LidarMap& map)
{
    MapFingerprint f;
    f.points = map.size();
    uint64_t h = core::kFnv1aSeed;
    for (size_t i = 0; i < map.size(); i += 997)
    {
        const float xyz[3] = {map.xs()[i], map.ys()[i], map.zs()[i]};
        h = core::fnv1a(h, xyz, sizeof(xyz));
    }
    f.hash = h;
    return f;
}

std::string MapFingerprint::text() const
{
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%016" PRIx64, hash);
    return std::to_string(points) + " points, sample hash " + buf;
}

std::vector<size_t> selectPlaces(const std::vector<Eigen::Vector3d>& positions, double place_spacing_m)
{
    std::map<std::tuple<int64_t, int64_t, int64_t>, size_t> first;
    std::vector<size_t> places;
    for (size_t i = 0; i < positions.size(); ++i)
    {
        const auto& p = positions[i];
        // Cells of the place grid, offset by a small fraction so that grid positions at multiples of the spacing
        // do not fall on a cell border.
        const auto cell = [&](double v) { return int64_t(std::floor(v / place_spacing_m + 1e-6)); };
        const auto key = std::make_tuple(cell(p.x()), cell(p.y()), int64_t(std::llround(p.z() * 100)));
        if (first.emplace(key, i).second) places.push_back(i);
    }
    return places;
}

PlaceIndex buildPlaceIndex(const map::DistanceField& field, const std::vector<Eigen::Vector3f>& places,
                           const PlaceDescriptorOptions& o, const MapFingerprint& map, ShardSelection s, double tile_m)
{
    PlaceIndex index;
    index.descriptor = o;
    index.map = map;
    index.selection = s;
    index.total_places = places.size();
    std::vector<mrpt::poses::CPose3D> poses;
    poses.reserve(places.size());
    for (const auto& p : places) poses.emplace_back(p.x(), p.y(), p.z(), 0, 0, 0);
    const std::vector<size_t> mine = shardViews(poses, tile_m, s);
    index.ids.assign(mine.begin(), mine.end());
    index.positions.resize(mine.size());
    index.profiles.resize(mine.size() * o.cells());
    cv::parallel_for_(cv::Range(0, int(mine.size())), [&](const cv::Range& r) {
        for (int i = r.start; i < r.end; ++i)
        {
            const Eigen::Vector3f& p = places[mine[size_t(i)]];
            index.positions[size_t(i)] = p;
            const std::vector<float> profile = placeProfile(field, p, o);
            std::copy(profile.begin(), profile.end(), index.profiles.begin() + ptrdiff_t(size_t(i) * profile.size()));
        }
    });
    return index;
}

void PlaceIndex::save(const std::string& path) const
{
    core::StagedOutputs staged;
    const std::string tmp = staged.addFile(path);
    {
        std::ofstream out(tmp, std::ios::binary);
        core::require(out.good(), path, "cannot write the place file");
        out.write(kMagic, sizeof(kMagic));
        put(out, kVersion);
        put(out, int32_t(descriptor.sectors));
        put(out, descriptor.max_range_m);
        put(out, uint32_t(descriptor.band_centres_m.size()));
        for (double v : descriptor.band_centres_m) put(out, v);
        put(out, uint32_t(descriptor.band_offsets_m.size()));
        for (double v : descriptor.band_offsets_m) put(out, v);
        put(out, descriptor.band_half_m);
        put(out, descriptor.hit_m);
        put(out, map.points);
        put(out, map.hash);
        put(out, int32_t(selection.index));
        put(out, int32_t(selection.count));
        put(out, total_places);
        put(out, uint64_t(ids.size()));
        for (size_t i = 0; i < ids.size(); ++i)
        {
            put(out, ids[i]);
            out.write(reinterpret_cast<const char*>(positions[i].data()), 3 * sizeof(float));
            out.write(reinterpret_cast<const char*>(profile(i)), std::streamsize(descriptor.cells() * sizeof(float)));
        }
        out.flush();
        core::require(out.good(), path, "write error in the place file");
    }
    staged.commit();
}

PlaceIndex PlaceIndex::load(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    core::require(in.good(), path, "cannot read the place file");
    PlaceIndex p;
    try
    {
        char magic[sizeof(kMagic)] = {};
        in.read(magic, sizeof(magic));
        if (!in || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
            throw std::runtime_error("not a place file (no QLPLACES header)");
        const auto version = get<uint32_t>(in, "version");
        if (version != kVersion)
            throw std::runtime_error("format version " + std::to_string(version) + ", this program reads " +
                                     std::to_string(kVersion) + ": rebuild it");
        p.descriptor.sectors = get<int32_t>(in, "sectors");
        p.descriptor.max_range_m = get<double>(in, "range");
        const auto bands = get<uint32_t>(in, "bands");
        if (bands > 16) throw std::runtime_error("corrupt header (" + std::to_string(bands) + " bands)");
        p.descriptor.band_centres_m.clear();
        for (uint32_t i = 0; i < bands; ++i) p.descriptor.band_centres_m.push_back(get<double>(in, "band centre"));
        const auto offsets = get<uint32_t>(in, "band offsets");
        if (offsets > 64) throw std::runtime_error("corrupt header (" + std::to_string(offsets) + " band offsets)");
        p.descriptor.band_offsets_m.clear();
        for (uint32_t i = 0; i < offsets; ++i) p.descriptor.band_offsets_m.push_back(get<double>(in, "band offset"));
        p.descriptor.band_half_m = get<double>(in, "band");
        p.descriptor.hit_m = get<double>(in, "hit distance");
        p.descriptor.check(path, "GeometricLocalization");
        p.map.points = get<uint64_t>(in, "map points");
        p.map.hash = get<uint64_t>(in, "map hash");
        p.selection.index = get<int32_t>(in, "shard index");
        p.selection.count = get<int32_t>(in, "shard count");
        if (p.selection.count < 1 || p.selection.index < 0 || p.selection.index >= p.selection.count)
            throw std::runtime_error("corrupt shard " + p.selection.text());
        p.total_places = get<uint64_t>(in, "number of places");
        const auto n = get<uint64_t>(in, "places in the file");
        if (p.total_places > kMaxPlaces || n > p.total_places)
            throw std::runtime_error("corrupt header (" + std::to_string(n) + " of " + std::to_string(p.total_places) +
                                     " places)");
        const size_t sectors = p.descriptor.cells();
        for (uint64_t i = 0; i < n; ++i)
        {
            const auto id = get<uint64_t>(in, "place");
            if (id >= p.total_places || (!p.ids.empty() && id <= p.ids.back()))
                throw std::runtime_error("corrupt place index " + std::to_string(id));
            p.ids.push_back(id);
            Eigen::Vector3f pos;
            in.read(reinterpret_cast<char*>(pos.data()), 3 * sizeof(float));
            p.positions.push_back(pos);
            const size_t old = p.profiles.size();
            p.profiles.resize(old + sectors);
            in.read(reinterpret_cast<char*>(p.profiles.data() + old), std::streamsize(sectors * sizeof(float)));
            if (!in)
                throw std::runtime_error("truncated (place " + std::to_string(i) + " of " + std::to_string(n) + ")");
        }
        if (in.peek() != std::char_traits<char>::eof()) throw std::runtime_error("trailing bytes after the places");
    }
    catch (const core::InputError&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        throw core::InputError(path, e.what());
    }
    return p;
}

PlaceIndex mergePlaceIndexes(const std::vector<PlaceIndex>& shards, const std::vector<std::string>& names)
{
    core::require(!shards.empty() && shards.size() == names.size(), "place merge", "no shard given");
    const PlaceIndex& first = shards.front();
    const int count = first.selection.count;
    std::vector<int> seen(size_t(count), -1);
    for (size_t i = 0; i < shards.size(); ++i)
    {
        const PlaceIndex& s = shards[i];
        core::require(
            s.map == first.map, names[i],
            "a shard of another map (" + s.map.text() + " against " + first.map.text() + " in " + names[0] + ")");
        core::require(s.descriptor == first.descriptor, names[i],
                      "built with other descriptor options than " + names[0]);
        core::require(
            s.selection.count == count, names[i],
            "shard " + s.selection.text() + " of another split than " + names[0] + " (" + first.selection.text() + ")");
        core::require(s.total_places == first.total_places, names[i],
                      std::to_string(s.total_places) + " places in the map, " + std::to_string(first.total_places) +
                          " in " + names[0]);
        int& slot = seen[size_t(s.selection.index)];
        core::require(
            slot < 0, names[i],
            "shard " + s.selection.text() + " given twice (also " + (slot < 0 ? "" : names[size_t(slot)]) + ")");
        slot = int(i);
    }
    for (int k = 0; k < count; ++k)
        core::require(seen[size_t(k)] >= 0, "place merge",
                      "shard " + std::to_string(k) + "/" + std::to_string(count) + " missing");

    // Every place once: gather (index, shard, row), sorted by index.
    std::vector<std::tuple<uint64_t, size_t, size_t>> rows;
    for (size_t i = 0; i < shards.size(); ++i)
        for (size_t r = 0; r < shards[i].size(); ++r) rows.emplace_back(shards[i].ids[r], i, r);
    std::sort(rows.begin(), rows.end());
    for (size_t r = 1; r < rows.size(); ++r)
        core::require(
            std::get<0>(rows[r]) != std::get<0>(rows[r - 1]), names[std::get<1>(rows[r])],
            "place " + std::to_string(std::get<0>(rows[r])) + " is also in " + names[std::get<1>(rows[r - 1])]);
    core::require(
        rows.size() == first.total_places, "place merge",
        std::to_string(rows.size()) + " places in the shards, " + std::to_string(first.total_places) + " in the map");
    PlaceIndex out;
    out.descriptor = first.descriptor;
    out.map = first.map;
    out.selection = ShardSelection{};
    out.total_places = first.total_places;
    const size_t sectors = first.descriptor.cells();
    for (const auto& [id, shard, row] : rows)
    {
        out.ids.push_back(id);
        out.positions.push_back(shards[shard].positions[row]);
        const float* prof = shards[shard].profile(row);
        out.profiles.insert(out.profiles.end(), prof, prof + sectors);
    }
    return out;
}

}  // namespace quasiloc::reloc
