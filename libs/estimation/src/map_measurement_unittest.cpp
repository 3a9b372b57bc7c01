// The map alignment as a pose measurement: observability-shaped information and its move to the body frame.
#include <gtest/gtest.h>

#include <quasiloc/estimation/map_measurement.h>

using namespace quasiloc::estimation;

TEST(MapMeasurement, IsotropicHessianGivesTheFixedInformation)
{
    const double sr = 0.2 * M_PI / 180, sm = 0.01;
    Vector6d h;
    h << Eigen::Vector3d::Constant(1 / (sr * sr)), Eigen::Vector3d::Constant(1 / (sm * sm));
    const Matrix6d I = observabilityMapInformation(7.0 * Matrix6d(h.asDiagonal()), sr, sm);
    EXPECT_LT((I - fixedMapInformation(sr, sm)).norm() / fixedMapInformation(sr, sm).norm(), 1e-9);
    EXPECT_EQ(observabilityMapInformation(Matrix6d::Zero(), sr, sm), fixedMapInformation(sr, sm));
}

TEST(MapMeasurement, UnobservedDirectionGetsNoInformation)
{
    // Edges that see everything but translation along a direction n (a wall seen head-on: sliding along it).
    const double sr = 0.2 * M_PI / 180, sm = 0.01;
    const Eigen::Vector3d n = Eigen::Vector3d(1, 0.5, 0).normalized();
    Matrix6d H = Matrix6d::Zero();
    H.topLeftCorner<3, 3>() = Eigen::Matrix3d::Identity() * 50.0 / (sr * sr);
    H.bottomRightCorner<3, 3>() = (Eigen::Matrix3d::Identity() - n * n.transpose()) * 50.0 / (sm * sm);
    const Matrix6d I = observabilityMapInformation(H, sr, sm);
    Vector6d slide = Vector6d::Zero();
    slide.tail<3>() = n;
    EXPECT_NEAR(slide.dot(I * slide), 0.0, 1e-6 / (sm * sm));
    Vector6d up = Vector6d::Zero();
    up.tail<3>() = n.cross(Eigen::Vector3d::UnitZ()).normalized();
    EXPECT_NEAR(up.dot(I * up), 1 / (sm * sm), 1e-6 / (sm * sm));
    // A direction observed 4x less (in sigma units) gets 4x less information.
    H(0, 0) /= 4;
    const Matrix6d I4 = observabilityMapInformation(H, sr, sm);
    EXPECT_NEAR(I4(0, 0) * sr * sr, 0.25, 1e-9);
}

TEST(MapMeasurement, BodyInformationMatchesTheCameraOneThroughTheExtrinsic)
{
    // The cost of a body-frame perturbation under I_body equals that of the camera-frame perturbation it causes
    // under I_cam (checked through boxPlus, small step).
    Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
    T_body_cam.linear() = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -1, 0.4).normalized()).toRotationMatrix();
    T_body_cam.translation() = Eigen::Vector3d(0.06, -0.02, 0.1);
    Eigen::Isometry3d T_map_body = Eigen::Isometry3d::Identity();
    T_map_body.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    T_map_body.translation() = Eigen::Vector3d(1, -2, 0.5);
    Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Random();
    const Matrix6d I_cam = M * M.transpose() + Matrix6d::Identity();
    const Matrix6d I_body = cameraToBodyInformation(I_cam, T_body_cam);
    for (int k = 0; k < 6; ++k)
    {
        Vector6d db = Vector6d::Zero();
        db[k] = 1e-6;
        const Eigen::Isometry3d T_map_cam = T_map_body * T_body_cam;
        const Vector6d dc = boxMinus(boxPlus(T_map_body, db) * T_body_cam, T_map_cam);
        EXPECT_NEAR(dc.dot(I_cam * dc), db.dot(I_body * db), 1e-6 * db.dot(I_body * db)) << "direction " << k;
    }
}

TEST(MapMeasurement, DirectionsObservedAsWellAsTheMedianKeepTheConfiguredSigma)
{
    // One direction observed far better than the rest must not deweight the rest (they are observed as well as
    // the median direction).
    const double sr = 0.2 * M_PI / 180, sm = 0.01;
    Vector6d h;
    h << 1000 / (sr * sr), 50 / (sr * sr), 50 / (sr * sr), 50 / (sm * sm), 50 / (sm * sm), 60 / (sm * sm);
    const Matrix6d I = observabilityMapInformation(Matrix6d(h.asDiagonal()), sr, sm);
    EXPECT_LT((I - fixedMapInformation(sr, sm)).norm() / fixedMapInformation(sr, sm).norm(), 1e-9);
}
