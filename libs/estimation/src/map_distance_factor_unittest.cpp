// MapDistanceCostFunction: analytic Jacobian against numeric differentiation on the pose manifold, and a solve
// with the factor alone that returns a corner-of-a-room view to its true pose.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <quasiloc/core/error.h>
#include <quasiloc/estimation/map_distance_factor.h>

#include "test_helpers.h"

using namespace quasiloc;
using namespace quasiloc::estimation;

namespace
{
/** A floor, two walls meeting in a corner and a box on the floor (2 cm spacing). */
map::LidarMap cornerMap()
{
    map::LidarMap m;
    const float s = 0.02f;
    for (float x = -1; x <= 3; x += s)
        for (float y = -1; y <= 3; y += s) m.addPoint(x, y, 0, 0.5f);
    for (float y = -1; y <= 3; y += s)
        for (float z = 0; z <= 2; z += s) m.addPoint(3, y, z, 0.5f);
    for (float x = -1; x <= 3; x += s)
        for (float z = 0; z <= 2; z += s) m.addPoint(x, 3, z, 0.5f);
    for (float x = 1.5f; x <= 2; x += s)
        for (float y = 0.5f; y <= 1; y += s) m.addPoint(x, y, 0.5f, 0.5f);
    return m;
}

struct Scene
{
    map::LidarMap map = cornerMap();
    map::DistanceField field;
    Eigen::Isometry3d T_map_body, T_body_cam;
    std::vector<Eigen::Vector3d> p_cam;
    std::vector<double> sigma;
    Scene()
    {
        map::DistanceFieldOptions o;
        o.voxel_m = 0.04;
        field = map::DistanceField::build(map, o);
        T_body_cam = test::makePose({0.01, -0.02, 0.03}, {0.05, -0.01, 0.0});
        Eigen::Matrix3d R;  // camera z -> world x, camera x -> world -y, camera y -> world -z, tilted down
        R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
        Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();
        T_map_cam.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R *
                             Eigen::AngleAxisd(-0.35, Eigen::Vector3d::UnitX()).toRotationMatrix();
        T_map_cam.translation() = Eigen::Vector3d(0.2, 0.4, 1.2);
        T_map_body = T_map_cam * T_body_cam.inverse();
        // Every 37th map point in front of the camera within 4 m, as stereo would see them.
        for (size_t i = 0; i < map.size(); i += 37)
        {
            const Eigen::Vector3d p = T_map_cam.inverse() * map.point(i).cast<double>();
            if (p.z() < 0.3 || p.z() > 4 || std::abs(p.x()) > p.z() || std::abs(p.y()) > 0.8 * p.z()) continue;
            p_cam.push_back(p);
            sigma.push_back(0.02);
        }
    }
};

Eigen::VectorXd evaluate(const ceres::CostFunction& f, const Eigen::Isometry3d& T, Eigen::MatrixXd* J6 = nullptr)
{
    double params[kPoseSize];
    poseToParams(T, params);
    const double* blocks[] = {params};
    Eigen::VectorXd r(f.num_residuals());
    Eigen::Matrix<double, Eigen::Dynamic, kPoseSize, Eigen::RowMajor> J7(f.num_residuals(), kPoseSize);
    double* jacobians[] = {J7.data()};
    f.Evaluate(blocks, r.data(), J6 ? jacobians : nullptr);
    if (J6) *J6 = J7.leftCols<6>();
    return r;
}
}  // namespace

TEST(MapDistanceFactor, JacobianMatchesNumericDifferences)
{
    const Scene s;
    ASSERT_GT(s.p_cam.size(), 200u);
    const MapDistanceCostFunction f(s.field, s.p_cam, s.sigma, s.T_body_cam, 0.15, 2.0);
    const Eigen::Isometry3d T = test::perturbedPose(s.T_map_body, 0.03, 1.0, 4);
    Eigen::MatrixXd J;
    evaluate(f, T, &J);
    // The field is sampled in float: steps of 1e-4 (a 1e-6 step is a few float ulps at metres). The trilinear
    // interpolant's derivative jumps across voxel faces, so a row whose point crosses one may differ: at most 3 %.
    const Eigen::MatrixXd numeric =
        test::numericPoseJacobian([&](const Eigen::Isometry3d& X) { return evaluate(f, X); }, T, 1e-4);
    int differing = 0, active = 0;
    for (int i = 0; i < J.rows(); ++i)
    {
        active += J.row(i).cwiseAbs().maxCoeff() > 0;
        differing += test::relativeError(J.row(i), numeric.row(i)) > 1e-2;
    }
    EXPECT_LE(differing, 0.03 * J.rows()) << differing << " of " << J.rows() << " rows differ";
    EXPECT_GT(active, J.rows() / 2);  // most points pull (not trivially zero)
}

TEST(MapDistanceFactor, AloneItReturnsACornerViewToItsPose)
{
    const Scene s;
    const Eigen::Isometry3d T_true = s.T_map_body;
    for (int seed = 1; seed <= 3; ++seed)
    {
        const Eigen::Isometry3d T0 = test::perturbedPose(T_true, 0.1, 3.0, seed);
        double params[kPoseSize];
        poseToParams(T0, params);
        ceres::Problem problem;
        problem.AddParameterBlock(params, kPoseSize, new PoseManifold);
        problem.AddResidualBlock(new MapDistanceCostFunction(s.field, s.p_cam, s.sigma, s.T_body_cam, 0.3, 2.0),
                                 nullptr, params);
        ceres::Solver::Options o;
        o.max_num_iterations = 50;
        ceres::Solver::Summary summary;
        ceres::Solve(o, &problem, &summary);
        const Eigen::Isometry3d T = paramsToPose(params);
        const double e_m = (T.translation() - T_true.translation()).norm();
        const double e_deg = logSO3(T.linear().transpose() * T_true.linear()).norm() * 180 / M_PI;
        EXPECT_LT(e_m, 0.01) << "seed " << seed;
        EXPECT_LT(e_deg, 0.2) << "seed " << seed;
    }
}

TEST(MapDistanceFactor, RejectsInconsistentInput)
{
    const Scene s;
    EXPECT_THROW(MapDistanceCostFunction(s.field, s.p_cam, {0.01}, s.T_body_cam, 0.15, 2.0), core::InputError);
    EXPECT_THROW(MapDistanceCostFunction(s.field, {}, {}, s.T_body_cam, 0.15, 2.0), core::InputError);
    std::vector<double> zero(s.p_cam.size(), 0.0);
    EXPECT_THROW(MapDistanceCostFunction(s.field, s.p_cam, zero, s.T_body_cam, 0.15, 2.0), core::InputError);
}
