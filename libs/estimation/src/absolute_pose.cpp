#include <ceres/ceres.h>

#include <Eigen/Core>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/absolute_pose.h>
#include <quasiloc/estimation/visual_factors.h>

namespace quasiloc::estimation
{
const std::vector<std::pair<std::string, PnpMethod>>& pnpMethodNames()
{
    static const std::vector<std::pair<std::string, PnpMethod>> names = {
        {"magsac", PnpMethod::Magsac}, {"usac_default", PnpMethod::UsacDefault}, {"ransac", PnpMethod::Ransac}};
    return names;
}

void AbsolutePoseOptions::check(const std::string& input) const
{
    core::require(max_reproj_error_px > 0, input + ": max_reproj_error_px", "must be > 0");
    core::require(confidence > 0 && confidence < 1, input + ": confidence", "must be in (0, 1)");
    core::require(max_iterations >= 1, input + ": max_iterations", "must be >= 1");
    core::require(min_inliers >= 4, input + ": min_inliers", "must be >= 4");
    core::require(refine_iterations >= 1, input + ": refine_iterations", "must be >= 1");
}

namespace
{
double reprojectionError(const core::CameraModel& cam, const Eigen::Isometry3d& T_cam_world, const Eigen::Vector3d& X,
                         const Eigen::Vector2d& u)
{
    Eigen::Vector2d px;
    if (!cam.project(T_cam_world * X, px, nullptr, 1e-6)) return 1e300;
    return (px - u).norm();
}

int ransacIterationBound(double inlier_ratio, double confidence, int max_iterations)
{
    const double w4 = std::pow(inlier_ratio, 4);
    if (w4 >= 1.0 - 1e-12) return 1;
    if (w4 <= 1e-12) return max_iterations;
    return std::min(max_iterations, static_cast<int>(std::ceil(std::log(1 - confidence) / std::log(1 - w4))));
}
}  // namespace

bool estimateAbsolutePose(const AbsolutePoseOptions& options, const std::vector<Eigen::Vector2d>& points2D,
                          const std::vector<Eigen::Vector3d>& points3D, const core::CameraModel& camera,
                          Eigen::Isometry3d* T_cam_world, AbsolutePoseStats* stats)
{
    options.check("AbsolutePoseOptions");
    core::require(points2D.size() == points3D.size(), "estimateAbsolutePose", "points2D and points3D differ in size");
    AbsolutePoseStats local;
    AbsolutePoseStats& st = stats ? *stats : local;
    st = AbsolutePoseStats{};
    st.inlier_mask.assign(points2D.size(), 0);
    const size_t n = points2D.size();
    if (n < 4 || static_cast<int>(n) < options.min_inliers) return false;

    // Undistorted pixels of the ideal pinhole K (same fx, fy, cx, cy): any distortion model works, and the
    // threshold stays in pixels (MAGSAC++ misbehaves on normalised coordinates with a tiny threshold).
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> img;
    for (size_t i = 0; i < n; ++i)
    {
        core::require(points2D[i].allFinite() && points3D[i].allFinite(), "estimateAbsolutePose",
                      "correspondence " + std::to_string(i) + " is not finite");
        const Eigen::Vector3d xn = camera.unproject(points2D[i]);
        img.emplace_back(static_cast<float>(camera.fx * xn.x() + camera.cx),
                         static_cast<float>(camera.fy * xn.y() + camera.cy));
        obj.emplace_back(static_cast<float>(points3D[i].x()), static_cast<float>(points3D[i].y()),
                         static_cast<float>(points3D[i].z()));
    }
    int flags = static_cast<int>(cv::SOLVEPNP_EPNP);  // classic RANSAC with EPnP minimal solutions
    if (options.method == PnpMethod::Magsac) flags = static_cast<int>(cv::USAC_MAGSAC);
    if (options.method == PnpMethod::UsacDefault) flags = static_cast<int>(cv::USAC_DEFAULT);
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    const cv::Mat K = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    const double thr = options.max_reproj_error_px;
    bool ok = false;
    try
    {
        ok = cv::solvePnPRansac(obj, img, K, cv::noArray(), rvec, tvec, false, options.max_iterations,
                                static_cast<float>(thr), options.confidence, inliers, flags);
    }
    catch (const cv::Exception&)
    {
        ok = false;  // degenerate samples only (e.g. all points collinear): no pose
    }
    if (!ok || static_cast<int>(inliers.size()) < options.min_inliers) return false;

    cv::Mat Rcv;
    cv::Rodrigues(rvec, Rcv);
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    cv::cv2eigen(Rcv, R);
    cv::cv2eigen(tvec, t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = t;

    if (options.refine)
    {
        CameraGeometry geom;
        geom.model = camera;
        double params[kPoseSize];
        poseToParams(T.inverse(), params);  // the state is T_world_cam (body = camera)
        ceres::Problem problem;
        PoseManifold* manifold = new PoseManifold;
        for (int i : inliers)
            problem.AddResidualBlock(new PointReprojectionFactor(geom, points2D[i], points3D[i], 1.0),
                                     new ceres::HuberLoss(options.max_reproj_error_px), params);
        problem.SetManifold(params, manifold);
        ceres::Solver::Options so;
        so.max_num_iterations = options.refine_iterations;
        so.linear_solver_type = ceres::DENSE_QR;
        so.logging_type = ceres::SILENT;
        ceres::Solver::Summary summary;
        ceres::Solve(so, &problem, &summary);
        st.refinement_initial_cost = summary.initial_cost;
        st.refinement_final_cost = summary.final_cost;
        if (summary.IsSolutionUsable()) T = paramsToPose(params).inverse();
    }

    double err_sum = 0;
    for (size_t i = 0; i < n; ++i)
    {
        const double e = reprojectionError(camera, T, points3D[i], points2D[i]);
        if (e <= options.max_reproj_error_px)
        {
            st.inlier_mask[i] = 1;
            ++st.num_inliers;
            err_sum += e;
        }
    }
    st.inlier_ratio = static_cast<double>(st.num_inliers) / n;
    st.mean_inlier_error_px = st.num_inliers ? err_sum / st.num_inliers : 0;
    st.iterations = ransacIterationBound(st.inlier_ratio, options.confidence, options.max_iterations);
    if (T_cam_world) *T_cam_world = T;
    return st.num_inliers >= options.min_inliers;
}

}  // namespace quasiloc::estimation
