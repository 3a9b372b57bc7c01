#pragma once
// Shared by the unit tests: numeric differentiation on the pose manifold and small scene helpers.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <quasiloc/estimation/pose_parametrization.h>
#include <quasiloc/estimation/visual_factors.h>
#include <random>

namespace quasiloc::estimation::test
{
/** Central differences of f(T (+) delta) with respect to delta (6 columns). */
inline Eigen::MatrixXd numericPoseJacobian(const std::function<Eigen::VectorXd(const Eigen::Isometry3d&)>& f,
                                           const Eigen::Isometry3d& T, double h = 1e-6)
{
    const Eigen::VectorXd f0 = f(T);
    Eigen::MatrixXd J(f0.size(), 6);
    for (int k = 0; k < 6; ++k)
    {
        Vector6d d = Vector6d::Zero();
        d[k] = h;
        J.col(k) = (f(boxPlus(T, d)) - f(boxPlus(T, -d))) / (2 * h);
    }
    return J;
}

/** Central differences of a function of a vector. */
inline Eigen::MatrixXd numericJacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                       const Eigen::VectorXd& x, double h = 1e-6)
{
    const Eigen::VectorXd f0 = f(x);
    Eigen::MatrixXd J(f0.size(), x.size());
    for (int k = 0; k < x.size(); ++k)
    {
        Eigen::VectorXd xp = x, xm = x;
        xp[k] += h;
        xm[k] -= h;
        J.col(k) = (f(xp) - f(xm)) / (2 * h);
    }
    return J;
}

inline Eigen::Isometry3d makePose(const Eigen::Vector3d& rotvec, const Eigen::Vector3d& t)
{
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = expSO3(rotvec);
    T.translation() = t;
    return T;
}

/** A 640x480 pinhole camera, f = 400, with the body frame at the camera unless given. */
inline CameraGeometry pinholeCamera(const Eigen::Isometry3d& T_body_cam = Eigen::Isometry3d::Identity())
{
    CameraGeometry cam;
    cam.model = core::CameraModel::pinhole(640, 480, 400, 400, 320, 240);
    cam.T_body_cam = T_body_cam;
    return cam;
}

/** The test view of quasi::makeSyntheticRoom: inside the room looking along +x, tilted down a little, towards a
 *  corner with boxes (T_world_cam). */
inline Eigen::Isometry3d syntheticRoomCameraPose()
{
    Eigen::Matrix3d R;
    R << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // camera z -> world x, camera x -> world -y, camera y -> world -z
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R *
                 Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitX()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(-2.0, -0.5, 1.4);
    return T;
}

/** T (+) delta with a rotation of exactly rot_deg and a translation of exactly t_m along directions fixed by seed. */
inline Eigen::Isometry3d perturbedPose(const Eigen::Isometry3d& T, double t_m, double rot_deg, int seed)
{
    const Eigen::Vector3d a = Eigen::Vector3d(std::sin(seed), std::cos(3 * seed), std::sin(5 * seed + 1)).normalized();
    const Eigen::Vector3d b = Eigen::Vector3d(std::cos(2 * seed), std::sin(7 * seed), std::cos(seed + 2)).normalized();
    Vector6d d;
    d << a * rot_deg * M_PI / 180, b * t_m;
    return boxPlus(T, d);
}

/** Relative difference of two matrices (max abs difference over max(1, max abs of the reference)). */
inline double relativeError(const Eigen::MatrixXd& A, const Eigen::MatrixXd& ref)
{
    return (A - ref).cwiseAbs().maxCoeff() / std::max(1.0, ref.cwiseAbs().maxCoeff());
}

}  // namespace quasiloc::estimation::test
