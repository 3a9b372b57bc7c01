#include <Eigen/SVD>
#include <algorithm>
#include <quasiloc/core/error.h>
#include <quasiloc/eval/umeyama.h>

namespace quasiloc::eval
{
Eigen::Matrix4d Similarity3::matrix() const
{
    Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
    M.block<3, 3>(0, 0) = scale * R;
    M.block<3, 1>(0, 3) = t;
    return M;
}

Similarity3 umeyamaAlignment(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, bool with_scale)
{
    core::require(src.cols() == dst.cols(), "Umeyama alignment", "point sets differ in size");
    core::require(src.cols() > 0, "Umeyama alignment", "no points");
    core::require(src.allFinite() && dst.allFinite(), "Umeyama alignment", "non-finite point");
    const double n = static_cast<double>(src.cols());
    const Eigen::Vector3d mu_src = src.rowwise().mean(), mu_dst = dst.rowwise().mean();
    const Eigen::Matrix3Xd src_c = src.colwise() - mu_src, dst_c = dst.colwise() - mu_dst;
    const double var_src = src_c.squaredNorm() / n;
    const Eigen::Matrix3d Sigma = dst_c * src_c.transpose() / n;

    Eigen::JacobiSVD<Eigen::Matrix3d> svd(Sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
    // S flips the last axis when U V^T would be a reflection (det = -1), so that R is a proper rotation.
    Eigen::Vector3d S = Eigen::Vector3d::Ones();
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2) = -1;

    Similarity3 out;
    out.R = svd.matrixU() * S.asDiagonal() * svd.matrixV().transpose();
    const Eigen::Vector3d sv = svd.singularValues();
    // Rank < 2 of the cross-covariance: points collinear (or a single point), rotation about the line free.
    out.degenerate = src.cols() < 3 || sv(1) <= 1e-12 * std::max(1.0, sv(0));
    if (with_scale)
    {
        core::require(var_src > 0, "Umeyama alignment (Sim(3))", "all source points coincide: scale undefined");
        out.scale = sv.dot(S) / var_src;
    }
    out.t = mu_dst - out.scale * out.R * mu_src;
    return out;
}

}  // namespace quasiloc::eval
