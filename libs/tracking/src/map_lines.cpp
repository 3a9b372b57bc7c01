// Map lines for the point-to-line map factor (map_lines.h).
#include <quasiloc/tracking/map_lines.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace quasiloc::tracking
{
namespace
{
/** Light direction of the shading, camera frame: chosen so that the five axis normals a camera can face (+-x, +-y,
 *  -z) shade at least 0.22 apart (28 grey levels): a room's walls, floor and boxes differ. */
const Eigen::Vector3d kLight = Eigen::Vector3d(1, 2, 4).normalized();
constexpr double kDiscontinuityRel = 0.05;
}  // namespace

MapLineExtractor::MapLineExtractor(const core::CameraModel& camera, const MapLineOptions& options,
                                   const frontend::LineOptions& lines)
    : options_(options), rays_(camera)
{
    frontend::LineOptions shading_lines = lines;  // the same lengths in image pixels
    shading_lines.min_length_px /= options.shading_step;
    shading_detector_ = std::make_unique<frontend::LineDetector>(shading_lines);
}

MapLineExtractor::~MapLineExtractor() = default;

std::vector<MapLine> MapLineExtractor::mapLines(const cv::Mat& depth, const Eigen::Isometry3d& T_world_cam) const
{
    const cv::Mat shading = normalShading(depth);
    std::vector<MapLine> out;
    for (frontend::LineSegment s : shading_detector_->detect(shading))
    {
        if (!isEdge(shading, s)) continue;
        s.p0 *= float(options_.shading_step), s.p1 *= float(options_.shading_step);  // shading -> image pixels
        if (auto m = lift(s, depth, T_world_cam)) out.push_back(std::move(*m));
    }
    return out;
}

namespace
{
/** Sums over a window x window box (odd) of the camera points (x z, y z, z) and of the valid pixels, centred at every
 *  step-th pixel: element (y, x) for pixel (x step, y step); outside the image counts as empty. Only the centres
 *  that are used are summed (separably: row sums at those columns, then a running sum down them). */
cv::Mat boxSumsAtStep(const cv::Mat& depth, const cv::Mat& ray_x, const cv::Mat& ray_y, int step, int window)
{
    const int r = window / 2, out_rows = depth.rows / step, out_cols = depth.cols / step;
    cv::Mat sums(out_rows, out_cols, CV_32FC4, cv::Scalar::all(0));
    std::vector<cv::Vec4d> ring(size_t(window) * size_t(out_cols), cv::Vec4d::all(0));  // the last `window` rows' sums
    std::vector<cv::Vec4d> column(size_t(out_cols), cv::Vec4d::all(0));                 // their sum
    for (int v_in = 0; v_in < depth.rows + r; ++v_in)
    {
        cv::Vec4d* row = &ring[size_t(v_in % window) * size_t(out_cols)];
        for (int x = 0; x < out_cols; ++x) column[size_t(x)] -= row[x];  // the row leaving the window
        std::fill(row, row + out_cols, cv::Vec4d::all(0));
        if (v_in < depth.rows)
        {
            // A running sum along the row (an invalid pixel has z = 0, so only its count needs the test), stored at
            // the centres.
            const float* d = depth.ptr<float>(v_in);
            const float* rx = ray_x.ptr<float>(v_in);
            const float* ry = ray_y.ptr<float>(v_in);
            double sx = 0, sy = 0, sz = 0, sn = 0;
            int x_next = 0, next_centre = 0;
            for (int u_in = 0; u_in < depth.cols + r; ++u_in)
            {
                if (u_in < depth.cols)
                {
                    const double z = d[u_in];
                    sx += rx[u_in] * z, sy += ry[u_in] * z, sz += z, sn += z > 0;
                }
                const int u_out = u_in - window;  // leaves the window
                if (u_out >= 0)
                {
                    const double z = d[u_out];
                    sx -= rx[u_out] * z, sy -= ry[u_out] * z, sz -= z, sn -= z > 0;
                }
                if (u_in == next_centre + r)  // the window of the next centre is complete
                {
                    if (x_next < out_cols) row[x_next] = cv::Vec4d(sx, sy, sz, sn);
                    ++x_next, next_centre += step;
                }
            }
            for (int x = 0; x < out_cols; ++x) column[size_t(x)] += row[x];
        }
        const int v = v_in - r;  // the centre row whose window is now complete
        if (v < 0 || v % step != 0 || v / step >= out_rows) continue;
        cv::Vec4f* o = sums.ptr<cv::Vec4f>(v / step);
        for (int x = 0; x < out_cols; ++x) o[x] = cv::Vec4f(column[size_t(x)]);
    }
    return sums;
}
}  // namespace

cv::Mat MapLineExtractor::normalShading(const cv::Mat& depth) const
{
    CV_Assert(depth.type() == CV_32FC1 && depth.size() == rays_.x.size());
    // The map's points are noisy at the pixel scale (a centimetre of range noise across 4 mm pixels): normals come
    // from the points averaged over a window and differenced over kBaselinePx, about 5 cm at 2 m. The shading is
    // made at every step-th pixel, so only those windows are summed.
    constexpr int kWindowPx = 9, kBaselinePx = 4;
    const int step = options_.shading_step;
    cv::Mat out(depth.rows / step, depth.cols / step, CV_8UC1, cv::Scalar(0));
    const cv::Mat sums = boxSumsAtStep(depth, rays_.x, rays_.y, step, kWindowPx);
    // The windows' mean points, at the centres: a baseline of kBaselinePx is kBaselinePx / step shading pixels.
    cv::Mat points(out.size(), CV_32FC3);
    for (int y = 0; y < out.rows; ++y)
    {
        const cv::Vec4f* in = sums.ptr<cv::Vec4f>(y);
        cv::Vec3f* p = points.ptr<cv::Vec3f>(y);
        for (int x = 0; x < out.cols; ++x)
        {
            const float n = std::max(in[x][3], 1.f);
            p[x] = cv::Vec3f(in[x][0] / n, in[x][1] / n, in[x][2] / n);
        }
    }
    auto point = [&](int x, int y) {
        const cv::Vec3f& p = points.at<cv::Vec3f>(y, x);
        return Eigen::Vector3f(p[0], p[1], p[2]);
    };
    const Eigen::Vector3f light = kLight.cast<float>();
    const int b = std::max(1, kBaselinePx / step);
    const float min_valid = 0.5f * kWindowPx * kWindowPx;
    for (int y = b; y + b < out.rows; ++y)
    {
        const int v = y * step;
        const float* d0 = depth.ptr<float>(v);
        const float* dm = depth.ptr<float>(v - 1);
        const float* dp = depth.ptr<float>(v + 1);
        uint8_t* o = out.ptr<uint8_t>(y);
        for (int x = b; x + b < out.cols; ++x)
        {
            const int u = x * step;
            const float d = d0[u];
            if (d > 0)
            {
                // A contour's background side (a 4-neighbour nearer by more than 5 %) stays dark: the step is at
                // the foreground's edge.
                const float near = d * float(1 - kDiscontinuityRel);
                const float nb[4] = {d0[u - 1], d0[u + 1], dm[u], dp[u]};
                bool far_side = false;
                for (float n : nb) far_side |= n > 0 && n < near;
                if (far_side) continue;
            }
            // Holes between the map's points (most of the window valid) are shaded from their neighbours: left
            // dark, they would be speckles the line detector strings together.
            else if (sums.at<cv::Vec4f>(y, x)[3] < min_valid)
                continue;
            Eigen::Vector3f n = (point(x + b, y) - point(x - b, y)).cross(point(x, y + b) - point(x, y - b));
            const float norm = n.norm();
            if (!(norm > 0)) continue;
            n /= norm;
            if (n.dot(point(x, y)) > 0) n = -n;  // facing the camera
            o[x] = uint8_t(std::lround(128 + 127 * std::clamp(n.dot(light), -1.f, 1.f)));
        }
    }
    return out;
}

bool MapLineExtractor::isEdge(const cv::Mat& shading, const frontend::LineSegment& segment) const
{
    // Mean shading on either side of the segment (3 px away): a crease or a contour differs, a line the detector
    // found in the map's noise on one surface does not.
    const Eigen::Vector2f across(-segment.direction().y(), segment.direction().x());
    double side[2] = {0, 0};
    int count[2] = {0, 0};
    for (int s = 0; s < options_.samples; ++s)
    {
        const Eigen::Vector2f p = segment.p0 + (segment.p1 - segment.p0) * ((s + 0.5f) / float(options_.samples));
        for (int k = 0; k < 2; ++k)
        {
            const Eigen::Vector2f q = p + (k == 0 ? 3.f : -3.f) * across;
            const int u = int(std::lround(q.x())), v = int(std::lround(q.y()));
            if (u < 0 || v < 0 || u >= shading.cols || v >= shading.rows) continue;
            side[k] += shading.at<uint8_t>(v, u), ++count[k];
        }
    }
    if (count[0] < options_.samples / 2 || count[1] < options_.samples / 2) return false;
    return std::abs(side[0] / count[0] - side[1] / count[1]) >= options_.min_contrast;
}

std::optional<MapLine> MapLineExtractor::lift(const frontend::LineSegment& segment, const cv::Mat& depth,
                                              const Eigen::Isometry3d& T_world_cam) const
{
    // Along the segment, the surface on it; where a depth discontinuity lies within contour_band_px across it (a
    // contour: the detector places it a few pixels off, the shading is smoothed), the foreground pixel next to
    // the jump: the foreground's edge is the 3D line (the background's is only its shadow).
    const Eigen::Vector2f across(-segment.direction().y(), segment.direction().x());
    std::vector<Eigen::Vector3d> pts;
    const int band = int(std::ceil(options_.contour_band_px));
    std::vector<float> d(size_t(2 * band + 1));
    std::vector<cv::Point> px(d.size());
    for (int s = 0; s < options_.samples; ++s)
    {
        const Eigen::Vector2f p = segment.p0 + (segment.p1 - segment.p0) * ((s + 0.5f) / float(options_.samples));
        for (int k = -band; k <= band; ++k)
        {
            const int u = int(std::lround(p.x() + float(k) * across.x()));
            const int v = int(std::lround(p.y() + float(k) * across.y()));
            const bool inside = u >= 0 && v >= 0 && u < depth.cols && v < depth.rows;
            d[size_t(k + band)] = inside ? depth.at<float>(v, u) : 0.f;
            px[size_t(k + band)] = {u, v};
        }
        int pick = -1, pick_offset = 1 << 20;
        for (int k = 0; k + 1 < int(d.size()); ++k)
        {
            const float a = d[size_t(k)], b = d[size_t(k + 1)];
            if (a <= 0 || b <= 0 || std::abs(a - b) <= float(kDiscontinuityRel) * std::min(a, b)) continue;
            const int fg = a < b ? k : k + 1;
            if (std::abs(fg - band) < pick_offset) pick = fg, pick_offset = std::abs(fg - band);
        }
        if (pick < 0 && d[size_t(band)] > 0) pick = band;  // a crease: the pixel on the segment
        if (pick < 0) continue;
        pts.push_back(T_world_cam * (double(d[size_t(pick)]) * rays_.ray(px[size_t(pick)].x, px[size_t(pick)].y)));
    }
    if (int(pts.size()) < options_.min_support) return std::nullopt;
    // RANSAC over pairs (at most samples^2 / 2 of them): the line with the most points within tolerance_m.
    std::vector<char> best_in;
    size_t best_count = 0;
    for (size_t i = 0; i < pts.size(); ++i)
        for (size_t j = i + 1; j < pts.size(); ++j)
        {
            const Eigen::Vector3d dir = pts[j] - pts[i];
            if (dir.norm() < 1e-6) continue;
            const Eigen::Vector3d d = dir.normalized();
            std::vector<char> in(pts.size());
            size_t count = 0;
            for (size_t k = 0; k < pts.size(); ++k)
            {
                const Eigen::Vector3d w = pts[k] - pts[i];
                in[k] = (w - w.dot(d) * d).norm() < options_.tolerance_m;
                count += size_t(in[k]);
            }
            if (count > best_count) best_count = count, best_in = std::move(in);
        }
    if (int(best_count) < options_.min_support) return std::nullopt;
    MapLine line;
    for (size_t k = 0; k < pts.size(); ++k)
        if (best_in[k]) line.support_world.push_back(pts[k]);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : line.support_world) mean += p;
    mean /= double(line.support_world.size());
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (const auto& p : line.support_world) C += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C);
    line.point = mean;
    line.direction = eig.eigenvectors().col(2);
    // Ordered along the line (the association reads the projected direction from the first and last point).
    std::sort(line.support_world.begin(), line.support_world.end(),
              [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
                  return (a - mean).dot(line.direction) < (b - mean).dot(line.direction);
              });
    const double extent = (line.support_world.back() - line.support_world.front()).dot(line.direction);
    if (extent < options_.min_length_m) return std::nullopt;
    return line;
}

