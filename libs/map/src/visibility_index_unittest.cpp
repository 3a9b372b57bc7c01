#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <quasiloc/core/pose.h>
#include <quasiloc/map/visibility_index.h>
#include <random>

using namespace quasiloc;
using namespace quasiloc::map;

namespace
{
std::vector<core::CameraModel> testCameras()
{
    core::CameraModel pinhole = core::CameraModel::pinhole(640, 480, 400, 400, 319.5, 239.5);
    core::CameraModel radtan = core::CameraModel::pinhole(752, 480, 458.654, 457.296, 367.215, 248.375);
    radtan.model = core::DistortionModel::RadTan;  // EuRoC cam0: strong barrel distortion
    radtan.dist = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0};
    core::CameraModel fisheye = core::CameraModel::pinhole(512, 512, 190.98, 190.98, 254.93, 256.90);
    fisheye.model = core::DistortionModel::Equidistant;  // TUM-VI like, ~190 deg diagonal would fold: keep sane
    fisheye.dist = {0.0034823894, 0.0007150348, -0.0020532361, 0.0002029367, 0};
    return {pinhole, radtan, fisheye};
}

LidarMap randomCloud(size_t n, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    LidarMap m;
    m.reserve(n);
    for (size_t i = 0; i < n; ++i)
        m.addPoint(lo.x() + U(rng) * (hi.x() - lo.x()), lo.y() + U(rng) * (hi.y() - lo.y()),
                   lo.z() + U(rng) * (hi.z() - lo.z()), U(rng));
    return m;
}

/** Camera at `eye` looking at `target` (z forward, y roughly down = -world z). */
mrpt::poses::CPose3D lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target)
{
    const Eigen::Vector3d z = (target - eye).normalized();
    const Eigen::Vector3d x = z.cross(Eigen::Vector3d(0, 0, 1)).normalized();
    const Eigen::Vector3d y = z.cross(x);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear().col(0) = x;
    T.linear().col(1) = y;
    T.linear().col(2) = z;
    T.translation() = eye;
    return core::fromIsometry(T);
}

/** covered[k] = stored point k is inside one of the ranges; also checks the ranges are well formed. */
std::vector<char> coverage(const VisibilityIndex& index, const std::vector<VisibilityIndex::Range>& ranges)
{
    std::vector<char> covered(index.size(), 0);
    uint32_t prev_end = 0;
    for (const auto& r : ranges)
    {
        EXPECT_LT(r.begin, r.end);
        EXPECT_LE(r.end, index.size());
        EXPECT_GE(r.begin, prev_end) << "ranges must be sorted and disjoint";
        prev_end = r.end;
        for (uint32_t k = r.begin; k < r.end; ++k) covered[k] = 1;
    }
    return covered;
}

/** Number of points that project into the image at depth (0, max_range] but are not covered. */
size_t missedVisiblePoints(const VisibilityIndex& index, const mrpt::poses::CPose3D& T_world_cam,
                           const core::CameraModel& cam, double max_range, const std::vector<char>& covered,
                           size_t* visible)
{
    const Eigen::Isometry3d T_cam_world = core::toIsometry(T_world_cam).inverse();
    size_t missed = 0;
    *visible = 0;
    for (size_t k = 0; k < index.size(); ++k)
    {
        const Eigen::Vector3d p_cam = T_cam_world * Eigen::Vector3d(index.xs()[k], index.ys()[k], index.zs()[k]);
        if (p_cam.z() <= 0 || p_cam.z() > max_range) continue;
        Eigen::Vector2d px;
        if (!cam.project(p_cam, px) || !cam.isInImage(px)) continue;
        ++*visible;
        if (!covered[k]) ++missed;
    }
    return missed;
}
}  // namespace

