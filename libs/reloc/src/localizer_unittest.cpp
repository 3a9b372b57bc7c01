// Global localization on a simulated room : a query rendered exactly at a database view
// localizes to < 1 cm, one between views to < 0.3 m, and a query of a place that is not in the map answers
// "not localized". The queries are quasi-images (the map seen from the query pose), so the test checks the
// localization machinery, not cross-modal matching (which bench_crossmodal and quasiloc-localize measure).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/synthetic_scene.h>
#include <quasiloc/reloc/database_builder.h>
#include <quasiloc/reloc/localizer.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/world_builder.h>

#include "test_room.h"

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;

struct Fixture
{
    map::LidarMap map;
    core::CameraModel camera;
    reloc::Database db;
    reloc::DatabaseBuildStats stats;
};

reloc::DatabaseBuildConfig testConfig()
{
    reloc::DatabaseBuildConfig c;
    c.sampling.grid_spacing_m = 0.5;
    c.sampling.heights_m = {1.3};
    c.sampling.pitches_deg = {-10};
    c.sampling.num_headings = 12;
    c.build.store_lines = false;                 // not used by the localizer; keeps the test short
    c.quasi.reflectivity_scope = "map";          // the same point gets the same grey level in every view
    c.sampling.region = {-1.5, -1.0, 0.5, 1.0};  // part of the room: keeps the test short
    c.features.dense_map = false;
    c.association.lift_search_radius_px = 1;
    return c;
}

const Fixture& fixture()
{
    static const Fixture f = [] {
        Fixture f;
        const sim::World world = reloc::test::testRoom(kShared);
        f.map = reloc::test::testRoomMap(world);
        const std::string calib = kShared + "/data/euroc/calib/";
        f.camera = core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml").left;
        f.db = reloc::buildDatabase(f.map, f.camera, testConfig(), &f.stats);
        return f;
    }();
    return f;
}

cv::Mat renderQuery(const map::LidarMap& map, const core::CameraModel& camera, const mrpt::poses::CPose3D& T_world_cam)
{
    quasi::QuasiRenderer renderer(map, testConfig().quasi);  // rendered as the database's views are
    quasi::QuasiImage q;
    renderer.render(T_world_cam, camera, q);
    return q.gray.clone();
}

double translationError(const reloc::LocalizationReport& r, const mrpt::poses::CPose3D& T)
{
    return (r.T_world_cam.translation() - Eigen::Vector3d(T.x(), T.y(), T.z())).norm();
}
}  // namespace

void checkDatabaseRoundTrip()
{
    const Fixture& f = fixture();
    std::cout << "database: " << f.db.summary() << "; sampled " << f.stats.sampling.views << " views, kept "
              << f.stats.kept << ", " << f.stats.ms_per_view_cpu << " ms per view\n";
    ASSERT_GT(f.db.views.size(), 60u);  // (ASSERTs in these helpers end the helper, not the test)
    EXPECT_GT(f.db.views.front().numLifted(), 100);
    EXPECT_TRUE(f.db.views.front().lines.empty());
    const std::string path = testing::TempDir() + "/reloc_test.qdb";
    f.db.save(path);
    const reloc::Database back = reloc::Database::load(path);
    ASSERT_EQ(back.views.size(), f.db.views.size());
    EXPECT_EQ(back.camera.fx, f.camera.fx);
    EXPECT_EQ(back.features.type, f.db.features.type);
    EXPECT_EQ(back.features.max_keypoints, f.db.features.max_keypoints);
    EXPECT_EQ(back.image_blur_sigma_px, f.db.image_blur_sigma_px);
    const auto& a = f.db.views[7];
    const auto& b = back.views[7];
    EXPECT_EQ(cv::norm(a.points.descriptors, b.points.descriptors, cv::NORM_INF), 0.0);
    ASSERT_EQ(a.points.keypoints.size(), b.points.keypoints.size());
    EXPECT_EQ(a.points.keypoints[3].pt, b.points.keypoints[3].pt);
    EXPECT_EQ(a.words, b.words);
    EXPECT_EQ(a.words, f.db.vocabulary.words(a.points.descriptors));
    EXPECT_EQ(b.points.image_size, cv::Size(f.camera.width, f.camera.height));
    EXPECT_EQ(a.bow, b.bow);
    EXPECT_TRUE((a.T_world_cam.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>() -
                 b.T_world_cam.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>())
                    .array()
                    .abs()
                    .maxCoeff() == 0);
    std::filesystem::remove(path);
}

TEST(Localizer, LoadRejectsAFileThatIsNotADatabase)
{
    const std::string path = testing::TempDir() + "/not_a_db.qdb";
    {
        std::ofstream(path) << "hello";
    }
    EXPECT_THROW(reloc::Database::load(path), core::InputError);
    EXPECT_THROW(reloc::Database::load(path + ".missing"), core::InputError);
    std::filesystem::remove(path);
}

