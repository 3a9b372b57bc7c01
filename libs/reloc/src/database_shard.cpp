#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <quasiloc/core/error.h>
#include <quasiloc/core/fnv_hash.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/reloc/database_builder.h>
#include <quasiloc/reloc/database_shard.h>
#include <set>
#include <sstream>

#include "database_io.h"

namespace quasiloc::reloc
{
namespace
{
const std::string kMagic = "quasiloc-reloc-database-shard";
constexpr uint32_t kVersion = 1;

std::string trim(const std::string& s)
{
    const auto b = s.find_first_not_of(" \t\r\n");
    const auto e = s.find_last_not_of(" \t\r\n");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

/** "[section] key = value" lines of every key `options` saves, but `skip`. */
void appendSection(std::string& text, const mrpt::config::CLoadableOptions& options, const std::string& section,
                   const std::set<std::string>& skip = {})
{
    mrpt::config::CConfigFileMemory mem;
    options.saveToConfigFile(mem, section);
    std::vector<std::string> keys;
    mem.getAllKeys(section, keys);
    for (auto& k : keys) k = trim(k);
    std::sort(keys.begin(), keys.end());
    for (const auto& k : keys)
        if (!skip.count(k)) text += "[" + section + "] " + k + " = " + trim(mem.read_string(section, k, "")) + "\n";
}

/** key ("[section] key") -> value, from resultOptionsText(). */
std::map<std::string, std::string> optionLines(const std::string& text)
{
    std::map<std::string, std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
    {
        const auto eq = line.find(" = ");
        if (eq != std::string::npos) lines[line.substr(0, eq)] = line.substr(eq + 3);
    }
    return lines;
}

std::string shardName(const std::string& path, ShardSelection s) { return "shard " + s.text() + " (" + path + ")"; }
}  // namespace

ShardSelection ShardSelection::parse(const std::string& text, const std::string& input)
{
    const auto slash = text.find('/');
    const auto number = [&](const std::string& part) {
        return !part.empty() && part.size() <= 9 && part.find_first_not_of("0123456789") == std::string::npos;
    };
    core::require(slash != std::string::npos && number(text.substr(0, slash)) && number(text.substr(slash + 1)), input,
                  "'" + text + "' is not a shard i/N (for example 2/8)");
    ShardSelection s;
    s.index = std::stoi(text.substr(0, slash));
    s.count = std::stoi(text.substr(slash + 1));
    core::require(s.count >= 1 && s.index < s.count, input,
                  "'" + text + "': the shard index i of i/N must be in [0, N) and N >= 1");
    return s;
}

MapIdentity MapIdentity::ofFile(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    core::require(in.good(), path, "cannot read the map file to identify it");
    MapIdentity id;
    uint64_t h = core::kFnv1aSeed;
    std::vector<char> buf(1 << 20);
    while (in)
    {
        in.read(buf.data(), std::streamsize(buf.size()));
        const std::streamsize got = in.gcount();
        h = core::fnv1a(h, buf.data(), size_t(got));
        id.file_bytes += uint64_t(got);
    }
    core::require(in.eof(), path, "read error while identifying the map file");
    id.file_hash = h;
    return id;
}

std::string MapIdentity::text() const
{
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%016" PRIx64, file_hash);
    return std::to_string(file_bytes) + " bytes, FNV-1a " + buf;
}

std::string resultOptionsText(const DatabaseBuildConfig& config, const core::CameraModel& camera)
{
    std::string text;
    mrpt::config::CConfigFileMemory cam;
    camera.saveToIni(cam, "camera");
    std::vector<std::string> keys;
    cam.getAllKeys("camera", keys);
    std::sort(keys.begin(), keys.end());
    for (const auto& k : keys) text += "[camera] " + trim(k) + " = " + trim(cam.read_string("camera", k, "")) + "\n";
    // The library's keys only (a program's subclass adds its file keys), and not the worker count: the result
    // does not depend on it, and a shard on a small node may run with fewer workers.
    const DatabaseBuildOptions build = config.build;
    appendSection(text, build, "BuildDatabase", {"threads"});
    appendSection(text, config.sampling, "ViewSampling");
    appendSection(text, config.quasi, "QuasiImage", {"num_threads"});
    appendSection(text, config.features, "Features");
    appendSection(text, config.lines, "Lines");
    appendSection(text, config.association, "Association");
    appendSection(text, config.vocabulary, "Vocabulary");
    return text;
}

std::string optionsDifference(const std::string& a, const std::string& a_name, const std::string& b,
                              const std::string& b_name)
{
    const auto la = optionLines(a), lb = optionLines(b);
    std::set<std::string> keys;
    for (const auto& [k, v] : la) keys.insert(k);
    for (const auto& [k, v] : lb) keys.insert(k);
    for (const auto& k : keys)
    {
        const auto ia = la.find(k), ib = lb.find(k);
        const std::string va = ia == la.end() ? "(no such key)" : ia->second;
        const std::string vb = ib == lb.end() ? "(no such key)" : ib->second;
        if (va != vb) return k + " = " + va + " in " + a_name + ", " + vb + " in " + b_name;
    }
    return a == b ? "" : "the option lists of " + a_name + " and " + b_name + " differ";
}

std::vector<size_t> tileOrder(const std::vector<mrpt::poses::CPose3D>& poses, double cell_m)
{
    core::require(cell_m > 0, "tile cell size", "must be > 0");
    if (poses.empty()) return {};
    double x0 = poses[0].x(), y0 = poses[0].y();
    for (const auto& p : poses)
    {
        x0 = std::min(x0, p.x());
        y0 = std::min(y0, p.y());
    }
    const auto cell = [&](double v, double v0) {
        return uint64_t(std::min(std::floor((v - v0) / cell_m + 0.5), double(uint64_t(1) << 31)));
    };
    std::vector<std::pair<uint64_t, uint64_t>> cells(poses.size());
    uint64_t side = 1;  // the curve's grid: a power of two covering every cell
    for (size_t i = 0; i < poses.size(); ++i)
    {
        cells[i] = {cell(poses[i].x(), x0), cell(poses[i].y(), y0)};
        while (side <= std::max(cells[i].first, cells[i].second)) side *= 2;
    }
    // Position along a Hilbert curve over the cells: consecutive cells are neighbours, so a contiguous run of the
    // order is one connected, compact region (a Z-order run can jump across the map).
    const auto hilbert = [side](uint64_t x, uint64_t y) {
        uint64_t d = 0;
        for (uint64_t s = side / 2; s > 0; s /= 2)
        {
            const uint64_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
            d += s * s * ((3 * rx) ^ ry);
            if (ry == 0)
            {
                if (rx == 1)
                {
                    x = side - 1 - x;
                    y = side - 1 - y;
                }
                std::swap(x, y);
            }
        }
        return d;
    };
    std::vector<std::pair<uint64_t, size_t>> keyed(poses.size());
    for (size_t i = 0; i < poses.size(); ++i) keyed[i] = {hilbert(cells[i].first, cells[i].second), i};
    std::sort(keyed.begin(), keyed.end());
    std::vector<size_t> order(poses.size());
    for (size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
    return order;
}

size_t shardSize(size_t num_views, ShardSelection s)
{
    const auto begin = [&](int k) { return size_t(uint64_t(num_views) * uint64_t(k) / uint64_t(s.count)); };
    return begin(s.index + 1) - begin(s.index);
}

std::vector<size_t> shardViews(const std::vector<mrpt::poses::CPose3D>& poses, double cell_m, ShardSelection s)
{
    const std::vector<size_t> order = tileOrder(poses, cell_m);
    const size_t begin = size_t(uint64_t(order.size()) * uint64_t(s.index) / uint64_t(s.count));
    std::vector<size_t> views(order.begin() + long(begin), order.begin() + long(begin + shardSize(order.size(), s)));
    std::sort(views.begin(), views.end());
    return views;
}

void DatabaseShard::save(const std::string& path) const
{
    detail::writeArchiveAtomically(path, [&](mrpt::serialization::CArchive& out) {
        out.WriteBuffer(kMagic.data(), kMagic.size());
        out.WriteAs<uint32_t>(kVersion);
        out.WriteAs<int32_t>(selection.index);
        out.WriteAs<int32_t>(selection.count);
        out.WriteAs<uint64_t>(map.file_bytes);
        out.WriteAs<uint64_t>(map.file_hash);
        out << map_file << options;
        out.WriteAs<uint64_t>(map_points);
        out.WriteAs<uint64_t>(sampled_views);
        out.WriteAs<uint64_t>(rendered);
        out.WriteAs<uint64_t>(dropped_valid);
        out.WriteAs<uint64_t>(dropped_lifted);
        out << build_seconds;
        detail::writeCameraAndFeatures(out, camera, features);
        out << image_blur_sigma_px;
        out.WriteAs<uint64_t>(views.size());
        for (const auto& v : views) detail::writeView(out, v);
    });
}

DatabaseShard DatabaseShard::load(const std::string& path, bool header_only)
{
    core::require(std::filesystem::is_regular_file(path), path, "shard file not found");
    mrpt::io::CFileGZInputStream stream;
    core::require(stream.open(path), path, "cannot open the shard file for reading");
    DatabaseShard s;
    try
    {
        auto in = mrpt::serialization::archiveFrom(stream);
        std::string magic(kMagic.size(), '\0');
        core::require(in.ReadBuffer(magic.data(), magic.size()) == magic.size() && magic == kMagic, path,
                      "is not a quasiloc database shard (build one with quasiloc-build-db <config.ini> --shard i/N)");
        const uint32_t version = in.ReadAs<uint32_t>();
        core::require(version == kVersion, path,
                      "shard format version " + std::to_string(version) + ", this program reads version " +
                          std::to_string(kVersion) + ": rebuild the shard");
        s.selection.index = in.ReadAs<int32_t>();
        s.selection.count = in.ReadAs<int32_t>();
        core::require(s.selection.count >= 1 && s.selection.index >= 0 && s.selection.index < s.selection.count, path,
                      "corrupt shard header (shard " + s.selection.text() + ")");
        s.map.file_bytes = in.ReadAs<uint64_t>();
        s.map.file_hash = in.ReadAs<uint64_t>();
        in >> s.map_file >> s.options;
        s.map_points = in.ReadAs<uint64_t>();
        s.sampled_views = in.ReadAs<uint64_t>();
        s.rendered = in.ReadAs<uint64_t>();
        s.dropped_valid = in.ReadAs<uint64_t>();
        s.dropped_lifted = in.ReadAs<uint64_t>();
        in >> s.build_seconds;
        detail::readCameraAndFeatures(in, s.camera, s.features);
        in >> s.image_blur_sigma_px;
        if (header_only) return s;
        const uint64_t n = in.ReadAs<uint64_t>();
        core::require(n <= s.rendered, path, "corrupt view count " + std::to_string(n));
        s.views.reserve(n);
        for (uint64_t i = 0; i < n; ++i)
        {
            s.views.push_back(detail::readView(in, false));
            const int id = s.views.back().id;
            core::require(id >= 0 && uint64_t(id) < s.sampled_views && (i == 0 || s.views[i - 1].id < id), path,
                          "corrupt view index " + std::to_string(id));
            s.views.back().points.type = s.features.type;
            s.views.back().points.image_size = cv::Size(s.camera.width, s.camera.height);
        }
    }
    catch (const core::InputError&)
    {
        throw;
    }
    catch (const std::exception& e)
    {
        throw core::InputError(
            path, "cannot be read as a quasiloc database shard (truncated or corrupt): " + mrpt::exception_to_str(e));
    }
    return s;
}

std::string shardPath(const std::string& output, ShardSelection s)
{
    return output + ".shard-" + std::to_string(s.index) + "-of-" + std::to_string(s.count);
}

std::vector<DatabaseShard> loadShardsForMerge(const std::string& output, const ShardExpectation& expected)
{
    core::require(expected.count >= 1, "the merge", "needs a shard count N >= 1");
    const int n = expected.count;
    std::vector<std::string> paths;
    std::vector<int> missing;
    for (int i = 0; i < n; ++i)
    {
        paths.push_back(shardPath(output, {i, n}));
        if (!std::filesystem::is_regular_file(paths.back())) missing.push_back(i);
    }
    if (!missing.empty())
    {
        // Every missing index, and the files of the first few (a whole failed array job would give N of them).
        constexpr size_t kFilesNamed = 8;
        std::string indices, files;
        for (size_t k = 0; k < missing.size(); ++k)
        {
            indices += (k ? ", " : "") + std::to_string(missing[k]);
            if (k < kFilesNamed) files += (k ? ", '" : "'") + paths[size_t(missing[k])] + "'";
        }
        if (missing.size() > kFilesNamed) files += " and " + std::to_string(missing.size() - kFilesNamed) + " more";
        const bool several = missing.size() > 1;
        throw core::InputError(output + " (merge of " + std::to_string(n) + " shards)",
                               std::string(several ? "shards " : "shard ") + indices + " missing: " + files +
                                   " not found (build " + (several ? "them" : "it") + " with quasiloc-build-db " +
                                   expected.config_name + " --shard i/" + std::to_string(n) + ")");
    }

    // Every header first: a wrong shard is found before any view is read.
    uint64_t sampled = 0;
    for (int i = 0; i < n; ++i)
    {
        const DatabaseShard h = DatabaseShard::load(paths[size_t(i)], true);
        const ShardSelection want{i, n};
        core::require(
            h.selection == want, paths[size_t(i)],
            "holds shard " + h.selection.text() + ", not shard " + want.text() + " (a copied or renamed shard file?)");
        core::require(h.map == expected.map, shardName(paths[size_t(i)], want),
                      "is from another map: built from '" + h.map_file + "' (" + h.map.text() +
                          "), the merge's map_file '" + expected.map_file + "' is " + expected.map.text());
        const std::string diff = optionsDifference(h.options, "the shard", expected.options,
                                                   "the merge's configuration (" + expected.config_name + ")");
        core::require(diff.empty(), shardName(paths[size_t(i)], want), "was built with other options: " + diff);
        if (i == 0) sampled = h.sampled_views;
        core::require(h.sampled_views == sampled, shardName(paths[size_t(i)], want),
                      "sampled " + std::to_string(h.sampled_views) + " views, shard 0/" + std::to_string(n) +
                          " sampled " + std::to_string(sampled));
        core::require(h.rendered == shardSize(sampled, want), shardName(paths[size_t(i)], want),
                      "rendered " + std::to_string(h.rendered) + " views, its tile has " +
                          std::to_string(shardSize(sampled, want)));
    }

    std::vector<DatabaseShard> shards;
    std::vector<int> owner(sampled, -1);
    for (int i = 0; i < n; ++i)
    {
        shards.push_back(DatabaseShard::load(paths[size_t(i)]));
        for (const auto& v : shards.back().views)
        {
            core::require(owner[size_t(v.id)] < 0, shardName(paths[size_t(i)], {i, n}),
                          "has view " + std::to_string(v.id) + ", which shard " + std::to_string(owner[size_t(v.id)]) +
                              "/" + std::to_string(n) + " has too");
            owner[size_t(v.id)] = i;
        }
    }
    return shards;
}

}  // namespace quasiloc::reloc
