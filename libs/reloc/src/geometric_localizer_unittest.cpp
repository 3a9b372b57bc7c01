// Global localization by geometry on the simulated room: a rendered stereo frame localizes with no initial guess,
// the refinement converges from a few decimetres, a scene that is not the room is "not localized", and bad
// options are named.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>
#include <filesystem>
#include <random>

#include "test_room.h"

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;

struct Fixture
{
    sim::World world;
    map::LidarMap map;
    core::StereoRig rig;
    std::unique_ptr<reloc::GeometricLocalizer> localizer;
};

reloc::GeometricLocalizationOptions testOptions()
{
    reloc::GeometricLocalizationOptions o;
    o.region = {-2.0, -1.5, 1.0, 1.5};  // part of the room: keeps the test short (the query lies inside)
    return o;
}

const Fixture& fixture()
{
    static const Fixture f = [] {
        Fixture f;
        f.world = reloc::test::testRoom(kShared);
        f.map = reloc::test::testRoomMap(f.world);
        const std::string calib = kShared + "/data/euroc/calib/";
        f.rig = core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml");
        f.localizer = std::make_unique<reloc::GeometricLocalizer>(f.map, f.rig, testOptions());
        return f;
    }();
    return f;
}

/** A camera in the room, tilted down and rolled a little, as the MAV flies. */
Eigen::Isometry3d queryPose()
{
    Eigen::Isometry3d T = core::toIsometry(reloc::viewPose(-0.6, 0.3, 1.25, 35 * M_PI / 180, -18 * M_PI / 180));
    T.linear() = T.linear() * Eigen::AngleAxisd(4 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
}

std::vector<Eigen::Vector3f> stereoPoints(const Fixture& f, const Eigen::Isometry3d& T_world_cam)
{
    sim::StereoRenderer renderer(f.world, f.rig, sim::AppearanceOptions(), 7);
    cv::Mat left, right;
    renderer.render({core::fromIsometry(T_world_cam)}, 0.0, 0, left, right);
    return reloc::StereoCloud(f.rig, testOptions().stereo).compute(left, right);
}

Eigen::Vector3d upIn(const Eigen::Isometry3d& T_world_cam)
{
    return T_world_cam.linear().transpose() * Eigen::Vector3d::UnitZ();
}

double errorM(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return core::translationDistance(a, b); }
double errorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
    return core::rotationDistanceRad(a, b) * 180 / M_PI;
}
}  // namespace

TEST(GeometricLocalizer, LocalizesARenderedStereoFrameWithNoGuess)
{
    const Fixture& f = fixture();
    const Eigen::Isometry3d T_true = queryPose();
    const auto points = stereoPoints(f, T_true);
    ASSERT_GT(points.size(), 500u);
    // Gravity as an accelerometer on a slowly moving platform measures it: 3 deg off.
    const Eigen::Vector3d up = Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitX()) * upIn(T_true);
    const reloc::GeometricLocalization r = f.localizer->localizePoints(points, up);
    std::cout << "localized " << r.localized << " (" << r.reason << "), inliers " << r.inlier_ratio << ", runner-up "
              << r.runner_up_inlier_ratio << ", error " << errorM(r.T_world_cam, T_true) << " m "
              << errorDeg(r.T_world_cam, T_true) << " deg, " << f.localizer->positions() << " positions, "
              << r.candidates << " candidates\n";
    EXPECT_TRUE(r.localized) << r.reason;
    EXPECT_LT(errorM(r.T_world_cam, T_true), 0.04);
    EXPECT_LT(errorDeg(r.T_world_cam, T_true), 1.0);
}

TEST(GeometricLocalizer, ASearchSphereScoresOnlyThePositionsInsideIt)
{
    // A relocalization near the last confirmed pose: the same answer from a fraction of the candidates, and a
    // sphere holding no candidate position is a reason, not a guess.
    const Fixture& f = fixture();
    const Eigen::Isometry3d T_true = queryPose();
    const auto points = stereoPoints(f, T_true);
    const reloc::GeometricLocalization all = f.localizer->localizePoints(points, upIn(T_true));
    const reloc::SearchSphere near{T_true.translation() + Eigen::Vector3d(0.3, -0.2, 0.1), 0.8};
    const reloc::GeometricLocalization r = f.localizer->localizePoints(points, upIn(T_true), &near);
    EXPECT_TRUE(r.localized) << r.reason;
    EXPECT_LT(errorM(r.T_world_cam, T_true), 0.04);
    EXPECT_LT(errorDeg(r.T_world_cam, T_true), 1.0);
    EXPECT_GT(r.candidates, 0u);
    EXPECT_LT(4 * r.candidates, all.candidates) << "the sphere should leave out most positions";
    const reloc::SearchSphere nowhere{Eigen::Vector3d(50, 50, 50), 1.0};
    const reloc::GeometricLocalization none = f.localizer->localizePoints(points, upIn(T_true), &nowhere);
    EXPECT_FALSE(none.localized);
    EXPECT_NE(none.reason.find("no candidate position within"), std::string::npos) << none.reason;
}

