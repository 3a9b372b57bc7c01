#include <limits>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/sim/inspection.h>

namespace quasiloc::sim
{
cv::Mat projectReflectivity(const map::LidarMap& map, const core::CameraModel& cam,
                            const mrpt::poses::CPose3D& T_world_cam, double max_depth_m)
{
    const Eigen::Isometry3d T_cam_world = core::toIsometry(T_world_cam).inverse();
    cv::Mat depth(cam.height, cam.width, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
    cv::Mat out = cv::Mat::zeros(cam.height, cam.width, CV_8U);
    for (size_t i = 0; i < map.size(); ++i)
    {
        const Eigen::Vector3d p = T_cam_world * map.point(i).cast<double>();
        if (p.z() < 0.05 || p.z() > max_depth_m) continue;
        Eigen::Vector2d px;
        if (!cam.project(p, px) || !cam.isInImage(px)) continue;
        const int u0 = static_cast<int>(std::floor(px.x())), v0 = static_cast<int>(std::floor(px.y()));
        for (int v = v0; v <= v0 + 1; ++v)
            for (int u = u0; u <= u0 + 1; ++u)
            {
                if (u < 0 || v < 0 || u >= cam.width || v >= cam.height) continue;
                float& d = depth.at<float>(v, u);
                if (p.z() >= d) continue;
                d = static_cast<float>(p.z());
                out.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(255.0 * map.reflectivity(i));
            }
    }
    // Fill pixels between projected points (map spacing is coarser than a pixel far away): empty pixels take
    // the maximum of their 3x3 neighbourhood, twice. Display only.
    for (int pass = 0; pass < 2; ++pass)
    {
        cv::Mat grown;
        cv::dilate(out, grown, cv::Mat());
        grown.copyTo(out, out == 0);
    }
    return out;
}

cv::Mat makeInspectionImage(const cv::Mat& camera_gray, const cv::Mat& reflectivity_gray)
{
    cv::Mat cam_bgr, refl_bgr, overlay;
    cv::cvtColor(camera_gray, cam_bgr, cv::COLOR_GRAY2BGR);
    cv::cvtColor(reflectivity_gray, refl_bgr, cv::COLOR_GRAY2BGR);
    cv::Mat edges;
    cv::Mat smooth;
    cv::GaussianBlur(camera_gray, smooth, cv::Size(0, 0), 1.5);  // sensor noise would light up every pixel
    cv::Canny(smooth, edges, 30, 80);
    overlay = refl_bgr.clone();
    overlay.setTo(cv::Scalar(0, 255, 0), edges);
    cv::Mat out;
    cv::hconcat(std::vector<cv::Mat>{cam_bgr, refl_bgr, overlay}, out);
    const auto label = [&](const std::string& text, int panel) {
        cv::putText(out, text, {panel * camera_gray.cols + 10, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.7,
                    cv::Scalar(0, 0, 255), 2);
    };
    label("camera (left, raw)", 0);
    label("LiDAR map reflectivity, same pose", 1);
    label("camera edges on reflectivity", 2);
    return out;
}

}  // namespace quasiloc::sim
