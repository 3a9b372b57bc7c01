#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>

namespace quasiloc::core
{
Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& T)
{
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear() = T.getRotationMatrix().asEigen();
    out.translation() = Eigen::Vector3d(T.x(), T.y(), T.z());
    return out;
}

mrpt::poses::CPose3D fromIsometry(const Eigen::Isometry3d& T)
{
    mrpt::math::CMatrixDouble44 M;
    M.asEigen() = T.matrix();
    return mrpt::poses::CPose3D(M);
}

mrpt::poses::CPose3D fromTranslationQuaternion(const Eigen::Vector3d& t, const Eigen::Quaterniond& q_in)
{
    const Eigen::Quaterniond q = q_in.normalized();
    const mrpt::math::CQuaternionDouble mq(q.w(), q.x(), q.y(), q.z());
    return mrpt::poses::CPose3D(mrpt::poses::CPose3DQuat(t.x(), t.y(), t.z(), mq));
}

Eigen::Quaterniond quaternionOf(const mrpt::poses::CPose3D& T)
{
    Eigen::Quaterniond q(T.getRotationMatrix().asEigen());
    q.normalize();
    if (q.w() < 0) q.coeffs() *= -1;
    return q;
}

mrpt::poses::CPose3D fromMatrixRowMajor(const std::vector<double>& v, const std::string& input)
{
    require(v.size() == 12 || v.size() == 16, input,
            "a pose matrix needs 12 (3x4) or 16 (4x4) values, got " + std::to_string(v.size()));
    for (double x : v) require(std::isfinite(x), input, "pose matrix has a non-finite value");
    Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) M(r, c) = v[r * 4 + c];
    const Eigen::Matrix3d R = M.block<3, 3>(0, 0);
    const double ortho_err = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    require(ortho_err < 1e-4 && R.determinant() > 0, input,
            "rotation part is not a rotation (orthonormality error " + std::to_string(ortho_err) + ")");
    // Re-orthonormalise to double precision so that MRPT accepts it.
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
    T.translation() = M.block<3, 1>(0, 3);
    return fromIsometry(T);
}

double rotationDistanceRad(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
    const Eigen::Matrix3d dR = a.getRotationMatrix().asEigen().transpose() * b.getRotationMatrix().asEigen();
    return Eigen::AngleAxisd(dR).angle();
}

double translationDistance(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b)
{
    return (a.translation() - b.translation()).norm();
}

double rotationDistanceRad(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
    return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

double translationDistance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b)
{
    return (a.translation() - b.translation()).norm();
}

void checkFinite(const mrpt::poses::CPose3D& T, const std::string& input)
{
    const auto M = T.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) require(std::isfinite(M(r, c)), input, "pose has a non-finite (NaN/inf) element");
}

}  // namespace quasiloc::core