TEST(VisibilityIndex, StoresEveryPointOnceWithItsMapIndex)
{
    const LidarMap map = randomCloud(30000, {-10, -5, 0}, {10, 5, 3}, 1);
    const VisibilityIndex index(map, {});
    ASSERT_EQ(index.size(), map.size());
    EXPECT_GE(index.numBlocks(), 20u * 10 * 3 - 10);
    std::vector<char> seen(map.size(), 0);
    for (size_t k = 0; k < index.size(); ++k)
    {
        const uint32_t i = index.mapIndex()[k];
        ASSERT_LT(i, map.size());
        EXPECT_FALSE(seen[i]) << "map point " << i << " stored twice";
        seen[i] = 1;
        EXPECT_EQ(index.xs()[k], map.xs()[i]);
        EXPECT_EQ(index.ys()[k], map.ys()[i]);
        EXPECT_EQ(index.zs()[k], map.zs()[i]);
        EXPECT_EQ(index.reflectivities()[k], map.reflectivities()[i]);
    }
    const VisibilityIndex empty(LidarMap(), {});
    std::vector<VisibilityIndex::Range> out{{1, 2}};
    empty.query(mrpt::poses::CPose3D(), core::CameraModel::pinhole(10, 10, 5, 5, 5, 5), 10, out);
    EXPECT_TRUE(out.empty());
}

TEST(VisibilityIndex, ConservativeAgainstBruteForceProjection)
{
    const Eigen::Vector3f lo(-10, -10, -3), hi(10, 10, 3);
    const LidarMap map = randomCloud(40000, lo, hi, 2);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(0, 1);
    for (const double block : {1.0, 2.5})
    {
        VisibilityIndex::Options o;
        o.block_size_m = block;
        const VisibilityIndex index(map, o);
        for (const core::CameraModel& cam : testCameras())
        {
            size_t total_visible = 0, total_covered = 0;
            for (int trial = 0; trial < 40; ++trial)
            {
                Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
                T.linear() = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
                T.translation() = Eigen::Vector3d(-12 + 24 * U(rng), -12 + 24 * U(rng), -4 + 8 * U(rng));
                const double max_range = 1.0 + 15.0 * U(rng);
                const auto T_world_cam = core::fromIsometry(T);
                std::vector<VisibilityIndex::Range> ranges;
                index.query(T_world_cam, cam, max_range, ranges);
                const auto covered = coverage(index, ranges);
                size_t visible = 0;
                const size_t missed = missedVisiblePoints(index, T_world_cam, cam, max_range, covered, &visible);
                ASSERT_EQ(missed, 0u) << "block " << block << " camera " << cam.width << "x" << cam.height << " trial "
                                      << trial << ": " << missed << " of " << visible
                                      << " visible points are outside the returned ranges";
                total_visible += visible;
                total_covered += VisibilityIndex::countPoints(ranges);
            }
            EXPECT_GT(total_visible, 1000u) << "the poses should see something";
            // Culling works at all: far fewer points returned than 40 whole maps.
            EXPECT_LT(total_covered, 40 * map.size() / 2);
        }
    }
}

TEST(VisibilityIndex, LookingAtARoomCornerReturnsAFractionOfTheMap)
{
    // Walls, floor and ceiling of an 8 x 9 x 3.4 m room, 200k points.
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> U(0.f, 1.f);
    const Eigen::Vector3f size(8, 9, 3.4f);
    LidarMap room;
    for (int i = 0; i < 200000; ++i)
    {
        Eigen::Vector3f p(U(rng) * size.x(), U(rng) * size.y(), U(rng) * size.z());
        const int face = i % 6;
        p[face / 2] = (face % 2) ? size[face / 2] : 0.f;
        room.addPoint(p.x(), p.y(), p.z(), U(rng));
    }
    const VisibilityIndex index(room, {});
    const core::CameraModel cam = testCameras()[1];
    const auto T = lookAt({1.5, 1.5, 1.7}, {0, 0, 1.7});
    std::vector<VisibilityIndex::Range> ranges;
    index.query(T, cam, 20.0, ranges);
    const size_t returned = VisibilityIndex::countPoints(ranges);
    size_t visible = 0;
    EXPECT_EQ(missedVisiblePoints(index, T, cam, 20.0, coverage(index, ranges), &visible), 0u);
    EXPECT_GT(visible, 1000u);
    EXPECT_GE(returned, visible);
    EXPECT_LT(returned, room.size() / 4) << "returned " << returned << " of " << room.size();
    std::cout << "corner view: " << visible << " visible, " << returned << " returned in " << ranges.size()
              << " ranges, map " << room.size() << "\n";

    // Looking out of the room from outside it: nothing.
    index.query(lookAt({-1, -1, 1.7}, {-5, -5, 1.7}), cam, 20.0, ranges);
    EXPECT_TRUE(ranges.empty());
    // A short range sees only the blocks next to the camera.
    index.query(T, cam, 0.5, ranges);
    EXPECT_LT(VisibilityIndex::countPoints(ranges), returned / 4);
}

