#pragma once
// Shared by the unit tests: numeric differentiation on the pose manifold and small scene helpers.
#include <Eigen/Core>
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

/** Relative difference of two matrices (max abs difference over max(1, max abs of the reference)). */
inline double relativeError(const Eigen::MatrixXd& A, const Eigen::MatrixXd& ref)
{
    return (A - ref).cwiseAbs().maxCoeff() / std::max(1.0, ref.cwiseAbs().maxCoeff());
}

}  // namespace quasiloc::estimation::test