TEST(GeometricLocalizer, AHeadingSearchesAndWeighsOnlyTheRotationsNearIt)
{
    // A relocalization whose track kept its orientation: the same answer from the headings near it alone; the
    // opposite heading searches only there (the true place, 180 deg away, is neither an answer nor a rival).
    const Fixture& f = fixture();
    const Eigen::Isometry3d T_true = queryPose();
    const auto points = stereoPoints(f, T_true);
    const reloc::GeometricLocalization all = f.localizer->localizePoints(points, upIn(T_true));
    reloc::SearchSphere near{T_true.translation(), 1e9};
    near.R_world_cam = T_true.linear();
    near.heading_bound_deg = 10;
    const reloc::GeometricLocalization r = f.localizer->localizePoints(points, upIn(T_true), &near);
    EXPECT_TRUE(r.localized) << r.reason;
    EXPECT_LT(errorM(r.T_world_cam, T_true), 0.04);
    EXPECT_LT(errorDeg(r.T_world_cam, T_true), 1.0);
    EXPECT_LT(6 * r.candidates, all.candidates) << "about 3 of 36 headings";
    near.R_world_cam = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix() * T_true.linear();
    const reloc::GeometricLocalization turned = f.localizer->localizePoints(points, upIn(T_true), &near);
    if (turned.inlier_ratio > 0)
    {
        EXPECT_GT(errorDeg(turned.T_world_cam, T_true), 160);
    }
    EXPECT_FALSE(turned.localized && errorDeg(turned.T_world_cam, T_true) < 20);
}

TEST(GeometricLocalizer, RefinementConvergesFromAFewDecimetres)
{
    const Fixture& f = fixture();
    const Eigen::Isometry3d T_true = queryPose();
    const auto points = stereoPoints(f, T_true);
    std::mt19937 rng(9);
    std::normal_distribution<double> n(0, 1);
    for (int k = 0; k < 5; ++k)
    {
        Eigen::Isometry3d T = T_true;
        const Eigen::Vector3d dp = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized() * 0.2;
        const Eigen::Vector3d dr = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized() * (5 * M_PI / 180);
        T.translation() += dp;
        T.linear() = T.linear() * Eigen::AngleAxisd(dr.norm(), dr.normalized()).toRotationMatrix();
        const double inliers = f.localizer->refine(points, T);
        EXPECT_LT(errorM(T, T_true), 0.06) << "draw " << k;
        EXPECT_LT(errorDeg(T, T_true), 1.5) << "draw " << k;
        EXPECT_GT(inliers, 0.5) << "draw " << k;
    }
}

TEST(GeometricLocalizer, ASceneThatIsNotTheRoomIsNotLocalized)
{
    const Fixture& f = fixture();
    // A cloud with no surface: stereo points of something else entirely (random points 1-4 m ahead).
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f), depth(1.f, 4.f);
    std::vector<Eigen::Vector3f> points;
    for (int i = 0; i < 1500; ++i) points.emplace_back(u(rng), u(rng), depth(rng));
    const reloc::GeometricLocalization r = f.localizer->localizePoints(points, upIn(queryPose()));
    EXPECT_FALSE(r.localized);
    EXPECT_NE(r.reason.find("min_inlier_ratio"), std::string::npos) << r.reason;
    // Too few points: an answer with the reason, not an exception.
    const auto few = f.localizer->localizePoints({points.begin(), points.begin() + 20}, upIn(queryPose()));
    EXPECT_FALSE(few.localized);
    EXPECT_NE(few.reason.find("too few"), std::string::npos) << few.reason;
}

TEST(GeometricLocalizer, UpInCameraFromTheAccelerometer)
{
    // Body level (specific force +z), camera looking along body +x with x right and y down.
    Eigen::Matrix3d R_body_cam;
    R_body_cam << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    const Eigen::Vector3d up = reloc::upInCamera({{0.1, -0.05, 9.8}, {-0.1, 0.05, 9.82}}, R_body_cam.transpose());
    EXPECT_NEAR((up - Eigen::Vector3d(0, -1, 0)).norm(), 0.0, 1e-9);
    EXPECT_THROW(reloc::upInCamera({}, R_body_cam), core::InputError);
}