TEST(VisibilityIndex, SuperblockGroupingDoesNotChangeTheResult)
{
    const LidarMap map = randomCloud(20000, {-30, -30, -2}, {30, 30, 2}, 5);
    VisibilityIndex::Options flat, grouped;
    flat.superblock_blocks = 1;
    grouped.superblock_blocks = 4;
    const VisibilityIndex a(map, flat), b(map, grouped);
    const core::CameraModel cam = testCameras()[0];
    std::mt19937 rng(6);
    std::uniform_real_distribution<double> U(-25, 25);
    for (int trial = 0; trial < 20; ++trial)
    {
        const auto T = lookAt({U(rng), U(rng), 0}, {U(rng), U(rng), 0.5});
        std::vector<VisibilityIndex::Range> ra, rb;
        a.query(T, cam, 20, ra);
        b.query(T, cam, 20, rb);
        std::vector<uint32_t> ia, ib;
        for (const auto& r : ra)
            for (uint32_t k = r.begin; k < r.end; ++k) ia.push_back(a.mapIndex()[k]);
        for (const auto& r : rb)
            for (uint32_t k = r.begin; k < r.end; ++k) ib.push_back(b.mapIndex()[k]);
        std::sort(ia.begin(), ia.end());
        std::sort(ib.begin(), ib.end());
        EXPECT_EQ(ia, ib) << "trial " << trial;
    }
}

TEST(VisibilityIndex, ViewConeOfAPinholeIsItsImageRectangle)
{
    const core::CameraModel cam = core::CameraModel::pinhole(640, 480, 400, 400, 319.5, 239.5);
    const auto cone = VisibilityIndex::viewCone(cam);
    ASSERT_TRUE(cone.bounded);
    EXPECT_EQ(cone.side_normals.size(), 4u) << "diagonal planes are redundant for a rectangle";
    EXPECT_NEAR(cone.xn_min.x(), -320.0 / 400, 0.01);
    EXPECT_NEAR(cone.xn_max.x(), 320.0 / 400, 0.01);
    EXPECT_NEAR(cone.xn_min.y(), -240.0 / 400, 0.01);
    EXPECT_NEAR(cone.xn_max.y(), 240.0 / 400, 0.01);
    EXPECT_FALSE(VisibilityIndex::viewCone(core::CameraModel()).bounded);
}

TEST(VisibilityIndex, AQueryInALargeSparseWorldFindsEveryVisiblePointOfItsOwnCluster)
{
    // Rooms 100 m apart over 1 km: a query looks up only the super-block cells its range covers (not every
    // super-block of the map); it must still miss nothing, and return nothing from the other rooms.
    LidarMap map;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> U(-4.f, 4.f);
    for (int gy = 0; gy < 11; ++gy)
        for (int gx = 0; gx < 11; ++gx)
            for (int k = 0; k < 2000; ++k)
                map.addPoint(100.f * gx + U(rng), 100.f * gy + U(rng), 1.5f + 0.3f * U(rng), 0.5f);
    const VisibilityIndex index(map, {});
    const core::CameraModel cam = testCameras()[1];
    for (const auto& [eye, target] : {std::pair<Eigen::Vector3d, Eigen::Vector3d>{{500, 500, 1}, {503, 501, 1.5}},
                                      {{-3, 2, 1.5}, {4, -1, 1}},
                                      {{1000, 996, 2}, {1000, 1003, 1}}})
    {
        const auto T = lookAt(eye, target);
        std::vector<VisibilityIndex::Range> ranges;
        index.query(T, cam, 15, ranges);
        size_t visible = 0;
        EXPECT_EQ(missedVisiblePoints(index, T, cam, 15, coverage(index, ranges), &visible), 0u);
        EXPECT_GT(visible, 100u);
        EXPECT_LE(VisibilityIndex::countPoints(ranges), 2000u) << "only the camera's own room is in range";
    }
}