std::vector<estimation::LineFactorInput> associateMapLines(const std::vector<frontend::LineSegment>& camera_lines,
                                                           const std::vector<MapLine>& map_lines,
                                                           const core::CameraModel& camera,
                                                           const Eigen::Isometry3d& T_world_cam, double window_px,
                                                           double sigma_px, const MapLineOptions& options)
{
    // Every map line's support at the pose estimate (pixels; points behind the camera or far outside the image
    // are left out).
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    struct Projected
    {
        std::vector<Eigen::Vector2d> px;
        std::vector<const Eigen::Vector3d*> p_world;
    };
    std::vector<Projected> projected(map_lines.size());
    for (size_t m = 0; m < map_lines.size(); ++m)
        for (const auto& P : map_lines[m].support_world)
        {
            Eigen::Vector2d px;
            if (camera.project(T_cam_world * P, px, nullptr, 0.05) && camera.isInImage(px, -window_px))
                projected[m].px.push_back(px), projected[m].p_world.push_back(&P);
        }
    const double sin_max_angle = std::sin(options.max_angle_deg * M_PI / 180);
    const double sigma_assoc = std::max(window_px / 3, 1e-3);
    std::vector<estimation::LineFactorInput> out;
    for (const frontend::LineSegment& c : camera_lines)
    {
        const Eigen::Vector2d p0 = c.p0.cast<double>(), dir = c.direction().cast<double>();
        const double len = c.length();
        const Eigen::Vector3d l = c.homogeneous().cast<double>();
        struct Candidate
        {
            double rms;
            std::vector<Eigen::Vector3d> support;
        };
        std::vector<Candidate> candidates;
        for (const Projected& pm : projected)
        {
            if (pm.px.size() < 2) continue;
            const Eigen::Vector2d dm = pm.px.back() - pm.px.front();
            const double len_m = dm.norm();
            if (len_m < 1e-6 || std::abs(dir.x() * dm.y() - dir.y() * dm.x()) / len_m > sin_max_angle) continue;
            // The support points over the camera segment's extent: their distances to its line.
            Candidate cand{0, {}};
            double t_min = 1e9, t_max = -1e9;
            for (size_t k = 0; k < pm.px.size(); ++k)
            {
                const double t = (pm.px[k] - p0).dot(dir);
                if (t < -2 || t > len + 2) continue;
                const double e = l.dot(pm.px[k].homogeneous());
                cand.rms += e * e;
                cand.support.push_back(*pm.p_world[k]);
                t_min = std::min(t_min, t), t_max = std::max(t_max, t);
            }
            if (cand.support.size() < 3 || t_max - t_min < options.min_overlap * std::min(len, len_m)) continue;
            cand.rms = std::sqrt(cand.rms / double(cand.support.size()));
            if (cand.rms <= window_px) candidates.push_back(std::move(cand));
        }
        if (candidates.empty()) continue;
        std::sort(candidates.begin(), candidates.end(),
                  [](const Candidate& a, const Candidate& b) { return a.rms < b.rms; });
        if (int(candidates.size()) > options.max_candidates) candidates.resize(size_t(options.max_candidates));
        std::vector<double> p(candidates.size());
        double sum = 0;
        for (size_t i = 0; i < candidates.size(); ++i)
            sum += p[i] = std::exp(-0.5 * std::pow(candidates[i].rms / sigma_assoc, 2));
        estimation::LineFactorInput f;
        f.line_px = l;
        for (size_t i = 0; i < candidates.size(); ++i)
            if (sum > 0 && p[i] / sum >= options.min_probability)
                f.candidates.push_back({std::move(candidates[i].support), p[i] / sum});
        if (f.candidates.empty()) continue;
        double kept = 0;
        for (const auto& k : f.candidates) kept += k.probability;
        for (auto& k : f.candidates) k.probability /= kept;
        f.sigma_px = sigma_px * std::sqrt(std::max(1.0, double(f.candidates.front().support_map.size()) / 2));
        out.push_back(std::move(f));
    }
    return out;
}
}  // namespace quasiloc::tracking
