// searchAlongTrack: a wall ahead gives the position along the street back to a track that drifted along it; a
// street with nothing across it gives no fix; the prior widens along the fix's direction only.
#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/tracking/along_track_search.h>

#include "floor_wall_scene.h"

using namespace quasiloc;

namespace
{
/** Stereo points of the road (z = 0) every metre from 7 to 25 m ahead across +-3 m, and of a wall at wall_x (if
 *  any) up to 3 m, in the frame of the true camera; sigmas of a 0.54 m, fx 721 rig at 0.5 px. */
void stereoPoints(const Eigen::Isometry3d& T_world_cam, double wall_x, std::vector<Eigen::Vector3d>& p_cam,
                  std::vector<double>& sigma_m)
{
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    const auto add = [&](const Eigen::Vector3d& p_world) {
        const Eigen::Vector3d p = T_cam_world * p_world;
        p_cam.push_back(p);
        sigma_m.push_back(std::hypot(0.02, p.z() * p.z() / (721 * 0.54) * 0.5));
    };
    for (double x = 7; x <= 25; x += 1)
        for (double y = -3; y <= 3; y += 0.5) add({x, y, 0});
    if (wall_x > 0)
        for (double y = -3; y <= 3; y += 0.25)
            for (double z = 0.25; z <= 3; z += 0.25) add({wall_x, y, z});
}

map::DistanceField fieldOf(const map::LidarMap& map)
{
    map::DistanceFieldOptions o;
    o.voxel_m = 0.05;
    return map::DistanceField::build(map, o);
}

/** The true camera 1.65 m above the road looking along x, its stereo points, and a track 2.3 m behind it. */
struct Street
{
    Eigen::Isometry3d T_true = tracking::test::cameraAlongX(1.65), T_pred;
    std::vector<Eigen::Vector3d> p_cam;
    std::vector<double> sigma_m;
    explicit Street(double wall_x)
    {
        stereoPoints(T_true, wall_x, p_cam, sigma_m);
        T_pred = T_true;
        T_pred.translation().x() -= 2.3;
    }
};
}  // namespace

TEST(AlongTrackSearch, AWallAheadGivesThePositionAlongTheStreet)
{
    const map::DistanceField field = fieldOf(tracking::test::floorAndWall(-5, 32, 18, 6, 4, 0.05f));
    const Street s(18);
    tracking::AlongTrackSearchOptions o;
    const tracking::AlongTrackFix fix = tracking::searchAlongTrack(field, s.T_pred, s.p_cam, s.sigma_m, o);
    EXPECT_TRUE(fix.found);
    EXPECT_NEAR(fix.shift_m, 2.3, 0.1 + 1e-9);
    EXPECT_NEAR(fix.direction_world.x(), 1.0, 1e-9);
    EXPECT_GT(fix.chi2_prediction - fix.chi2_best, o.min_gain);
    // The scores averaged over +-0.2 m of shifts find the same position.
    o.smooth_m = 0.2;
    const tracking::AlongTrackFix smoothed = tracking::searchAlongTrack(field, s.T_pred, s.p_cam, s.sigma_m, o);
    EXPECT_TRUE(smoothed.found);
    EXPECT_NEAR(smoothed.shift_m, 2.3, 0.1 + 1e-9);
    o.smooth_m = 0;
    // At the truth the best shift is the prediction: no fix.
    const tracking::AlongTrackFix at_truth = tracking::searchAlongTrack(field, s.T_true, s.p_cam, s.sigma_m, o);
    EXPECT_FALSE(at_truth.found);
    EXPECT_NEAR(at_truth.shift_m, 0.0, 0.1 + 1e-9);
}

TEST(AlongTrackSearch, AStreetWithNothingAcrossItGivesNoFix)
{
    // The road alone (its wall far beyond the points' reach): every shift along it explains the points alike.
    const map::DistanceField field = fieldOf(tracking::test::floorAndWall(-10, 40, 39, 6, 4, 0.05f));
    const Street s(0);
    const tracking::AlongTrackFix fix =
        tracking::searchAlongTrack(field, s.T_pred, s.p_cam, s.sigma_m, tracking::AlongTrackSearchOptions{});
    EXPECT_FALSE(fix.found);
    EXPECT_LT(std::abs(fix.chi2_prediction - fix.chi2_best), 1.0);
}

TEST(AlongTrackSearch, ThePriorWidensAlongTheFixOnly)
{
    estimation::StatePrior prior;
    prior.mean.T_map_body.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    Eigen::Matrix<double, 15, 1> sigma;
    sigma << Eigen::Vector3d::Constant(0.01), Eigen::Vector3d::Constant(0.05), Eigen::Vector3d::Constant(0.05),
        Eigen::Vector3d::Constant(0.001), Eigen::Vector3d::Constant(0.01);
    prior.information = sigma.cwiseInverse().cwiseAbs2().asDiagonal();
    tracking::AlongTrackFix fix;
    fix.found = true;
    fix.shift_m = 2.0;
    fix.direction_world = Eigen::Vector3d::UnitX();
    tracking::widenAlongTrack(prior, fix, 0.5);
    const estimation::Matrix15d cov = prior.information.inverse();
    // World x is the body's -y (the body is turned by 90 degrees about z): the body-frame tangent's y widens.
    EXPECT_NEAR(cov(4, 4), 0.05 * 0.05 + 4.0, 1e-9);
    EXPECT_NEAR(cov(3, 3), 0.05 * 0.05, 1e-9);
    EXPECT_NEAR(cov(5, 5), 0.05 * 0.05, 1e-9);
    EXPECT_NEAR(cov(6, 6), 0.05 * 0.05 + 0.25, 1e-9);
    EXPECT_NEAR(cov(7, 7), 0.05 * 0.05, 1e-9);
    EXPECT_NEAR(cov(0, 0), 0.01 * 0.01, 1e-12);
    // The measurement weighs the body-frame direction of world x only.
    const estimation::PoseMeasurement m = tracking::alongTrackMeasurement(fix, prior.mean.T_map_body, 0.3);
    EXPECT_NEAR(m.T_map_body.translation().x(), 2.0, 1e-12);
    EXPECT_NEAR(m.information(4, 4), 1 / 0.09, 1e-9);
    EXPECT_NEAR(m.information.trace(), 1 / 0.09, 1e-9);
}
