#pragma once
// Least-squares similarity between two point sets (Umeyama, IEEE PAMI 1991): the (s, R, t) minimising
// sum_i || dst_i - (s R src_i + t) ||^2, with s fixed to 1 for a rigid (SE(3)) alignment.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace quasiloc::eval
{
/** x -> scale * R * x + t. Used as T_gtworld_estworld: maps estimate-world points into the ground-truth world. */
struct Similarity3
{
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    double scale = 1.0;
    /** True when the points do not fix the rotation (fewer than 3 points or all collinear): the returned
     *  transform is one of many minimisers. */
    bool degenerate = false;

    Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (R * p) + t; }
    Eigen::Matrix4d matrix() const;
};

/** src and dst have the same number of columns (InputError otherwise, or when empty or not finite). */
Similarity3 umeyamaAlignment(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, bool with_scale);

}  // namespace quasiloc::eval
