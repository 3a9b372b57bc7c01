#include "crossmodal_match.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>

namespace quasiloc::bench
{
namespace
{
using frontend::DescriptorField;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

/** The map channels a quasi-image is described by, holes filled: reflectivity, rank-equalised, depth edges. */
std::array<cv::Mat, 3> mapChannels(const quasi::QuasiImage& q, const MatchBenchOptions& o)
{
    const cv::Mat rank = frontend::rankEqualised(q.reflectivity, q.valid, q.depth, o.depth_bands);
    const cv::Mat edges = frontend::depthEdgeChannel(q.depth, q.valid, o.depth_edge_sigma_px, o.depth_edge_scale);
    return {frontend::fillInvalid(q.reflectivity, q.valid, o.fill_sigma_px),
            frontend::fillInvalid(rank, q.valid, o.fill_sigma_px),
            frontend::fillInvalid(edges, q.valid, o.fill_sigma_px)};
}

struct Keypoint
{
    cv::Point px;       ///< in the quasi-image at the guess = predicted position in the camera image
    cv::Point2d truth;  ///< the map point projected at the true pose
    int window_px = 0;  ///< search radius
    bool reachable = false;
    double chance = 0;  ///< share of the window's pixels within correct_px of the true position
};

std::vector<cv::Point> corners(const cv::Mat& channel, int n, const cv::Mat& mask, double min_distance)
{
    std::vector<cv::Point2f> c;
    if (n > 0) cv::goodFeaturesToTrack(channel, c, n, 0.01, min_distance, mask, 5);
    std::vector<cv::Point> out;
    for (const auto& p : c) out.emplace_back(int(std::lround(p.x)), int(std::lround(p.y)));
    return out;
}

std::vector<Keypoint> selectKeypoints(const quasi::QuasiImage& q, const std::array<cv::Mat, 3>& ch, int margin,
                                      const core::CameraModel& camera, const map::LidarMap& map,
                                      const Eigen::Isometry3d& T_world_true, double t_m, double rot_deg,
                                      const MatchBenchOptions& o)
{
    const cv::Mat mask = quasi::keypointSupportMask(q, margin, o.min_valid_share);
    std::vector<cv::Point> pts = corners(ch[1], o.keypoints / 2, mask, o.min_keypoint_distance_px);
    for (const cv::Point& p : corners(ch[2], o.keypoints - int(pts.size()), mask, o.min_keypoint_distance_px))
    {
        bool near = false;
        for (const cv::Point& e : pts) near = near || cv::norm(e - p) < 0.5 * o.min_keypoint_distance_px;
        if (!near) pts.push_back(p);
    }
    const Eigen::Isometry3d T_true_world = T_world_true.inverse();
    const double f = 0.5 * (camera.fx + camera.fy), rot = rot_deg * M_PI / 180;
    std::vector<Keypoint> kps;
    for (const cv::Point& p : pts)
    {
        const int idx = q.provenance.at<int32_t>(p);
        const float z = q.depth.at<float>(p);
        if (idx < 0 || z <= 0) continue;
        Eigen::Vector2d uv;
        if (!camera.project(T_true_world * map.point(size_t(idx)).cast<double>(), uv)) continue;
        Keypoint k;
        k.px = p;
        k.truth = {uv.x(), uv.y()};
        k.window_px = int(std::ceil(std::min(o.window_max_px, o.window_base_px + f * (rot + t_m / z))));
        k.reachable = std::abs(uv.x() - p.x) <= k.window_px && std::abs(uv.y() - p.y) <= k.window_px;
        const int c = int(std::ceil(o.correct_px));
        int near = 0;
        for (int y = int(std::lround(uv.y())) - c; y <= int(std::lround(uv.y())) + c; ++y)
            for (int x = int(std::lround(uv.x())) - c; x <= int(std::lround(uv.x())) + c; ++x)
                near += std::abs(x - p.x) <= k.window_px && std::abs(y - p.y) <= k.window_px &&
                        std::hypot(x - uv.x(), y - uv.y()) <= o.correct_px;
        k.chance = near / std::pow(2.0 * k.window_px + 1, 2);
        kps.push_back(k);
    }
    return kps;
}

struct Found
{
    bool any = false;
    cv::Point at;
    float d1 = std::numeric_limits<float>::max(), d2 = std::numeric_limits<float>::max();
    float ratio() const { return d2 > 0 ? std::sqrt(d1 / d2) : 1.f; }
    double beaten = -1;  ///< share of candidates farther than the true position (-1: not measured)
};

/** Searches the window for each of `map_desc`'s descriptors (one per map channel) in one camera field. */
void searchWindow(const DescriptorField& cam, const Keypoint& k, const std::vector<std::vector<float>>& map_desc,
                  const std::vector<bool>& have, std::vector<Found>& found)
{
    const int r = k.window_px, step = std::max(1, int(std::lround(r / 16.0))), n = cam.dims();
    const int M = int(map_desc.size());
    std::vector<float> buf(static_cast<size_t>(n));
    struct Cand
    {
        cv::Point p;
        float d;
    };
    std::vector<std::vector<Cand>> cands(static_cast<size_t>(M));
    for (int dy = -r; dy <= r; dy += step)
        for (int dx = -r; dx <= r; dx += step)
        {
            const cv::Point p = k.px + cv::Point(dx, dy);
            if (!cam.describe(p.x, p.y, buf.data())) continue;
            for (int m = 0; m < M; ++m)
                if (have[size_t(m)])
                    cands[size_t(m)].push_back(
                        {p, frontend::squaredDistance(buf.data(), map_desc[size_t(m)].data(), n)});
        }
    const int excl = std::max(3, 2 * step);
    found.assign(size_t(M), Found{});
    const cv::Point truth(int(std::lround(k.truth.x)), int(std::lround(k.truth.y)));
    std::vector<float> at_truth(static_cast<size_t>(n));
    const bool truth_described = k.reachable && cam.describe(truth.x, truth.y, at_truth.data());
    for (int m = 0; m < M; ++m)
    {
        const auto& c = cands[size_t(m)];
        if (c.empty()) continue;
        Found& f = found[size_t(m)];
        f.any = true;
        for (const Cand& x : c)
            if (x.d < f.d1) f.d1 = x.d, f.at = x.p;
        for (const Cand& x : c)
            if (std::max(std::abs(x.p.x - f.at.x), std::abs(x.p.y - f.at.y)) > excl) f.d2 = std::min(f.d2, x.d);
        if (truth_described)
        {
            const float dt = frontend::squaredDistance(at_truth.data(), map_desc[size_t(m)].data(), n);
            long farther = 0;
            for (const Cand& x : c) farther += x.d > dt;
            f.beaten = double(farther) / double(c.size());
        }
        const cv::Point coarse = f.at;
        for (int dy = 1 - step; dy < step; ++dy)
            for (int dx = 1 - step; dx < step; ++dx)
            {
                const cv::Point p = coarse + cv::Point(dx, dy);
                if ((dx == 0 && dy == 0) || !cam.describe(p.x, p.y, buf.data())) continue;
                const float d = frontend::squaredDistance(buf.data(), map_desc[size_t(m)].data(), n);
                if (d < f.d1) f.d1 = d, f.at = p;
            }
    }
}

void count(MatchCounts& c, const Keypoint& k, const Found& f, const MatchBenchOptions& o)
{
    ++c.keypoints;
    c.reachable += k.reachable;
    c.chance += k.chance;
    if (!f.any) return;
    if (f.beaten >= 0) c.beaten_sum += f.beaten, ++c.beaten_n;
    ++c.found, c.sum_dx += f.at.x - k.truth.x, c.sum_dy += f.at.y - k.truth.y;
    const bool ok = std::hypot(f.at.x - k.truth.x, f.at.y - k.truth.y) <= o.correct_px;
    c.top1_correct += ok;
    if (f.ratio() < o.ratio) ++c.accepted, c.correct += ok;
}

cv::Mat toGray(const cv::Mat& image)
{
    if (image.channels() == 1) return image;
    cv::Mat g;
    cv::cvtColor(image, g, cv::COLOR_BGR2GRAY);
    return g;
}

void evaluateXFeat(const CameraSide& cam, const quasi::QuasiImage& q, const std::array<cv::Mat, 3>& ch,
                   const core::CameraModel& camera, const map::LidarMap& map, const Eigen::Isometry3d& T_world_true,
                   double t_m, double rot_deg, const MatchBenchOptions& o, XFeatMatchers& xf, GuessResult& r)
{
    const auto t0 = Clock::now();
    cv::Mat img;
    ch[1].convertTo(img, CV_8U, 255.0);
    img.setTo(0, q.valid == 0);
    frontend::Features fq;
    xf.extractor->extract(img, q.valid, fq);
    const double f = 0.5 * (camera.fx + camera.fy), rot = rot_deg * M_PI / 180;
    std::vector<double> radius(fq.size());
    for (size_t i = 0; i < fq.size(); ++i)
    {
        const cv::Point p(int(std::lround(fq.keypoints[i].pt.x)), int(std::lround(fq.keypoints[i].pt.y)));
        const float z = q.depth.at<float>(p);
        radius[i] = z > 0 ? std::min(o.window_max_px, o.window_base_px + f * (rot + t_m / z)) : 0;
    }
    frontend::SearchRegion region;
    region.accept = [&](int qi, int ti) {
        const cv::Point2f d = fq.keypoints[size_t(qi)].pt - cam.xfeat.keypoints[size_t(ti)].pt;
        return std::max(std::abs(d.x), std::abs(d.y)) <= radius[size_t(qi)];
    };
    const Eigen::Isometry3d T_true_world = T_world_true.inverse();
    frontend::PointMatcher* matchers[kXFeatRows] = {xf.lighterglue.get(), xf.mutual_nn.get()};
    for (int m = 0; m < kXFeatRows; ++m)
    {
        if (!matchers[m]) continue;
        MatchCounts& c = r.xfeat[size_t(m)];
        c.keypoints += long(fq.size());
        for (const auto& pm : matchers[m]->match(fq, cam.xfeat, &region))
        {
            const cv::Point2f qp = fq.keypoints[size_t(pm.query)].pt;
            const int idx = q.provenance.at<int32_t>(cv::Point(int(std::lround(qp.x)), int(std::lround(qp.y))));
            ++c.accepted;
            Eigen::Vector2d uv;
            if (idx < 0 || !camera.project(T_true_world * map.point(size_t(idx)).cast<double>(), uv)) continue;
            const cv::Point2f tp = cam.xfeat.keypoints[size_t(pm.train)].pt;
            c.correct += std::hypot(tp.x - uv.x(), tp.y - uv.y()) <= o.correct_px;
        }
    }
    r.ms_xfeat += msSince(t0);
}
}  // namespace

std::string cameraVariantName(int camera) { return camera == 0 ? "camera raw" : "camera locally normalised"; }

std::string mapChannelName(int channel)
{
    static const char* names[kMapChannels] = {"reflectivity", "rank-equalised reflectivity", "depth edges",
                                              "rank refl. + depth edges apart"};
    return names[channel];
}

frontend::DescriptorKind kindOf(int kind)
{
    static const frontend::DescriptorKind kinds[kKinds] = {
        frontend::DescriptorKind::Ncc, frontend::DescriptorKind::Mind, frontend::DescriptorKind::OrientationField};
    return kinds[kind];
}

void MatchCounts::add(const MatchCounts& o)
{
    keypoints += o.keypoints, reachable += o.reachable, top1_correct += o.top1_correct;
    accepted += o.accepted, correct += o.correct, chance += o.chance;
    sum_dx += o.sum_dx, sum_dy += o.sum_dy, found += o.found;
    beaten_sum += o.beaten_sum, beaten_n += o.beaten_n;
}

CameraSide describeCamera(const cv::Mat& image, const MatchBenchOptions& o, XFeatMatchers* xfeat)
{
    const cv::Mat gray = toGray(image);
    const cv::Mat variants[kCameraVariants] = {
        gray, frontend::locallyNormalised(gray, o.local_norm_sigma_px, o.local_norm_min_std)};
    CameraSide s;
    for (int c = 0; c < kCameraVariants; ++c)
        for (int k = 0; k < kKinds; ++k)
            s.fields[size_t(c)][size_t(k)] = frontend::computeDescriptorField(variants[c], kindOf(k), o.descriptors);
    if (xfeat && xfeat->extractor) xfeat->extractor->extract(gray, cv::Mat(), s.xfeat);
    return s;
}

GuessResult evaluateGuess(const CameraSide& cam, const core::CameraModel& camera, const map::LidarMap& map,
                          quasi::QuasiRenderer& renderer, const Eigen::Isometry3d& T_world_true,
                          const Eigen::Isometry3d& T_world_guess, double t_m, double rot_deg,
                          const MatchBenchOptions& o, XFeatMatchers* xfeat)
{
    GuessResult r;
    auto t0 = Clock::now();
    quasi::QuasiImage q;
    renderer.render(core::fromIsometry(T_world_guess), camera, q, false);
    r.ms_render = msSince(t0);

    t0 = Clock::now();
    const std::array<cv::Mat, 3> ch = mapChannels(q, o);
    std::array<std::array<DescriptorField, kKinds>, 3> map_fields;
    int margin = 0;
    for (int m = 0; m < 3; ++m)
        for (int k = 0; k < kKinds; ++k)
        {
            map_fields[size_t(m)][size_t(k)] =
                frontend::computeDescriptorField(ch[size_t(m)], kindOf(k), o.descriptors);
            margin = std::max(margin, map_fields[size_t(m)][size_t(k)].radius() + 2);
        }
    const std::vector<Keypoint> kps = selectKeypoints(q, ch, margin, camera, map, T_world_true, t_m, rot_deg, o);
    r.ms_descriptors = msSince(t0);

    t0 = Clock::now();
    std::vector<std::vector<float>> map_desc(3);
    std::vector<bool> have(3);
    std::vector<Found> found;
    for (const Keypoint& k : kps)
        for (int kind = 0; kind < kKinds; ++kind)
        {
            for (int m = 0; m < 3; ++m)
            {
                const DescriptorField& f = map_fields[size_t(m)][size_t(kind)];
                map_desc[size_t(m)].resize(size_t(f.dims()));
                have[size_t(m)] = f.describe(k.px.x, k.px.y, map_desc[size_t(m)].data());
            }
            for (int c = 0; c < kCameraVariants; ++c)
            {
                searchWindow(cam.fields[size_t(c)][size_t(kind)], k, map_desc, have, found);
                for (int m = 0; m < 3; ++m) count(r.combos[size_t(comboIndex(c, m, kind))], k, found[size_t(m)], o);
                // Kept apart: the channel whose best match stands out more.
                const Found& apart =
                    found[1].any && (!found[2].any || found[1].ratio() <= found[2].ratio()) ? found[1] : found[2];
                count(r.combos[size_t(comboIndex(c, 3, kind))], k, apart, o);
            }
        }
    r.ms_search = msSince(t0);
    if (xfeat && xfeat->extractor) evaluateXFeat(cam, q, ch, camera, map, T_world_true, t_m, rot_deg, o, *xfeat, r);
    return r;
}

}  // namespace quasiloc::bench
