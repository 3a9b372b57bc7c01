// Map points associated across the modality gap by the orientation field (crossmodal_points.h).
#include <quasiloc/tracking/crossmodal_points.h>
#include <quasiloc/tracking/map_points.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

namespace quasiloc::tracking
{
namespace
{
constexpr int kMinSeparationPx = 3;  ///< the second best and the candidates lie at least this far apart

struct MapKeypoint
{
    cv::Point px;  ///< in the quasi-image
    Eigen::Vector3d p_world;
    Eigen::Vector2d u0;  ///< projected at the aligned pose
    double depth = 0;
};

/** Shi-Tomasi corners of the map channel on pixels a map point won, with a mostly valid descriptor footprint. */
std::vector<MapKeypoint> mapKeypoints(const quasi::QuasiImage& q, const cv::Mat& channel, int margin,
                                      const map::LidarMap& map, const core::CameraModel& camera,
                                      const Eigen::Isometry3d& T_cam_world, const CrossModalPointOptions& o)
{
    if (q.valid.cols <= 2 * margin || q.valid.rows <= 2 * margin || o.keypoints <= 0) return {};
    const cv::Mat mask = quasi::keypointSupportMask(q, margin, o.min_valid_share);
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(channel, corners, o.keypoints, 0.01, o.min_keypoint_distance_px, mask, 5);
    std::vector<MapKeypoint> out;
    for (const cv::Point2f& c : corners)
    {
        MapKeypoint k;
        k.px = cv::Point(int(std::lround(c.x)), int(std::lround(c.y)));
        const int idx = q.provenance.at<int32_t>(k.px);
        if (idx < 0 || size_t(idx) >= map.size()) continue;
        k.p_world = map.point(size_t(idx)).cast<double>();
        const Eigen::Vector3d p_cam = T_cam_world * k.p_world;
        if (!camera.project(p_cam, k.u0)) continue;
        k.depth = p_cam.z();
        out.push_back(k);
    }
    return out;
}

struct Best
{
    cv::Point at;
    float d1 = std::numeric_limits<float>::max(), d2 = std::numeric_limits<float>::max();
};

/** Dense search of the camera field around `center` for the map descriptor: the best pixel and the best one
 *  farther than kMinSeparationPx from it (coarse grid of step max(1, r / 16), refined at step 1). */
Best searchCamera(const frontend::DescriptorField& cam, const cv::Point& center, int r, const float* map_desc)
{
    const int step = std::max(1, int(std::lround(r / 16.0))), n = cam.dims();
    std::vector<float> buf(size_t(n), 0.f);
    std::vector<std::pair<cv::Point, float>> cands;
    Best b;
    for (int dy = -r; dy <= r; dy += step)
        for (int dx = -r; dx <= r; dx += step)
        {
            const cv::Point p = center + cv::Point(dx, dy);
            if (!cam.describe(p.x, p.y, buf.data())) continue;
            const float d = frontend::squaredDistance(buf.data(), map_desc, n);
            cands.emplace_back(p, d);
            if (d < b.d1) b.d1 = d, b.at = p;
        }
    if (cands.empty()) return b;
    const int excl = std::max(kMinSeparationPx, 2 * step);
    for (const auto& [p, d] : cands)
        if (std::max(std::abs(p.x - b.at.x), std::abs(p.y - b.at.y)) > excl) b.d2 = std::min(b.d2, d);
    const cv::Point coarse = b.at;
    for (int dy = 1 - step; dy < step; ++dy)
        for (int dx = 1 - step; dx < step; ++dx)
        {
            const cv::Point p = coarse + cv::Point(dx, dy);
            if ((dx == 0 && dy == 0) || !cam.describe(p.x, p.y, buf.data())) continue;
            const float d = frontend::squaredDistance(buf.data(), map_desc, n);
            if (d < b.d1) b.d1 = d, b.at = p;
        }
    return b;
}

struct MapCandidate
{
    Eigen::Vector2d u;  ///< projected at the aligned pose
    Eigen::Vector3d p_world;
    float d = 0;
};

/** The map points at their own quasi-image pixels whose projection lies within r of u*, with their distance to the
 *  camera descriptor at u*; `shift` maps a quasi-image pixel to its position at the aligned pose (locally). */
std::vector<MapCandidate> mapCandidates(const frontend::DescriptorField& map_field, const quasi::QuasiImage& q,
                                        const map::LidarMap& map, const core::CameraModel& camera,
                                        const Eigen::Isometry3d& T_cam_world, const Eigen::Vector2d& u_star,
                                        const Eigen::Vector2d& shift, int r, const float* cam_desc)
{
    const int n = map_field.dims();
    std::vector<float> buf(size_t(n), 0.f);
    std::vector<MapCandidate> out;
    const int cx = int(std::lround(u_star.x() - shift.x())), cy = int(std::lround(u_star.y() - shift.y()));
    const int slack = 2;  // the shift varies with depth across the window
    for (int y = cy - r - slack; y <= cy + r + slack; ++y)
        for (int x = cx - r - slack; x <= cx + r + slack; ++x)
        {
            if (x < 0 || y < 0 || x >= q.provenance.cols || y >= q.provenance.rows) continue;
            const int idx = q.provenance.at<int32_t>(y, x);
            if (idx < 0 || size_t(idx) >= map.size() || !q.sparse.at<uint8_t>(y, x)) continue;
            MapCandidate c;
            c.p_world = map.point(size_t(idx)).cast<double>();
            if (!camera.project(T_cam_world * c.p_world, c.u)) continue;
            if ((c.u - u_star).cwiseAbs().maxCoeff() > r) continue;
            if (!map_field.describe(x, y, buf.data())) continue;
            c.d = frontend::squaredDistance(buf.data(), cam_desc, n);
            out.push_back(c);
        }
    return out;
}

/** Local minima kept kMinSeparationPx apart, within the ratio band of the best, at most max_candidates; their
 *  probabilities from the distances. */
void selectCandidates(std::vector<MapCandidate> all, const CrossModalPointOptions& o, CrossModalPointAssociation& a)
{
    std::sort(all.begin(), all.end(), [](const MapCandidate& l, const MapCandidate& r) { return l.d < r.d; });
    if (all.empty()) return;
    const double limit = all.front().d / (o.ratio * o.ratio);
    std::vector<const MapCandidate*> kept;
    for (const MapCandidate& c : all)
    {
        if (c.d > limit || int(kept.size()) >= o.max_candidates) break;
        bool near = false;
        for (const MapCandidate* k : kept) near = near || (k->u - c.u).cwiseAbs().maxCoeff() < kMinSeparationPx;
        if (!near) kept.push_back(&c);
    }
    double sum = 0;
    for (const MapCandidate* k : kept)
    {
        a.p_map.push_back(k->p_world);
        a.probability.push_back(std::exp(-(double(k->d) - double(all.front().d)) / o.temperature));
        sum += a.probability.back();
    }
    for (double& p : a.probability) p /= sum;
}
}  // namespace

int CrossModalPointAssociation::nominal() const
{
    return int(std::max_element(probability.begin(), probability.end()) - probability.begin());
}

frontend::DescriptorField describeCameraForMapPoints(const cv::Mat& gray, const CrossModalPointOptions& o)
{
    return frontend::computeDescriptorField(gray, frontend::DescriptorKind::OrientationField, o.descriptors);
}

std::vector<CrossModalPointAssociation> associateCrossModalPoints(const frontend::DescriptorField& camera_field,
                                                                  const quasi::QuasiImage& q, const map::LidarMap& map,
                                                                  const core::CameraModel& camera,
                                                                  const Eigen::Isometry3d& T_world_cam, double sigma_m,
                                                                  double sigma_rad, const CrossModalPointOptions& o,
                                                                  CrossModalPointStats* stats)
{
    std::vector<CrossModalPointAssociation> out;
    if (q.reflectivity.empty() || camera_field.channels.empty()) return out;
    const cv::Mat channel = frontend::fillInvalid(
        o.channel == CrossModalChannel::Reflectivity
            ? frontend::rankEqualised(q.reflectivity, q.valid, q.depth, o.depth_bands)
            : frontend::depthEdgeChannel(q.depth, q.valid, o.depth_edge_sigma_px, o.depth_edge_scale),
        q.valid, o.fill_sigma_px);
    const frontend::DescriptorField map_field =
        frontend::computeDescriptorField(channel, frontend::DescriptorKind::OrientationField, o.descriptors);
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    const std::vector<MapKeypoint> kps = mapKeypoints(q, channel, map_field.radius() + 2, map, camera, T_cam_world, o);
    const int n = map_field.dims();
    std::vector<float> map_desc(size_t(n), 0.f), cam_desc(size_t(n), 0.f);
    const double f = 0.5 * (camera.fx + camera.fy);
    CrossModalPointStats s;
    for (const MapKeypoint& k : kps)
    {
        if (k.depth <= 0 || !map_field.describe(k.px.x, k.px.y, map_desc.data())) continue;
        ++s.map_keypoints;
        const int r = int(std::ceil(std::min(o.window_max_px, o.window_base_px + f * (sigma_rad + sigma_m / k.depth))));
        const cv::Point center(int(std::lround(k.u0.x())), int(std::lround(k.u0.y())));
        const Best b = searchCamera(camera_field, center, r, map_desc.data());
        if (b.d2 == std::numeric_limits<float>::max() || std::sqrt(b.d1 / b.d2) >= o.ratio) continue;
        if (!camera_field.describe(b.at.x, b.at.y, cam_desc.data())) continue;
        ++s.accepted;
        CrossModalPointAssociation a;
        a.px = Eigen::Vector2d(b.at.x, b.at.y);
        a.p_searched = k.p_world;
        const Eigen::Vector2d shift = k.u0 - Eigen::Vector2d(k.px.x, k.px.y);
        selectCandidates(mapCandidates(map_field, q, map, camera, T_cam_world, a.px, shift, r, cam_desc.data()), o, a);
        if (!a.p_map.empty()) out.push_back(std::move(a));
    }
    if (stats) *stats = s;
    return out;
}

void appendAxisLineFactors(const std::vector<CrossModalPointAssociation>& associations, double sigma_px,
                           std::vector<estimation::LineFactorInput>& lines)
{
    for (const CrossModalPointAssociation& a : associations)
        for (int axis = 0; axis < 2; ++axis)
        {
            estimation::LineFactorInput l;
            // u - u* = 0 and v - v* = 0: unit normals, so l^T [u; 1] is the pixel offset along that axis.
            l.line_px = axis == 0 ? Eigen::Vector3d(1, 0, -a.px.x()) : Eigen::Vector3d(0, 1, -a.px.y());
            l.sigma_px = sigma_px;
            for (size_t c = 0; c < a.p_map.size(); ++c)
            {
                estimation::LineCandidate lc;
                lc.support_map = {a.p_map[c]};
                lc.probability = a.probability[c];
                l.candidates.push_back(std::move(lc));
            }
            lines.push_back(std::move(l));
        }
}

int countCorrect(const std::vector<CrossModalPointAssociation>& associations, const core::CameraModel& camera,
                 const Eigen::Isometry3d& T_world_cam_true, double correct_px)
{
    std::vector<estimation::PointMatch> nominal;
    for (const CrossModalPointAssociation& a : associations) nominal.push_back({a.px, a.p_map[size_t(a.nominal())]});
    return countCorrectMatches(nominal, camera, T_world_cam_true, correct_px);
}

}  // namespace quasiloc::tracking
