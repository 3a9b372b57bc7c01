#include "structure_matching.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace quasiloc::reloc
{
namespace
{
constexpr float kNone = std::numeric_limits<float>::max();

struct WindowBest
{
    cv::Point at;
    float best = kNone, second = kNone;  ///< squared descriptor distances
};

/** The window's distances on a grid of `step` px (a cost image), its minimum, the minimum outside max(3, 2 step)
 *  px of it, then the minimum refined at step 1 around the coarse one. */
WindowBest searchWindow(const frontend::DescriptorField& field, const cv::Point& centre, int radius,
                        const float* map_desc, std::vector<float>& buf)
{
    const int step = std::max(1, int(std::lround(radius / 16.0))), half = radius / step, n = field.dims();
    cv::Mat cost(2 * half + 1, 2 * half + 1, CV_32F, cv::Scalar(kNone));
    for (int j = 0; j < cost.rows; ++j)
        for (int i = 0; i < cost.cols; ++i)
        {
            const cv::Point p = centre + cv::Point((i - half) * step, (j - half) * step);
            if (field.describe(p.x, p.y, buf.data()))
                cost.at<float>(j, i) = frontend::squaredDistance(buf.data(), map_desc, n);
        }
    WindowBest w;
    double lo = 0;
    cv::Point at;
    cv::minMaxLoc(cost, &lo, nullptr, &at);
    if (lo >= kNone) return w;
    w.best = float(lo);
    w.at = centre + cv::Point((at.x - half) * step, (at.y - half) * step);
    const int excluded = std::max(3, 2 * step) / step;
    cv::Mat rest = cost.clone();
    rest(cv::Rect(cv::Point(std::max(0, at.x - excluded), std::max(0, at.y - excluded)),
                  cv::Point(std::min(cost.cols, at.x + excluded + 1), std::min(cost.rows, at.y + excluded + 1))))
        .setTo(kNone);
    cv::minMaxLoc(rest, &lo);
    w.second = float(lo);
    const cv::Point coarse = w.at;
    for (int dy = 1 - step; dy < step; ++dy)
        for (int dx = 1 - step; dx < step; ++dx)
        {
            const cv::Point p = coarse + cv::Point(dx, dy);
            if (!field.describe(p.x, p.y, buf.data())) continue;
            const float d = frontend::squaredDistance(buf.data(), map_desc, n);
            if (d < w.best) w.best = d, w.at = p;
        }
    return w;
}
}  // namespace

std::vector<cv::Mat> structureChannels(const quasi::QuasiImage& q, const StructureLocalizerOptions& o)
{
    return {
        frontend::fillInvalid(frontend::rankEqualised(q.reflectivity, q.valid, q.depth, o.depth_bands), q.valid,
                              o.fill_sigma_px),
        frontend::fillInvalid(frontend::depthEdgeChannel(q.depth, q.valid, o.depth_edge_sigma_px, o.depth_edge_scale),
                              q.valid, o.fill_sigma_px)};
}

GuessCorrespondences matchAtGuess(const frontend::DescriptorField& camera_field, const quasi::QuasiImage& q,
                                  const map::LidarMap& map, const core::CameraModel& camera, double sigma_m,
                                  double sigma_rad, const StructureLocalizerOptions& o)
{
    GuessCorrespondences out;
    if (q.reflectivity.empty() || camera_field.channels.empty()) return out;
    const double f = 0.5 * (camera.fx + camera.fy);
    const std::vector<cv::Mat> channels = structureChannels(q, o);
    for (const cv::Mat& channel : channels)
    {
        const frontend::DescriptorField map_field =
            frontend::computeDescriptorField(channel, frontend::DescriptorKind::OrientationField, {});
        const int margin = map_field.radius() + 2;
        if (q.valid.cols <= 2 * margin || q.valid.rows <= 2 * margin) continue;
        std::vector<cv::Point2f> corners;
        cv::goodFeaturesToTrack(channel, corners, std::max(1, o.keypoints / int(channels.size())), 0.01,
                                o.min_keypoint_distance_px, quasi::keypointSupportMask(q, margin, o.min_valid_share),
                                5);
        std::vector<float> map_desc(size_t(map_field.dims())), buf(size_t(map_field.dims()));
        for (const cv::Point2f& c : corners)
        {
            const cv::Point px(int(std::lround(c.x)), int(std::lround(c.y)));
            const int idx = q.provenance.at<int32_t>(px);
            const float depth = q.depth.at<float>(px);
            if (idx < 0 || size_t(idx) >= map.size() || depth <= 0) continue;
            if (!map_field.describe(px.x, px.y, map_desc.data())) continue;
            ++out.keypoints;
            const int r =
                int(std::ceil(std::min(o.window_max_px, o.window_base_px + f * (sigma_rad + sigma_m / depth))));
            const WindowBest w = searchWindow(camera_field, px, r, map_desc.data(), buf);
            if (w.second >= kNone || std::sqrt(w.best / w.second) >= o.ratio) continue;
            out.camera_px.emplace_back(w.at.x, w.at.y);
            out.p_world.push_back(map.point(size_t(idx)).cast<double>());
            out.guess_px.emplace_back(px.x, px.y);
        }
    }
    return out;
}

GuessCorrespondences consensusOfDisplacements(const GuessCorrespondences& m,
                                              const std::vector<Eigen::Vector2d>& at_guess, double radius_px)
{
    if (radius_px <= 0 || m.camera_px.empty()) return m;
    const size_t n = m.camera_px.size();
    size_t best = 0;
    int best_count = -1;
    for (size_t i = 0; i < n; ++i)
    {
        const Eigen::Vector2d di = m.camera_px[i] - at_guess[i];
        int count = 0;
        for (size_t j = 0; j < n; ++j) count += (m.camera_px[j] - at_guess[j] - di).norm() <= radius_px;
        if (count > best_count) best_count = count, best = i;
    }
    const Eigen::Vector2d mode = m.camera_px[best] - at_guess[best];
    GuessCorrespondences out;
    out.keypoints = m.keypoints;
    for (size_t j = 0; j < n; ++j)
        if ((m.camera_px[j] - at_guess[j] - mode).norm() <= radius_px)
        {
            out.camera_px.push_back(m.camera_px[j]);
            out.p_world.push_back(m.p_world[j]);
            out.guess_px.push_back(at_guess[j]);
        }
    return out;
}

}  // namespace quasiloc::reloc