TEST(GeometricLocalizer, BadOptionsAreNamed)
{
    reloc::GeometricLocalizationOptions o;
    mrpt::config::CConfigFileMemory ini;
    ini.setContent("[GeometricLocalization]\nnum_yaws = 0\n");
    try
    {
        core::loadOptionsChecked(o, ini, "GeometricLocalization", "track.ini");
        FAIL() << "no error for num_yaws = 0";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("num_yaws"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("track.ini"), std::string::npos) << e.what();
    }
    o = reloc::GeometricLocalizationOptions();
    o.stereo.num_disparities = 50;
    EXPECT_THROW(o.check("track.ini"), core::InputError);
}

TEST(GeometricLocalizer, PlaceRetrievalFindsTheFrameFromAFractionOfTheCandidates)
{
    // The retrieval stage forced on the room (it runs by default only above retrieval_min_positions): the same
    // answer from the positions near the retrieved places, at headings near theirs.
    const Fixture& f = fixture();
    reloc::GeometricLocalizationOptions o = testOptions();
    o.retrieval_min_positions = 0;
    o.retrieval_places = 20;
    const reloc::GeometricLocalizer with(f.map, f.rig, o);
    ASSERT_NE(with.places(), nullptr);
    EXPECT_GT(with.places()->size(), 50u);
    EXPECT_LT(with.places()->size(), with.positions());
    const Eigen::Isometry3d T_true = queryPose();
    sim::StereoRenderer renderer(f.world, f.rig, sim::AppearanceOptions(), 7);
    cv::Mat left, right;
    renderer.render({core::fromIsometry(T_true)}, 0.0, 0, left, right);
    const reloc::GeometricLocalization all = f.localizer->localize(left, right, upIn(T_true));
    const reloc::GeometricLocalization r = with.localize(left, right, upIn(T_true));
    std::cout << "retrieval: " << r.retrieved_places << " places, " << r.candidates
              << " candidates (whole: " << all.candidates << "), error " << errorM(r.T_world_cam, T_true) << " m\n";
    EXPECT_TRUE(r.localized) << r.reason;
    EXPECT_EQ(r.retrieved_places, 20u);
    EXPECT_LT(errorM(r.T_world_cam, T_true), 0.04);
    EXPECT_LT(errorDeg(r.T_world_cam, T_true), 1.0);
    EXPECT_LT(5 * r.candidates, all.candidates) << "retrieval should leave out most candidates";
    // A place file of another map is refused, naming the file.
    const std::string file = (std::filesystem::temp_directory_path() / "quasiloc_other_map.qplaces").string();
    reloc::PlaceIndex other = *with.places();
    other.map.hash ^= 1;
    other.save(file);
    o.places_file = file;
    try
    {
        reloc::GeometricLocalizer bad(f.map, f.rig, o);
        ADD_FAILURE() << "a place file of another map was read";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("another map"), std::string::npos) << e.what();
    }
    std::filesystem::remove(file);
}

TEST(GeometricLocalizer, PlacesAreBuiltOnlyWhenASearchNeedsThem)
{
    // A search within a small prior sphere holds fewer positions than retrieval_min_positions and is searched whole:
    // the places of the whole map are not built for it. The first search over more positions builds them.
    const Fixture& f = fixture();
    reloc::GeometricLocalizationOptions o = testOptions();
    o.retrieval_min_positions = 100;
    const reloc::GeometricLocalizer lazy(f.map, f.rig, o);
    ASSERT_GT(lazy.positions(), 100u);
    EXPECT_EQ(lazy.placesBuildSeconds(), 0.0);
    const Eigen::Isometry3d T_true = queryPose();
    sim::StereoRenderer renderer(f.world, f.rig, sim::AppearanceOptions(), 7);
    cv::Mat left, right;
    renderer.render({core::fromIsometry(T_true)}, 0.0, 0, left, right);
    const reloc::SearchSphere near(T_true.translation(), 0.5);
    const reloc::GeometricLocalization r = lazy.localize(left, right, upIn(T_true), &near);
    EXPECT_TRUE(r.localized) << r.reason;
    EXPECT_EQ(r.retrieved_places, 0u);
    EXPECT_EQ(lazy.placesBuildSeconds(), 0.0) << "a search inside the prior built the places";
    const reloc::GeometricLocalization whole = lazy.localize(left, right, upIn(T_true));
    EXPECT_GT(whole.retrieved_places, 0u);
    EXPECT_GT(lazy.placesBuildSeconds(), 0.0);
    ASSERT_NE(lazy.places(), nullptr);
    EXPECT_GT(lazy.places()->size(), 50u);
}
