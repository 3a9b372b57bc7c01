#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/frontend/stereo_matcher.h>

namespace quasiloc::frontend
{
void StereoOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("max_epipolar_px", max_epipolar_px, "px", Range::above(0), "|v_left - v_right| in the rectified images");
    t.add("min_disparity_px", min_disparity_px, "px", Range::atLeast(0), "disparity at least");
    t.add("max_disparity_px", max_disparity_px, "px", Range::above(0), "disparity at most");
    t.add("ratio", ratio, "", Range{0, 1, true, false}, "ratio test among the epipolar candidates; 1 disables");
    t.add("max_distance_l2", max_distance_l2, "", Range{0, 2, true, false}, "float descriptors: L2 distance at most");
    t.add("max_distance_hamming", max_distance_hamming, "", Range::above(0),
          "binary descriptors: Hamming distance at most");
    t.add("max_depth_m", max_depth_m, "m", Range::above(0), "triangulated points farther than this are dropped");
}

void StereoOptions::check(const std::string& input) const
{
    checkRanges(input, "Stereo");
    core::require(max_disparity_px > min_disparity_px, input + ": " + core::iniKeyName("Stereo", "max_disparity_px"),
                  "must be > min_disparity_px");
}

StereoMatcher::StereoMatcher(const core::StereoRig& rig, const StereoOptions& options) : rig_(rig), opt_(options)
{
    options.check("stereo options");
    rig.check("stereo rig");
    const core::StereoRectification r = rig.rectify(0.0);
    cv::Matx33d R[2] = {r.R_left, r.R_right};
    for (int c = 0; c < 2; ++c)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) R_rect_raw_[c](i, j) = R[c](i, j);
    f_ = r.P_left(0, 0), cx_ = r.P_left(0, 2), cy_ = r.P_left(1, 2);
    baseline_m_ = r.baseline_m;
    core::require(f_ > 0 && baseline_m_ > 0, "stereo rig", "rectification gave no usable focal length or baseline");
}

Eigen::Vector2d StereoMatcher::rectifyPixel(int cam, const cv::Point2f& px) const
{
    const core::CameraModel& m = cam == 0 ? rig_.left : rig_.right;
    const Eigen::Vector3d p = R_rect_raw_[cam] * m.unproject({px.x, px.y});
    // Both cameras with the left principal point: the column difference is then the true disparity.
    return {f_ * p.x() / p.z() + cx_, f_ * p.y() / p.z() + cy_};
}

std::vector<StereoPoint> StereoMatcher::match(const Features& left, const Features& right) const
{
    std::vector<Eigen::Vector2d> L(left.size()), R(right.size());
    for (size_t i = 0; i < left.size(); ++i) L[i] = rectifyPixel(0, left.keypoints[i].pt);
    for (size_t j = 0; j < right.size(); ++j) R[j] = rectifyPixel(1, right.keypoints[j].pt);
    SearchRegion region;
    // Right keypoints bucketed by rectified row: a left keypoint only looks at the rows of its epipolar band.
    std::vector<std::vector<int>> rows;
    const int band = int(std::ceil(opt_.max_epipolar_px));
    auto rowOf = [&](double v) { return int(std::floor(v)) + band + 1; };
    for (size_t j = 0; j < R.size(); ++j)
    {
        const int r = rowOf(R[j].y());
        if (r < 0) continue;
        if (r >= int(rows.size())) rows.resize(size_t(r) + 1);
        rows[size_t(r)].push_back(int(j));
    }
    region.train_subsets.resize(L.size());
    for (size_t i = 0; i < L.size(); ++i)
        for (int r = std::max(0, rowOf(L[i].y()) - band - 1); r <= rowOf(L[i].y()) + band + 1 && r < int(rows.size());
             ++r)
            for (int j : rows[size_t(r)]) region.train_subsets[i].push_back(j);
    region.accept = [&](int i, int j) {
        const double disp = L[i].x() - R[j].x();
        return std::abs(L[i].y() - R[j].y()) <= opt_.max_epipolar_px && disp >= opt_.min_disparity_px &&
               disp <= opt_.max_disparity_px;
    };
    PointMatchingOptions pm;
    pm.ratio = opt_.ratio;
    pm.mutual = true;
    pm.max_distance_l2 = opt_.max_distance_l2;
    pm.max_distance_hamming = opt_.max_distance_hamming;
    std::vector<PointCandidate> best_left;
    const auto cands = findCandidates(left, right, 2, pm.maxDistance(left), region, &best_left);
    std::vector<StereoPoint> out;
    for (const auto& m : selectMatches(cands, best_left, pm))
    {
        StereoPoint s;
        s.left = m.query, s.right = m.train, s.similarity = m.similarity;
        s.disparity_px = float(L[m.query].x() - R[m.train].x());
        const double Z = f_ * baseline_m_ / s.disparity_px;
        if (!(Z > 0) || Z > opt_.max_depth_m) continue;
        const Eigen::Vector3d p_rect((L[m.query].x() - cx_) * Z / f_, (L[m.query].y() - cy_) * Z / f_, Z);
        s.p_left = R_rect_raw_[0].transpose() * p_rect;
        out.push_back(s);
    }
    return out;
}
}  // namespace quasiloc::frontend
