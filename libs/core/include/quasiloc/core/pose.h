#pragma once
// Pose helpers over mrpt::poses::CPose3D. Names carry frames: T_a_b maps b-coordinates to a-coordinates
// (the pose of frame b in frame a), so T_a_c = T_a_b * T_b_c, written (T_a_b + T_b_c) with MRPT poses.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>
#include <string>

namespace quasiloc::core
{
Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& T);
mrpt::poses::CPose3D fromIsometry(const Eigen::Isometry3d& T);

/** From translation and unit quaternion (w, x, y, z); the quaternion is normalised. */
mrpt::poses::CPose3D fromTranslationQuaternion(const Eigen::Vector3d& t, const Eigen::Quaterniond& q);
/** Quaternion of the rotation of T, with w >= 0. */
Eigen::Quaterniond quaternionOf(const mrpt::poses::CPose3D& T);

/** Row-major 4x4 (16 values) or 3x4 (12 values) -> pose; throws InputError naming `input` if the
 *  rotation is not orthonormal to 1e-4 or a value is not finite. */
mrpt::poses::CPose3D fromMatrixRowMajor(const std::vector<double>& values, const std::string& input);

/** Angle of the rotation between two poses, in radians, and translation distance in metres. */
double rotationDistanceRad(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);
double translationDistance(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);
double rotationDistanceRad(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);
double translationDistance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

/** Throws InputError when any element of the pose is not finite. */
void checkFinite(const mrpt::poses::CPose3D& T, const std::string& input);

}  // namespace quasiloc::core
