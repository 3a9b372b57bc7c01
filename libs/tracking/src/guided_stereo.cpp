// GuidedStereo: stereo points around the dense disparity (guided_stereo.h).
#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/tracking/guided_stereo.h>

namespace quasiloc::tracking
{
GuidedStereo::GuidedStereo(const core::StereoRig& rig, const core::StereoRectification& rect,
                           const frontend::StereoOptions& stereo, const GuidedStereoOptions& options)
    : rig_(rig), stereo_(stereo), opt_(options)
{
    core::require(
        opt_.patch_radius_px >= 1 && opt_.search_px >= 1 && opt_.max_prior_spread_px >= 0 && opt_.max_mean_abs_diff > 0,
        "GuidedStereo", "patch radius and search >= 1, spread >= 0 and difference > 0 needed");
    const cv::Matx33d R[2] = {rect.R_left, rect.R_right};
    for (int c = 0; c < 2; ++c)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) R_rect_raw_[c](i, j) = R[c](i, j);
    f_ = rect.P_left(0, 0), cx_ = rect.P_left(0, 2), cy_ = rect.P_left(1, 2);
    cx_right_ = rect.P_right(0, 2);
    baseline_m_ = rect.baseline_m;
    core::require(f_ > 0 && baseline_m_ > 0, "GuidedStereo", "rectification gave no usable focal length or baseline");
}

double GuidedStereo::priorDisparity(const reloc::StereoDisparity& d, double u, double v) const
{
    const int s = d.scale;
    const double xs = (u + 0.5) / s - 0.5, ys = (v + 0.5) / s - 0.5;
    const int x0 = int(std::floor(xs)), y0 = int(std::floor(ys));
    if (x0 < 0 || y0 < 0 || x0 + 1 >= d.disparity.cols || y0 + 1 >= d.disparity.rows) return -1;
    const int16_t* r0 = d.disparity.ptr<int16_t>(y0);
    const int16_t* r1 = d.disparity.ptr<int16_t>(y0 + 1);
    const int16_t n[4] = {r0[x0], r0[x0 + 1], r1[x0], r1[x0 + 1]};
    const auto [lo, hi] = std::minmax_element(n, n + 4);
    if (*lo <= 0 || s * (*hi - *lo) / 16.0 > opt_.max_prior_spread_px) return -1;
    const double ax = xs - x0, ay = ys - y0;
    const double top = (1 - ax) * n[0] + ax * n[1], bottom = (1 - ax) * n[2] + ax * n[3];
    return s * ((1 - ay) * top + ay * bottom) / 16.0;
}

double GuidedStereo::searchRow(const cv::Mat& left, const cv::Mat& right, int ul, int vl, int centre) const
{
    const int r = opt_.patch_radius_px, S = opt_.search_px, side = 2 * r + 1;
    if (vl - r < 0 || vl + r >= left.rows || ul - r < 0 || ul + r >= left.cols) return NAN;
    // One more column on each side than searched: the parabola needs the neighbours of a best column at +-S.
    if (centre - S - 1 - r < 0 || centre + S + 1 + r >= right.cols) return NAN;
    const double n = double(side * side);
    // Each patch's mean is removed: the two cameras' exposures and gains differ.
    const auto patchMean = [&](const cv::Mat& im, int cu) {
        int sum = 0;
        for (int y = vl - r; y <= vl + r; ++y)
        {
            const uint8_t* row = im.ptr<uint8_t>(y);
            for (int x = cu - r; x <= cu + r; ++x) sum += row[x];
        }
        return sum / n;
    };
    const double mean_left = patchMean(left, ul);
    double cost[64];
    const int count = 2 * S + 3;  // columns centre - S - 1 .. centre + S + 1
    if (count > 64) return NAN;
    for (int k = 0; k < count; ++k)
    {
        const int cu = centre - S - 1 + k;
        const double offset = patchMean(right, cu) - mean_left;
        double c = 0;
        for (int y = vl - r; y <= vl + r; ++y)
        {
            const uint8_t *lrow = left.ptr<uint8_t>(y) + ul - r, *rrow = right.ptr<uint8_t>(y) + cu - r;
            for (int x = 0; x < side; ++x) c += std::abs(double(rrow[x]) - double(lrow[x]) - offset);
        }
        cost[k] = c;
    }
    int best = 1;
    for (int k = 2; k <= 2 * S + 1; ++k)
        if (cost[k] < cost[best]) best = k;
    // A best column at the border of the search: the match may lie outside it.
    if (best == 1 || best == 2 * S + 1) return NAN;
    if (cost[best] / n > opt_.max_mean_abs_diff) return NAN;
    const double denom = cost[best - 1] - 2 * cost[best] + cost[best + 1];
    if (!(denom > 0)) return NAN;
    const double delta = std::clamp(0.5 * (cost[best - 1] - cost[best + 1]) / denom, -0.5, 0.5);
    return centre - S - 1 + best + delta;
}

std::vector<frontend::StereoPoint> GuidedStereo::match(const std::vector<cv::KeyPoint>& left,
                                                       const reloc::StereoDisparity& d,
                                                       std::vector<cv::KeyPoint>& right) const
{
    core::require(!d.disparity.empty() && d.disparity.type() == CV_16SC1 && d.scale >= 1, "GuidedStereo::match",
                  "no SGBM disparity (CV_16SC1) given");
    core::require(
        d.left_rect.type() == CV_8UC1 && d.right_rect.type() == CV_8UC1 && d.left_rect.size() == d.right_rect.size(),
        "GuidedStereo::match", "the rectified pair must be two 8-bit gray images of one size");
    std::vector<frontend::StereoPoint> out;
    right.clear();
    const double fb = f_ * baseline_m_;
    for (size_t i = 0; i < left.size(); ++i)
    {
        const Eigen::Vector3d p = R_rect_raw_[0] * rig_.left.unproject({left[i].pt.x, left[i].pt.y});
        if (!(p.z() > 0)) continue;
        const double u = f_ * p.x() / p.z() + cx_, v = f_ * p.y() / p.z() + cy_;
        const double prior = priorDisparity(d, u, v);
        if (prior <= 0) continue;
        const int ul = int(std::lround(u)), vl = int(std::lround(v));
        const double column = searchRow(d.left_rect, d.right_rect, ul, vl, ul - int(std::lround(prior)));
        if (std::isnan(column)) continue;
        // The patch was compared at the integer pixel (ul, vl); the keypoint keeps its sub-pixel offset.
        const double disparity = ul - column;
        if (disparity < stereo_.min_disparity_px || disparity > stereo_.max_disparity_px) continue;
        const double Z = fb / disparity;
        if (Z > stereo_.max_depth_m) continue;
        // The right camera's pixel: the rectified right ray, rotated back to the raw right camera.
        const double u_right = u - disparity;
        const Eigen::Vector3d ray_rect((u_right - cx_right_) / f_, (v - cy_) / f_, 1.0);
        Eigen::Vector2d px_right;
        if (!rig_.right.project(R_rect_raw_[1].transpose() * ray_rect, px_right)) continue;
        frontend::StereoPoint s;
        s.left = int(i);
        s.right = int(right.size());
        s.disparity_px = float(disparity);
        s.similarity = 1.0f;  // no descriptors compared
        s.p_left = R_rect_raw_[0].transpose() * Eigen::Vector3d((u - cx_) * Z / f_, (v - cy_) * Z / f_, Z);
        cv::KeyPoint k = left[i];
        k.pt = cv::Point2f(float(px_right.x()), float(px_right.y()));
        right.push_back(k);
        out.push_back(s);
    }
    return out;
}

}  // namespace quasiloc::tracking
