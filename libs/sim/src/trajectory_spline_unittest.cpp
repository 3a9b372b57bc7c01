// TrajectorySpline: fit to the real EuRoC V1_01_easy trajectory, C2 smoothness across knots, analytic
// derivatives against finite differences, recovery of an analytic motion, and input checks.
#include <gtest/gtest.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/sim/trajectory_spline.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <random>

namespace
{
using quasiloc::sim::BodyState;
using quasiloc::sim::TrajectorySpline;

const std::string kEuroc = std::string(QUASILOC_SHARED_DIR) + "/data/euroc";

Eigen::Vector3d rotationLog(const Eigen::Matrix3d& R)
{
    const Eigen::AngleAxisd aa(R);
    return aa.angle() * aa.axis();
}

/** V1_01_easy fitted once for every test of this file (about 0.1-0.5 s). */
const TrajectorySpline& v101Spline()
{
    static const TrajectorySpline spline = [] {
        const auto traj = quasiloc::core::readTum(kEuroc + "/groundtruth/cam0/V1_01_easy.txt");
        const auto T_body_cam0 = quasiloc::core::readEurocSensorPose(kEuroc + "/calib/cam0_sensor.yaml");
        const auto start = std::chrono::steady_clock::now();
        TrajectorySpline s = TrajectorySpline::fitCameraTrajectory(traj, T_body_cam0);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf(
            "[ fit      ] V1_01_easy: %zu poses (%zu duplicates dropped), %.1f s, %zu control points, "
            "%d SO(3) Gauss-Newton iterations, fit time %.3f s\n",
            s.fitStats().num_samples, s.fitStats().num_duplicates_dropped, s.tEnd() - s.tStart(),
            s.fitStats().num_control_points, s.fitStats().rotation_iterations, secs);
        return s;
    }();
    return spline;
}

TEST(TrajectorySpline, ReproducesEurocPoses)
{
    const auto traj = quasiloc::core::readTum(kEuroc + "/groundtruth/cam0/V1_01_easy.txt");
    const auto T_body_cam0 = quasiloc::core::readEurocSensorPose(kEuroc + "/calib/cam0_sensor.yaml");
    const TrajectorySpline& spline = v101Spline();
    const auto& st = spline.fitStats();
    std::printf("[ residual ] body position RMS %.3f mm, max %.3f mm; rotation RMS %.4f deg, max %.4f deg\n",
                st.rms_position_m * 1e3, st.max_position_m * 1e3, st.rms_rotation_rad * 180 / M_PI,
                st.max_rotation_rad * 180 / M_PI);
    EXPECT_GT(st.num_duplicates_dropped, 0u);  // the file starts with repeated rows
    EXPECT_EQ(st.num_samples + st.num_duplicates_dropped, traj.poses.size());
    EXPECT_DOUBLE_EQ(spline.tStart(), traj.poses.front().t);
    EXPECT_DOUBLE_EQ(spline.tEnd(), traj.poses.back().t);

    // Independently of the stats: the camera pose T_world_body * T_body_cam0 against every input row.
    double sum_p2 = 0, sum_r2 = 0;
    for (const auto& tp : traj.poses)
    {
        const auto T_world_cam0 = spline.T_world_body(tp.t) + T_body_cam0;
        sum_p2 += std::pow(quasiloc::core::translationDistance(T_world_cam0, tp.pose), 2);
        sum_r2 += std::pow(quasiloc::core::rotationDistanceRad(T_world_cam0, tp.pose), 2);
    }
    const double rms_p = std::sqrt(sum_p2 / traj.poses.size()), rms_r = std::sqrt(sum_r2 / traj.poses.size());
    std::printf("[ residual ] cam0 position RMS %.3f mm, rotation RMS %.4f deg (all %zu rows)\n", rms_p * 1e3,
                rms_r * 180 / M_PI, traj.poses.size());
    EXPECT_LT(st.rms_position_m, 3e-3);
    EXPECT_LT(st.max_position_m, 2e-2);
    EXPECT_LT(st.rms_rotation_rad, 0.2 * M_PI / 180);
    EXPECT_LT(rms_p, 3e-3);
    EXPECT_LT(rms_r, 0.2 * M_PI / 180);
}

/** Every Vicon sequence: the SO(3) fit converges (the last control point of a sequence whose last sample
 *  falls just after a knot is nearly unobserved: regression test) and the fit is tight and smooth. */
TEST(TrajectorySpline, FitsAllViconSequences)
{
    const auto T_body_cam0 = quasiloc::core::readEurocSensorPose(kEuroc + "/calib/cam0_sensor.yaml");
    for (const char* seq :
         {"V1_01_easy", "V1_02_medium", "V1_03_difficult", "V2_01_easy", "V2_02_medium", "V2_03_difficult"})
    {
        const auto traj = quasiloc::core::readTum(kEuroc + "/groundtruth/cam0/" + seq + ".txt");
        const auto start = std::chrono::steady_clock::now();
        const auto spline = TrajectorySpline::fitCameraTrajectory(traj, T_body_cam0);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        double max_a = 0, max_w = 0;
        for (double t = spline.tStart(); t <= spline.tEnd(); t += 0.005)
        {
            const BodyState st = spline.evaluate(t);
            max_a = std::max(max_a, st.a_world.norm());
            max_w = std::max(max_w, st.omega_body.norm());
        }
        const auto& st = spline.fitStats();
        std::printf(
            "[ fit      ] %-16s %5.1f s, %4zu poses, %d iterations, %.3f s; position RMS %.3f mm "
            "(max %.2f), rotation RMS %.3f deg (max %.2f); max |a| %.1f m/s^2, |omega| %.2f rad/s\n",
            seq, spline.tEnd() - spline.tStart(), st.num_samples, st.rotation_iterations, secs, st.rms_position_m * 1e3,
            st.max_position_m * 1e3, st.rms_rotation_rad * 180 / M_PI, st.max_rotation_rad * 180 / M_PI, max_a, max_w);
        EXPECT_LT(st.rotation_iterations, 10) << seq;
        EXPECT_LT(st.rms_position_m, 1e-3) << seq;
        EXPECT_LT(st.max_position_m, 1e-2) << seq;
        EXPECT_LT(st.rms_rotation_rad, 0.1 * M_PI / 180) << seq;
        EXPECT_LT(max_a, 15.0) << seq;
        EXPECT_LT(max_w, 4.0) << seq;
    }
}

TEST(TrajectorySpline, ContinuousAcrossKnots)
{
    const TrajectorySpline& spline = v101Spline();
    const double eps = std::ldexp(1.0, -20);  // ~1 us, a multiple of the timestamps' resolution
    const int num_knots = static_cast<int>((spline.tEnd() - spline.tStart()) / spline.knotSpacing());
    // v and omega: the change across the knot must be the one their (continuous) derivatives predict;
    // a and alpha: only continuity (their derivatives, jerk and d(alpha)/dt, jump at knots by design).
    double max_jump_v = 0, max_jump_a = 0, max_jump_w = 0, max_jump_alpha = 0, max_a = 0, max_w = 0;
    for (int i = 1; i < num_knots; ++i)
    {
        const double tk = spline.tStart() + i * spline.knotSpacing();
        const BodyState lo = spline.evaluate(tk - eps), hi = spline.evaluate(tk + eps);
        max_jump_v = std::max(max_jump_v, (hi.v_world - lo.v_world - eps * (hi.a_world + lo.a_world)).norm());
        max_jump_w =
            std::max(max_jump_w, (hi.omega_body - lo.omega_body - eps * (hi.alpha_body + lo.alpha_body)).norm());
        max_jump_a = std::max(max_jump_a, (hi.a_world - lo.a_world).norm());
        max_jump_alpha = std::max(max_jump_alpha, (hi.alpha_body - lo.alpha_body).norm());
        max_a = std::max(max_a, hi.a_world.norm());
        max_w = std::max(max_w, hi.omega_body.norm());
    }
    std::printf(
        "[ smooth   ] over %d knots, across 2 us: v - a*dt %.2e m/s, omega - alpha*dt %.2e rad/s, "
        "change of a %.2e m/s^2, of alpha %.2e rad/s^2; max |a| %.2f m/s^2, max |omega| %.2f rad/s\n",
        num_knots - 1, max_jump_v, max_jump_w, max_jump_a, max_jump_alpha, max_a, max_w);
    EXPECT_LT(max_jump_v, 1e-9);
    EXPECT_LT(max_jump_w, 1e-9);
    // Over 2 us a C2 curve changes a by jerk * 2 us (jerk here < 100 m/s^3); a step would be ~0.1-1.
    EXPECT_LT(max_jump_a, 1e-3);
    EXPECT_LT(max_jump_alpha, 1e-2);
    // A MAV flown gently in a room: a fit that followed the Vicon jitter would show spikes here.
    EXPECT_LT(max_a, 10.0);
    EXPECT_LT(max_w, 5.0);
}

/** Central differences of the spline's own pose against its analytic derivatives, away from knots
 *  (where the jerk jumps and a second difference would straddle the kink). */
TEST(TrajectorySpline, AnalyticDerivativesMatchFiniteDifferences)
{
    const TrajectorySpline& spline = v101Spline();
    const double h = std::ldexp(1.0, -10);  // ~1 ms; t +- h is exact for these timestamps
    const int num_segments = static_cast<int>((spline.tEnd() - spline.tStart()) / spline.knotSpacing());
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> segment(0, num_segments - 1);
    std::uniform_real_distribution<double> within(0.05, 0.95);
    double err_v = 0, err_a = 0, err_w = 0, err_alpha = 0;
    for (int i = 0; i < 300; ++i)
    {
        const double t = spline.tStart() + (segment(rng) + within(rng)) * spline.knotSpacing();
        const BodyState s0 = spline.evaluate(t), sp = spline.evaluate(t + h), sm = spline.evaluate(t - h);
        const Eigen::Vector3d v_fd = (sp.p_world - sm.p_world) / (2 * h);
        const Eigen::Vector3d a_fd = (sp.p_world - 2 * s0.p_world + sm.p_world) / (h * h);
        const Eigen::Vector3d w_fd = rotationLog(sm.R_world_body.transpose() * sp.R_world_body) / (2 * h);
        const Eigen::Vector3d alpha_fd = (sp.omega_body - sm.omega_body) / (2 * h);
        err_v = std::max(err_v, (v_fd - s0.v_world).norm());
        err_a = std::max(err_a, (a_fd - s0.a_world).norm());
        err_w = std::max(err_w, (w_fd - s0.omega_body).norm());
        err_alpha = std::max(err_alpha, (alpha_fd - s0.alpha_body).norm());
        // The MRPT pose agrees with the unrounded rotation and position.
        ASSERT_LT((s0.T_world_body.getRotationMatrix().asEigen() - s0.R_world_body).norm(), 1e-9);
        ASSERT_LT((Eigen::Vector3d(s0.T_world_body.x(), s0.T_world_body.y(), s0.T_world_body.z()) - s0.p_world).norm(),
                  1e-12);
    }
    std::printf(
        "[ fd       ] max |analytic - central difference|: v %.2e m/s, a %.2e m/s^2, omega %.2e rad/s, "
        "alpha %.2e rad/s^2\n",
        err_v, err_a, err_w, err_alpha);
    EXPECT_LT(err_v, 1e-4);
    EXPECT_LT(err_a, 1e-4);
    EXPECT_LT(err_w, 1e-4);
    EXPECT_LT(err_alpha, 1e-2);
}

/** A known smooth motion (helix with a rocking attitude) sampled at 20 Hz: the fitted spline's derivatives
 *  must match the analytic ones, which pins the frames (body rate, world acceleration). */
TEST(TrajectorySpline, RecoversAnalyticMotion)
{
    const double w0 = 0.8, t_base = 1.4e9;  // large timestamps as in EuRoC
    auto position = [&](double s) { return Eigen::Vector3d(2 * std::cos(w0 * s), 2 * std::sin(w0 * s), 0.3 * s); };
    auto rotation = [&](double s) {
        return Eigen::Matrix3d(Eigen::AngleAxisd(w0 * s, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(0.3 * std::sin(1.1 * s), Eigen::Vector3d::UnitX()));
    };
    quasiloc::core::Trajectory traj;
    for (int i = 0; i <= 200; ++i)
    {
        const double s = i * 0.05;
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = rotation(s);
        T.translation() = position(s);
        traj.poses.push_back({t_base + s, quasiloc::core::fromIsometry(T)});
    }
    const auto spline = TrajectorySpline::fitBodyTrajectory(traj);
    double err_p = 0, err_v = 0, err_a = 0, err_w = 0;
    for (double s = 1.0; s <= 9.0; s += 0.0371)
    {
        const BodyState st = spline.evaluate(t_base + s);
        const double h = 1e-4;
        const Eigen::Vector3d v = (position(s + h) - position(s - h)) / (2 * h);
        const Eigen::Vector3d a = (position(s + h) - 2 * position(s) + position(s - h)) / (h * h);
        const Eigen::Vector3d w = rotationLog(rotation(s - h).transpose() * rotation(s + h)) / (2 * h);
        err_p = std::max(err_p, (st.p_world - position(s)).norm());
        err_v = std::max(err_v, (st.v_world - v).norm());
        err_a = std::max(err_a, (st.a_world - a).norm());
        err_w = std::max(err_w, (st.omega_body - w).norm());
    }
    std::printf("[ analytic ] max error vs true motion: p %.2e m, v %.2e m/s, a %.2e m/s^2, omega %.2e rad/s\n", err_p,
                err_v, err_a, err_w);
    EXPECT_LT(err_p, 1e-4);
    EXPECT_LT(err_v, 1e-3);
    EXPECT_LT(err_a, 2e-2);  // |a| = 1.28 m/s^2
    EXPECT_LT(err_w, 1e-2);  // |omega| ~ 0.9 rad/s
}

TEST(TrajectorySpline, DropsDuplicateTimestampsAndRejectsBadInput)
{
    quasiloc::core::Trajectory traj;
    for (int i = 0; i < 20; ++i)
        traj.poses.push_back({100.0 + 0.05 * i, mrpt::poses::CPose3D(0.1 * i, 0, 0, 0.02 * i, 0, 0)});
    // A leading run of one timestamp whose first row is an outlier (as in V1_02_medium): the last row is kept.
    quasiloc::core::Trajectory with_dups = traj;
    with_dups.poses.insert(with_dups.poses.begin(), 2, traj.poses.front());
    with_dups.poses.front().pose = mrpt::poses::CPose3D(0.5, 0.5, 0.5, 1, 0, 0);
    const auto a = TrajectorySpline::fitBodyTrajectory(traj), b = TrajectorySpline::fitBodyTrajectory(with_dups);
    EXPECT_EQ(b.fitStats().num_duplicates_dropped, 2u);
    EXPECT_EQ(b.fitStats().num_samples, 20u);
    for (double t = 100.0; t <= 100.95; t += 0.0137)
        EXPECT_LT((a.evaluate(t).p_world - b.evaluate(t).p_world).norm(), 1e-12);
    EXPECT_THROW(a.evaluate(99.9), std::out_of_range);
    EXPECT_THROW(a.evaluate(101.0), std::out_of_range);

    quasiloc::core::Trajectory three;  // 6 rows, 3 distinct timestamps
    for (int i = 0; i < 6; ++i) three.poses.push_back({1.0 + (i / 2), mrpt::poses::CPose3D()});
    EXPECT_THROW(TrajectorySpline::fitBodyTrajectory(three), quasiloc::core::InputError);

    quasiloc::core::Trajectory unsorted = traj;
    std::swap(unsorted.poses[4], unsorted.poses[5]);
    EXPECT_THROW(TrajectorySpline::fitBodyTrajectory(unsorted), quasiloc::core::InputError);

    quasiloc::sim::TrajectorySplineOptions bad;
    bad.knot_spacing_s = 0;
    EXPECT_THROW(TrajectorySpline::fitBodyTrajectory(traj, bad), quasiloc::core::InputError);
}

}  // namespace
