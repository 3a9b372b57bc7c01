#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/quasi/synthetic_scene.h>
#include <quasiloc/reloc/view_sampling.h>

using namespace quasiloc;

TEST(ViewSampling, ViewPoseLooksAlongItsHeadingWithoutRoll)
{
    const double pi = 3.14159265358979;
    const auto T = reloc::viewPose(1, 2, 3, pi / 2, 0.2);  // heading +y, looking slightly up
    mrpt::math::TPoint3D local;
    T.inverseComposePoint(mrpt::math::TPoint3D(1, 7, 3 + 5 * std::tan(0.2)), local);  // straight ahead
    EXPECT_NEAR(local.x, 0, 1e-9);
    EXPECT_NEAR(local.y, 0, 1e-9);
    EXPECT_GT(local.z, 4.9);
    T.inverseComposePoint(mrpt::math::TPoint3D(1, 2, 10), local);  // above: image up = camera -y
    EXPECT_LT(local.y, 0);
    T.inverseComposePoint(mrpt::math::TPoint3D(0, 3, 3), local);  // to the left of +y is -x in the world
    EXPECT_LT(local.x, 0);
}

TEST(ViewSampling, ViewsAreInsideTheRoomClearOfGeometryAtTheGivenHeights)
{
    const map::LidarMap room = quasi::makeSyntheticRoom(400000, 8.0f, 3.0f);
    reloc::ViewSamplingOptions o;
    o.grid_spacing_m = 1.0;
    o.heights_m = {1.0, 1.6};
    o.num_headings = 4;
    o.pitches_deg = {0, -10};
    reloc::ViewSamplingStats st;
    const auto views = reloc::sampleViewpoints(room, o, &st);
    ASSERT_FALSE(views.empty());
    EXPECT_EQ(st.views, views.size());
    EXPECT_EQ(views.size(), st.positions * 4 * 2);
    EXPECT_GT(st.not_clear, 0u);  // the boxes standing in the room block some positions
    for (const auto& T : views)
    {
        EXPECT_GT(T.x(), -4.0);
        EXPECT_LT(T.x(), 4.0);
        EXPECT_TRUE(std::abs(T.z() - 1.0) < 0.15 || std::abs(T.z() - 1.6) < 0.15) << T.z();
    }
    // Clearance: no map point closer than clearance_m to a sampled position (brute force on a subsample).
    for (size_t v = 0; v < views.size(); v += 8)
    {
        double nearest = 1e9;
        for (size_t i = 0; i < room.size(); i += 3)
        {
            const Eigen::Vector3f p = room.point(i);
            nearest = std::min(nearest, std::hypot(p.x() - views[v].x(), p.y() - views[v].y(), p.z() - views[v].z()));
        }
        EXPECT_GT(nearest, o.clearance_m - 0.02);
    }
}

TEST(ViewSampling, EnclosureRejectsPositionsOutsideTheRoom)
{
    const map::LidarMap room = quasi::makeSyntheticRoom(300000, 4.0f, 3.0f);
    reloc::ViewSamplingOptions o;
    o.grid_spacing_m = 0.5;
    o.heights_m = {1.2};
    o.num_headings = 1;
    o.margin_m = 0;
    // The region is wider than the room; the floor under the outside cells is missing, and with a floor
    // added outside the room, enclosure still rejects them.
    o.region = {-6, -6, 6, 6};
    map::LidarMap with_yard = room;
    for (float x = -6; x <= 6; x += 0.05f)
        for (float y = -6; y <= 6; y += 0.05f)
            if (std::abs(x) > 2.2f || std::abs(y) > 2.2f) with_yard.addPoint(x, y, 0.0f, 0.5f);
    reloc::ViewSamplingStats st;
    const auto views = reloc::sampleViewpoints(with_yard, o, &st);
    ASSERT_FALSE(views.empty());
    EXPECT_GT(st.not_enclosed, 0u);
    for (const auto& T : views)
    {
        EXPECT_LT(std::abs(T.x()), 2.0);
        EXPECT_LT(std::abs(T.y()), 2.0);
    }
    o.require_enclosed = false;  // outdoors: the yard is fine
    EXPECT_GT(reloc::sampleViewpoints(with_yard, o).size(), views.size());
}

TEST(ViewSampling, BadOptionsAndEmptyMapsAreErrors)
{
    reloc::ViewSamplingOptions o;
    mrpt::config::CConfigFileMemory ini;
    ini.setContent("[ViewSampling]\ngrid_spacing_m = 0\n");
    EXPECT_THROW(o.loadFromConfigFile(ini, "ViewSampling"), core::InputError);
    o.region = {1, 2, 0, 3};
    EXPECT_THROW(o.check("test.ini"), core::InputError);
    EXPECT_THROW(reloc::sampleViewpoints(map::LidarMap(), reloc::ViewSamplingOptions{}), core::InputError);
}