void checkQueryAtADatabaseView()
{
    const Fixture& f = fixture();
    reloc::Localizer loc(f.db, reloc::LocalizerOptions{});
    for (int id : {5, int(f.db.views.size() / 2), int(f.db.views.size()) - 3})
    {
        const auto& T = f.db.views[size_t(id)].T_world_cam;
        const auto r = loc.localize(renderQuery(f.map, f.camera, T), f.camera, reloc::LocalizationMode::Fast);
        ASSERT_TRUE(r.localized) << "view " << id << ": " << reloc::describe(r, f.db);
        EXPECT_LT(translationError(r, T), 0.01) << reloc::describe(r, f.db);
        EXPECT_LT(core::rotationDistanceRad(T, core::fromIsometry(r.T_world_cam)) * 180 / 3.14159265358979, 0.5);
    }
}

void checkQueryBetweenViews()
{
    const Fixture& f = fixture();
    reloc::Localizer loc(f.db, reloc::LocalizerOptions{});
    int tried = 0, ok = 0, wrong = 0;
    // Half a grid step off in x and y, 0.2 m higher, heading half-way between two database headings, another
    // pitch: a pose no view has. Every 13th view of the database gives one query.
    for (size_t id = 3; id < f.db.views.size(); id += 13)
    {
        const auto& V = f.db.views[id].T_world_cam;
        const auto R = V.getRotationMatrix();
        const double heading = std::atan2(R(1, 2), R(0, 2)) + 3.14159265358979 / 12;
        const auto T = reloc::viewPose(V.x() + 0.25, V.y() + 0.25, V.z() + 0.2, heading, -0.1);
        const auto r = loc.localize(renderQuery(f.map, f.camera, T), f.camera, reloc::LocalizationMode::Fast);
        ++tried;
        if (r.localized && translationError(r, T) < 0.3) ++ok;
        if (r.localized && translationError(r, T) > 1.0) ++wrong;
        if (!r.localized)
            std::cout << "  query near view " << id << ": not localized: " << r.reason << "\n";
        else if (translationError(r, T) >= 0.3)
            std::cout << "  query near view " << id << ": localized " << translationError(r, T) << " m off\n";
    }
    std::cout << "between views: " << ok << " of " << tried << " localized within 0.3 m, " << wrong
              << " more than 1 m off\n";
    // Measured when this test was written: 11 of 20 (one more at 0.39 m), none more than 1 m off. Corners on
    // quasi-images repeat poorly across viewpoints (blurred LiDAR speckle), so a denser database helps more than
    // anything in the localizer.
    EXPECT_GE(ok, tried / 2);
    EXPECT_EQ(wrong, 0);
}

void checkPlaceOutsideTheMap()
{
    const Fixture& f = fixture();
    reloc::Localizer loc(f.db, reloc::LocalizerOptions{});
    // Another place entirely: a synthetic checker room (not part of the map).
    const map::LidarMap other = quasi::makeSyntheticRoom(600000);
    for (double yaw : {0.0, 1.6, 3.2})
    {
        const auto T = reloc::viewPose(0.3, -0.4, 1.4, yaw, 0.0);
        const auto r = loc.localize(renderQuery(other, f.camera, T), f.camera, reloc::LocalizationMode::Full);
        EXPECT_FALSE(r.localized) << reloc::describe(r, f.db);
    }
    // Sensor noise: nothing of any place.
    cv::Mat noise(f.camera.height, f.camera.width, CV_8UC1);
    cv::randu(noise, 0, 255);
    EXPECT_FALSE(loc.localize(noise, f.camera, reloc::LocalizationMode::Full).localized);
}

void checkBadInput()
{
    const Fixture& f = fixture();
    reloc::Localizer loc(f.db, reloc::LocalizerOptions{});
    EXPECT_THROW(loc.localize(cv::Mat(), f.camera, reloc::LocalizationMode::Fast), core::InputError);
    EXPECT_THROW(loc.localize(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), f.camera, reloc::LocalizationMode::Fast),
                 core::InputError);
    reloc::LocalizerOptions o;
    o.fast_groups_retry = 2;
    EXPECT_THROW(reloc::Localizer(f.db, o), core::InputError);
}

// One test for everything that needs the simulated room's database: building it (world, LiDAR map, 250 views)
// takes about 10 s, and ctest runs every TEST in its own process.
TEST(Localizer, GlobalLocalizationInASimulatedRoom)
{
    {
        SCOPED_TRACE("database build and file round trip");
        checkDatabaseRoundTrip();
    }
    {
        SCOPED_TRACE("a query rendered at a database view localizes to < 1 cm");
        checkQueryAtADatabaseView();
    }
    {
        SCOPED_TRACE("queries between views localize within 0.3 m");
        checkQueryBetweenViews();
    }
    {
        SCOPED_TRACE("a place outside the map is not localized");
        checkPlaceOutsideTheMap();
    }
    {
        SCOPED_TRACE("bad input is an InputError");
        checkBadInput();
    }
}
