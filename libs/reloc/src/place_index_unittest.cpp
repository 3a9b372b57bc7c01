// Place descriptors, their index file and shards, and retrieval, on synthetic rooms of known geometry: a profile
// holds the distances to the walls, a query's profile matches its own place at the camera's heading and not another
// room's, shards merge into the single-process file byte for byte, and bad files are named.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <quasiloc/core/error.h>
#include <quasiloc/reloc/place_index.h>
#include <quasiloc/reloc/place_retrieval.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

using namespace quasiloc;

namespace
{
/** Walls of a box [x0, x0 + sx] x [y0, y0 + sy] x [0, 3] m every 5 cm, and a pillar of 0.4 m at (px, py) inside. */
void addRoom(map::LidarMap& m, float x0, float y0, float sx, float sy, float px, float py)
{
    const float step = 0.05f;
    for (float z = 0; z <= 3.0f; z += step)
    {
        for (float x = x0; x <= x0 + sx; x += step)
        {
            m.addPoint(x, y0, z, 0.5f);
            m.addPoint(x, y0 + sy, z, 0.5f);
        }
        for (float y = y0; y <= y0 + sy; y += step)
        {
            m.addPoint(x0, y, z, 0.5f);
            m.addPoint(x0 + sx, y, z, 0.5f);
        }
        for (float a = -0.2f; a <= 0.2f; a += step)
        {
            m.addPoint(px + a, py - 0.2f, z, 0.5f);
            m.addPoint(px + a, py + 0.2f, z, 0.5f);
            m.addPoint(px - 0.2f, py + a, z, 0.5f);
            m.addPoint(px + 0.2f, py + a, z, 0.5f);
        }
    }
}

/** Two rooms of different shapes, 30 m apart. */
const map::LidarMap& twoRooms()
{
    static const map::LidarMap m = [] {
        map::LidarMap m;
        addRoom(m, 0, 0, 6, 4, 4.5f, 1.0f);
        addRoom(m, 30, 0, 5, 5, 31.0f, 3.8f);
        return m;
    }();
    return m;
}

const map::DistanceField& field()
{
    static const map::DistanceField f = [] {
        map::DistanceFieldOptions o;
        o.layout = map::DistanceFieldLayout::Sparse;
        return map::DistanceField::build(twoRooms(), o, "two rooms");
    }();
    return f;
}

/** The points a forward-looking camera at `p` with heading `yaw` (90 deg field of view, 3.5 m depth) sees of the
 *  map, in a levelled camera frame (x forward, y left, z up): the walls' first surfaces, by casting on the field. */
std::vector<Eigen::Vector3f> seenPoints(const Eigen::Vector3f& p, double yaw)
{
    std::vector<Eigen::Vector3f> out;
    for (double a = -45; a <= 45; a += 1)
        for (double e = -30; e <= 30; e += 3)
        {
            const double az = yaw + a * M_PI / 180, el = e * M_PI / 180;
            const Eigen::Vector3f dir(float(std::cos(el) * std::cos(az)), float(std::cos(el) * std::sin(az)),
                                      float(std::sin(el)));
            for (float t = 0.2f; t < 3.5f; t += 0.01f)
                if (field().distance(p + t * dir) < 0.03f)
                {
                    const Eigen::Vector3f w = t * dir;  // world offset; the camera frame is this turned by -yaw
                    const Eigen::Vector3f c = Eigen::AngleAxisf(float(-yaw), Eigen::Vector3f::UnitZ()) * w;
                    out.push_back(c);
                    break;
                }
        }
    return out;
}

std::vector<Eigen::Vector3f> placesOf(float spacing)
{
    std::vector<Eigen::Vector3f> places;
    for (float x = 0.5f; x < 35.f; x += spacing)
        for (float y = 0.5f; y < 4.6f; y += spacing)
        {
            const bool in_a = x < 5.6f && y < 3.6f && std::hypot(x - 4.5f, y - 1.0f) > 0.5f;
            const bool in_b = x > 30.4f && x < 34.6f && std::hypot(x - 31.0f, y - 3.8f) > 0.5f;
            if (in_a || in_b) places.emplace_back(x, y, 1.2f);
        }
    return places;
}

std::string bytesOf(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string tempPath(const std::string& name)
{
    return (std::filesystem::temp_directory_path() / ("quasiloc_place_test_" + name)).string();
}
}  // namespace

TEST(PlaceDescriptor, AMapProfileHoldsTheDistancesToTheWalls)
{
    reloc::PlaceDescriptorOptions o;
    o.max_range_m = 8;
    o.band_centres_m = {0.0};
    const std::vector<float> p = reloc::placeProfile(field(), Eigen::Vector3f(1.5f, 2.0f, 1.2f), o);
    ASSERT_EQ(p.size(), 72u);
    // Sector 0 (0..5 deg, middle 2.5 deg) towards +x: the pillar's face at x = 4.3 is off this ray (y = 2 vs pillar
    // y in 0.8..1.2); the wall at x = 6: 4.5 m / cos(2.5 deg). Sector 18 (+y, middle 92.5 deg): wall at y = 4.
    EXPECT_NEAR(p[0], 4.5 / std::cos(2.5 * M_PI / 180), 0.08);
    EXPECT_NEAR(p[18], 2.0 / std::cos(2.5 * M_PI / 180), 0.08);
    EXPECT_NEAR(p[36], 1.5 / std::cos(2.5 * M_PI / 180), 0.08);  // -x
    EXPECT_NEAR(p[54], 2.0 / std::cos(2.5 * M_PI / 180), 0.08);  // -y
    // A range limit: nothing within 1 m in any direction.
    o.max_range_m = 1.0;
    for (float v : reloc::placeProfile(field(), Eigen::Vector3f(1.5f, 2.0f, 1.2f), o)) EXPECT_EQ(v, 1.0f);
}

TEST(PlaceDescriptor, AQueryMatchesItsPlaceAtItsHeadingOnlyInTheSectorsItSees)
{
    reloc::PlaceDescriptorOptions o;
    o.band_centres_m = {0.0};                    // one band: 18 sectors of 5 deg in the 90 deg view
    const Eigen::Vector3f at(4.5f, 3.0f, 1.2f);  // looking at the pillar and the walls at y = 0 and x = 6
    const double yaw = -60 * M_PI / 180;
    const std::vector<float> q = reloc::queryProfile(seenPoints(at, yaw), Eigen::Matrix3f::Identity(), o);
    const std::vector<int> covered = reloc::coveredSectors(q);
    EXPECT_GE(covered.size(), 15u);
    EXPECT_LE(covered.size(), 20u);  // 90 deg of 5 deg sectors
    const std::vector<float> place = reloc::placeProfile(field(), at, o);
    int best = -1;
    float best_cost = 1e9f;
    for (int s = 0; s < o.sectors; ++s)
    {
        const float c = reloc::profileCost(q, covered, place.data(), s, 72, 0.5f);
        if (c < best_cost) best_cost = c, best = s;
    }
    EXPECT_NEAR(std::remainder(best * 5.0 + 60.0, 360.0), 0.0, 5.0);
    EXPECT_LT(best_cost, 0.01f);
    EXPECT_GT(reloc::profileCost(q, covered, place.data(), (best + 36) % 72, 72, 0.5f), 10 * best_cost + 0.01f);
}

TEST(PlaceRetrieval, FindsTheQuerysPlaceAndHeadingAmongTwoRooms)
{
    const std::vector<Eigen::Vector3f> places = placesOf(0.5f);
    const reloc::PlaceIndex index =
        reloc::buildPlaceIndex(field(), places, {}, reloc::MapFingerprint::of(twoRooms()), {}, 4.0);
    ASSERT_EQ(index.size(), places.size());
    for (const auto& [at, yaw_deg] :
         {std::pair{Eigen::Vector3f(4.5f, 3.0f, 1.2f), -60.0}, std::pair{Eigen::Vector3f(33.0f, 2.5f, 1.2f), 160.0}})
    {
        const std::vector<float> q =
            reloc::queryProfile(seenPoints(at, yaw_deg * M_PI / 180), Eigen::Matrix3f::Identity(), {});
        reloc::RetrievalRequest request;
        request.top_k = 5;
        const auto got = reloc::retrievePlaces(index, q, request, 0.5f);
        ASSERT_FALSE(got.empty());
        EXPECT_LT((index.positions[got[0].place] - at).head<2>().norm(), 0.8f) << "query at " << at.transpose();
        EXPECT_NEAR(std::remainder(got[0].shift * 5.0 - yaw_deg, 360.0), 0.0, 10.0);
        for (size_t i = 1; i < got.size(); ++i) EXPECT_GE(got[i].cost, got[i - 1].cost);
        // Only the other room's places admitted: the query's own room is not among the answers.
        request.admitted.assign(index.size(), false);
        for (size_t i = 0; i < index.size(); ++i) request.admitted[i] = (index.positions[i].x() > 20) != (at.x() > 20);
        for (const auto& r : reloc::retrievePlaces(index, q, request, 0.5f))
            EXPECT_NE(index.positions[r.place].x() > 20, at.x() > 20);
    }
}

TEST(PlaceIndex, ShardsMergeIntoTheSingleProcessFileByteForByte)
{
    const std::vector<Eigen::Vector3f> places = placesOf(0.5f);
    const auto fp = reloc::MapFingerprint::of(twoRooms());
    const std::string whole = tempPath("whole.qplaces"), merged = tempPath("merged.qplaces");
    reloc::buildPlaceIndex(field(), places, {}, fp, {}, 2.0).save(whole);
    std::vector<reloc::PlaceIndex> shards;
    std::vector<std::string> names;
    size_t total = 0;
    for (int i = 0; i < 3; ++i)
    {
        names.push_back(tempPath("shard" + std::to_string(i)));
        reloc::buildPlaceIndex(field(), places, {}, fp, {i, 3}, 2.0).save(names.back());
        shards.push_back(reloc::PlaceIndex::load(names.back()));
        EXPECT_GT(shards.back().size(), 0u);
        total += shards.back().size();
    }
    EXPECT_EQ(total, places.size());
    reloc::mergePlaceIndexes(shards, names).save(merged);
    EXPECT_EQ(bytesOf(whole), bytesOf(merged));
    const reloc::PlaceIndex back = reloc::PlaceIndex::load(whole);
    EXPECT_EQ(back.size(), places.size());
    EXPECT_EQ(back.map, fp);

    // A shard missing, a shard twice, a shard of another map: errors naming the shard.
    EXPECT_THROW(reloc::mergePlaceIndexes({shards[0], shards[1]}, {names[0], names[1]}), core::InputError);
    try
    {
        reloc::mergePlaceIndexes({shards[0], shards[1], shards[1]}, {names[0], names[1], names[2]});
        ADD_FAILURE() << "a shard given twice was merged";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("given twice"), std::string::npos) << e.what();
    }
    reloc::PlaceIndex other = shards[2];
    other.map.hash ^= 1;
    try
    {
        reloc::mergePlaceIndexes({shards[0], shards[1], other}, names);
        ADD_FAILURE() << "a shard of another map was merged";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find(names[2]), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("another map"), std::string::npos) << e.what();
    }
    for (const auto& n : names) std::filesystem::remove(n);
    std::filesystem::remove(merged);

    // A truncated file and a foreign file: errors naming them.
    const std::string bytes = bytesOf(whole);
    std::ofstream(whole, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size() - 7));
    try
    {
        reloc::PlaceIndex::load(whole);
        ADD_FAILURE() << "a truncated place file was read";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find(whole), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
    std::ofstream(whole, std::ios::trunc) << "# not a place file\n";
    EXPECT_THROW(reloc::PlaceIndex::load(whole), core::InputError);
    std::filesystem::remove(whole);
}

TEST(PlaceIndex, SelectsOnePlacePerCellAndHeight)
{
    std::vector<Eigen::Vector3d> positions;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (double z : {0.5, 0.8}) positions.emplace_back(0.25 * i, 0.25 * j, z);
    const std::vector<size_t> places = reloc::selectPlaces(positions, 0.5);
    EXPECT_EQ(places.size(), 4u * 4u * 2u);
    for (size_t i = 1; i < places.size(); ++i) EXPECT_LT(places[i - 1], places[i]);
}
