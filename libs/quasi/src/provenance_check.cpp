#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/quasi/provenance_check.h>

namespace quasiloc::quasi
{
namespace
{
bool reproject(const map::LidarMap& map, const QuasiImage& q, int32_t idx, Eigen::Vector2d& px)
{
    double x, y, z;
    const Eigen::Vector3f p = map.point(size_t(idx));
    q.T_world_cam.inverseComposePoint(p.x(), p.y(), p.z(), x, y, z);
    return q.camera.project({x, y, z}, px);
}

cv::Mat toBgr(const cv::Mat& image)
{
    cv::Mat bgr;
    if (image.channels() == 1)
        cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
    else
        bgr = image.clone();
    return bgr;
}
}  // namespace

ProvenanceCheck checkProvenance(const map::LidarMap& map, const QuasiImage& q)
{
    ProvenanceCheck c;
    c.error_px.create(q.provenance.size(), CV_32FC1);
    c.error_px.setTo(std::nanf(""));
    for (int y = 0; y < q.provenance.rows; ++y)
        for (int x = 0; x < q.provenance.cols; ++x)
        {
            const int32_t idx = q.provenance.at<int32_t>(y, x);
            if (idx < 0) continue;
            core::require(size_t(idx) < map.size(), "quasi-image provenance",
                          "index " + std::to_string(idx) + " outside the map (" + std::to_string(map.size()) + ")");
            Eigen::Vector2d px;
            if (!reproject(map, q, idx, px)) continue;  // behind the camera: error stays NaN
            const double e = std::max(std::abs(px.x() - x), std::abs(px.y() - y));
            c.error_px.at<float>(y, x) = float(e);
            if (q.sparse.at<uint8_t>(y, x))
            {
                ++c.sparse_pixels;
                c.max_sparse_px = std::max(c.max_sparse_px, e);
                c.mean_sparse_px += e;
            }
            else
            {
                ++c.completed_pixels;
                c.max_completed_px = std::max(c.max_completed_px, e);
                c.mean_completed_px += e;
            }
        }
    if (c.sparse_pixels) c.mean_sparse_px /= double(c.sparse_pixels);
    if (c.completed_pixels) c.mean_completed_px /= double(c.completed_pixels);
    return c;
}

cv::Mat drawProvenanceOverlay(const cv::Mat& camera_image, const map::LidarMap& map, const QuasiImage& q,
                              int completion_radius_px, int step_px)
{
    cv::Mat out = toBgr(camera_image);
    const int step = std::max(1, step_px);
    for (int y = step / 2; y < q.provenance.rows; y += step)
        for (int x = step / 2; x < q.provenance.cols; x += step)
        {
            const int32_t idx = q.provenance.at<int32_t>(y, x);
            Eigen::Vector2d px;
            if (idx < 0 || !reproject(map, q, idx, px)) continue;
            const double e = std::max(std::abs(px.x() - x), std::abs(px.y() - y));
            const cv::Scalar colour = e <= 0.5 + 1e-3                          ? cv::Scalar(0, 255, 0)
                                      : e <= completion_radius_px + 0.5 + 1e-3 ? cv::Scalar(0, 255, 255)
                                                                               : cv::Scalar(0, 0, 255);
            cv::circle(out, cv::Point(int(std::lround(px.x())), int(std::lround(px.y()))), 1, colour, cv::FILLED);
        }
    return out;
}

cv::Mat makeTriple(const cv::Mat& camera_image, const QuasiImage& q, const cv::Mat& overlay)
{
    cv::Mat out;
    cv::hconcat(std::vector<cv::Mat>{toBgr(camera_image), q.bgr, toBgr(overlay)}, out);
    return out;
}

}  // namespace quasiloc::quasi
