#pragma once
// Robust absolute pose (PnP) in the COLMAP/PoseLib style: OpenCV's USAC (MAGSAC++ by default) on undistorted
// normalised coordinates (so any core::CameraModel works, equidistant included), then Levenberg-Marquardt
// refinement of the reprojection error on the inliers (Ceres, PointReprojectionFactor, Huber), then the
// inlier mask recomputed at the refined pose.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <quasiloc/core/camera_model.h>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::estimation
{
enum class PnpMethod
{
    Magsac,       ///< OpenCV USAC with MAGSAC++
    UsacDefault,  ///< OpenCV USAC_DEFAULT
    Ransac        ///< classic OpenCV RANSAC + EPnP
};
/** The INI names of the methods: magsac, usac_default, ransac. */
const std::vector<std::pair<std::string, PnpMethod>>& pnpMethodNames();

struct AbsolutePoseOptions
{
    PnpMethod method = PnpMethod::Magsac;
    double max_reproj_error_px = 2.0;
    double confidence = 0.999;
    int max_iterations = 2000;
    int min_inliers = 6;
    bool refine = true;
    int refine_iterations = 20;
    /** InputError naming `input` and the field for a value that cannot be used. */
    void check(const std::string& input) const;
};

struct AbsolutePoseStats
{
    int num_inliers = 0;
    /** RANSAC iterations needed for `confidence` at the final inlier ratio with 4-point samples (OpenCV
     *  does not report the iterations it ran; this is the adaptive stopping bound it applies). */
    int iterations = 0;
    double inlier_ratio = 0;
    double refinement_initial_cost = 0, refinement_final_cost = 0;
    double mean_inlier_error_px = 0;
    std::vector<char> inlier_mask;
};

/** True when a pose with at least options.min_inliers inliers was found. InputError when the inputs differ
 *  in size or hold non-finite values. */
bool estimateAbsolutePose(const AbsolutePoseOptions& options, const std::vector<Eigen::Vector2d>& points2D,
                          const std::vector<Eigen::Vector3d>& points3D, const core::CameraModel& camera,
                          Eigen::Isometry3d* T_cam_world, AbsolutePoseStats* stats);

}  // namespace quasiloc::estimation
