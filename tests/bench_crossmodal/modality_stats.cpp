#include "modality_stats.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/staged_output.h>
#include <random>
#include <sstream>

#include "rank_stats.h"

namespace quasiloc::bench
{
namespace
{
struct CellWinner
{
    float depth = 0;
    uint32_t point = 0;
    Eigen::Vector2f px = Eigen::Vector2f::Zero();
};

/** The nearest map point per cell_px x cell_px cell at the frame's pose. */
std::vector<CellWinner> zBufferedCells(const QueryFrame& frame, const core::CameraModel& cam, const map::LidarMap& m,
                                       const ModalityOptions& o)
{
    const int cw = (cam.width + o.cell_px - 1) / o.cell_px, ch = (cam.height + o.cell_px - 1) / o.cell_px;
    std::vector<CellWinner> cells(size_t(cw) * ch);
    const Eigen::Isometry3d T_cam_world = frame.T_world_cam.inverse();
    const Eigen::Matrix3f R = T_cam_world.linear().cast<float>();
    const Eigen::Vector3f t = T_cam_world.translation().cast<float>();
    for (size_t i = 0; i < m.size(); ++i)
    {
        const Eigen::Vector3f p = R * m.point(i) + t;
        if (p.z() < o.min_depth_m || p.z() > o.max_depth_m) continue;
        Eigen::Vector2d u;
        if (!cam.project(p.cast<double>(), u) || !cam.isInImage(u, 1.0)) continue;
        CellWinner& c = cells[size_t(int(u.y()) / o.cell_px) * cw + size_t(int(u.x()) / o.cell_px)];
        if (c.depth > 0 && c.depth <= p.z()) continue;
        c = {p.z(), uint32_t(i), u.cast<float>()};
    }
    cells.erase(std::remove_if(cells.begin(), cells.end(), [](const CellWinner& c) { return c.depth <= 0; }),
                cells.end());
    return cells;
}

cv::Mat greyOf(const cv::Mat& image)
{
    cv::Mat g;
    if (image.channels() == 3)
        cv::cvtColor(image, g, cv::COLOR_BGR2GRAY);
    else
        g = image;
    return g;
}

float bilinear(const cv::Mat& f32, const Eigen::Vector2f& u)
{
    const float x = std::clamp(u.x(), 0.f, float(f32.cols - 1.001)),
                y = std::clamp(u.y(), 0.f, float(f32.rows - 1.001));
    const int x0 = int(x), y0 = int(y);
    const float tx = x - x0, ty = y - y0;
    const float a = f32.at<float>(y0, x0) * (1 - tx) + f32.at<float>(y0, x0 + 1) * tx;
    const float b = f32.at<float>(y0 + 1, x0) * (1 - tx) + f32.at<float>(y0 + 1, x0 + 1) * tx;
    return a * (1 - ty) + b * ty;
}

/** Gaussian smoothing of `value` over the pixels where `valid` is set (normalised convolution). */
cv::Mat smoothValid(const cv::Mat& value, const cv::Mat& valid, double sigma)
{
    cv::Mat w, vw, num, den;
    valid.convertTo(w, CV_32F, 1.0 / 255);
    cv::multiply(value, w, vw);
    cv::GaussianBlur(vw, num, cv::Size(0, 0), sigma);
    cv::GaussianBlur(w, den, cv::Size(0, 0), sigma);
    cv::Mat out = cv::Mat::zeros(value.size(), CV_32F);
    for (int y = 0; y < out.rows; ++y)
        for (int x = 0; x < out.cols; ++x)
            if (den.at<float>(y, x) > 1e-3f) out.at<float>(y, x) = num.at<float>(y, x) / den.at<float>(y, x);
    return out;
}

struct Gradient
{
    cv::Mat gx, gy, mag;  // CV_32F
};

Gradient gradientOf(const cv::Mat& f32)
{
    Gradient g;
    cv::Sobel(f32, g.gx, CV_32F, 1, 0, 3);
    cv::Sobel(f32, g.gy, CV_32F, 0, 1, 3);
    cv::magnitude(g.gx, g.gy, g.mag);
    return g;
}

std::vector<cv::Point> maskPixels(const cv::Mat& mask)
{
    std::vector<cv::Point> px;
    cv::findNonZero(mask, px);
    return px;
}

double percentile(const cv::Mat& f32, const std::vector<cv::Point>& px, double q)
{
    std::vector<float> v;
    v.reserve(px.size());
    for (const auto& p : px) v.push_back(f32.at<float>(p));
    if (v.empty()) return 0;
    const size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    return v[k];
}

/** Weighted mean of cos(2 (theta_a - theta_b)) over px; b's gradients taken at pixel perm[i] when given. */
double orientationAgreement(const Gradient& a, const Gradient& b, const std::vector<cv::Point>& px,
                            const std::vector<size_t>* perm)
{
    const double na = std::max(1e-9, percentile(a.mag, px, 0.9)), nb = std::max(1e-9, percentile(b.mag, px, 0.9));
    double sum = 0, wsum = 0;
    for (size_t i = 0; i < px.size(); ++i)
    {
        const cv::Point pa = px[i], pb = perm ? px[(*perm)[i]] : px[i];
        const double ma = a.mag.at<float>(pa), mb = b.mag.at<float>(pb);
        if (ma <= 0 || mb <= 0) continue;
        const double w = std::min(1.0, ma / na) * std::min(1.0, mb / nb);
        const double ax = a.gx.at<float>(pa), ay = a.gy.at<float>(pa), bx = b.gx.at<float>(pb), by = b.gy.at<float>(pb);
        const double cos2 = ((ax * ax - ay * ay) * (bx * bx - by * by) + 4 * ax * ay * bx * by) / (ma * ma * mb * mb);
        sum += w * cos2, wsum += w;
    }
    return wsum > 0 ? sum / wsum : NAN;
}

/** Spearman of a's magnitude at p + shift and b's at p, over every second pixel and row of px. */
double magnitudeCorrelation(const cv::Mat& a_mag, const cv::Mat& b_mag, const std::vector<cv::Point>& px,
                            cv::Point shift)
{
    std::vector<double> va, vb;
    const cv::Rect inside(0, 0, a_mag.cols, a_mag.rows);
    for (const cv::Point& p : px)
    {
        if ((p.x | p.y) & 1) continue;
        const cv::Point q = p + shift;
        if (!inside.contains(q)) continue;
        va.push_back(a_mag.at<float>(q)), vb.push_back(b_mag.at<float>(p));
    }
    return spearman(va, vb);
}

double meanOverShifts(const std::vector<cv::Point>& shifts, const std::function<double(cv::Point)>& f)
{
    double s = 0;
    int n = 0;
    for (const cv::Point& d : shifts)
    {
        const double v = f(d);
        if (std::isfinite(v)) s += v, ++n;
    }
    return n ? s / n : NAN;
}

/** Canny edges from float derivatives (thresholds: the larger of the 90th percentile of the magnitude over px and
 *  min_high, and half of it); derivatives outside `keep` (if given) are zeroed. */
cv::Mat cannyFrom(const Gradient& g, const std::vector<cv::Point>& px, const cv::Mat& keep, double min_high)
{
    const double hi = std::max({1e-6, min_high, percentile(g.mag, px, 0.9)});
    const double scale = 1000.0 / std::max(hi, 1e-9);  // hi maps to 1000 in 16 bits
    cv::Mat dx, dy, edges;
    g.gx.convertTo(dx, CV_16S, scale);
    g.gy.convertTo(dy, CV_16S, scale);
    if (!keep.empty())
    {
        dx.setTo(0, keep == 0);
        dy.setTo(0, keep == 0);
    }
    cv::Canny(dx, dy, edges, 500, 1000, true);
    return edges;
}

/** Share of the edge pixels e(p + shift), p in px, that lie within r of a discontinuity (dist(p) <= r). */
double shareNear(const cv::Mat& edges, const cv::Mat& dist, const std::vector<cv::Point>& px, cv::Point shift, double r,
                 size_t* count = nullptr)
{
    const cv::Rect inside(0, 0, edges.cols, edges.rows);
    size_t n = 0, near = 0;
    for (const cv::Point& p : px)
    {
        const cv::Point q = p + shift;
        if (!inside.contains(q) || !edges.at<uint8_t>(q)) continue;
        ++n;
        near += dist.at<float>(p) <= r;
    }
    if (count) *count = n;
    return n ? double(near) / double(n) : NAN;
}

double density(const cv::Mat& dist, const std::vector<cv::Point>& px, double r)
{
    size_t near = 0;
    for (const cv::Point& p : px) near += dist.at<float>(p) <= r;
    return px.empty() ? NAN : double(near) / double(px.size());
}

/** Distance of every pixel to the nearest set pixel of `marks`. */
cv::Mat distanceTo(const cv::Mat& marks)
{
    cv::Mat inv = marks == 0, dist;
    cv::distanceTransform(inv, dist, cv::DIST_L2, 3);
    return dist;
}

/** The planes every structure statistic reads. */
struct StructurePlanes
{
    cv::Mat grey8, mask, log_depth, valid;
    Gradient cam, refl, depth;
    std::vector<cv::Point> px;
    cv::Mat cam_edges, refl_edges, depth_disc;
};

StructurePlanes structurePlanes(const QueryFrame& frame, const core::CameraModel& cam, quasi::QuasiRenderer& renderer,
                                const ModalityOptions& o)
{
    StructurePlanes s;
    quasi::QuasiImage q;
    renderer.render(core::fromIsometry(frame.T_world_cam), cam, q, false);
    s.grey8 = greyOf(frame.image);
    s.valid = q.valid;
    cv::Mat eroded;
    cv::erode(q.valid, eroded, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
    eroded.rowRange(0, 2).setTo(0), eroded.rowRange(eroded.rows - 2, eroded.rows).setTo(0);
    eroded.colRange(0, 2).setTo(0), eroded.colRange(eroded.cols - 2, eroded.cols).setTo(0);
    s.mask = eroded;
    s.px = maskPixels(s.mask);

    cv::Mat grey, grey_blur;
    s.grey8.convertTo(grey, CV_32F);
    cv::GaussianBlur(grey, grey_blur, cv::Size(0, 0), o.blur_sigma_px);
    s.cam = gradientOf(grey_blur);
    s.log_depth = cv::Mat::zeros(q.depth.size(), CV_32F);
    for (int y = 0; y < q.depth.rows; ++y)
        for (int x = 0; x < q.depth.cols; ++x)
            if (q.valid.at<uint8_t>(y, x))
                s.log_depth.at<float>(y, x) = std::log(std::max(q.depth.at<float>(y, x), 1e-3f));
    s.refl = gradientOf(smoothValid(q.reflectivity, q.valid, o.blur_sigma_px));
    s.depth = gradientOf(smoothValid(s.log_depth, q.valid, o.blur_sigma_px));

    std::vector<cv::Point> all_px;
    cv::findNonZero(cv::Mat(s.grey8.size(), CV_8U, cv::Scalar(255)), all_px);
    s.cam_edges = cannyFrom(s.cam, all_px, cv::Mat(), 0.0);
    s.refl_edges = cannyFrom(s.refl, s.px, s.mask, 0.0);
    // A step of depth_jump in log depth gives a Sobel response of about 4 * depth_jump after the smoothing.
    s.depth_disc = cannyFrom(s.depth, s.px, s.mask, 4 * o.depth_jump);
    return s;
}
}  // namespace

FrameModalityStats measureFrame(const QueryFrame& frame, const core::CameraModel& cam, const map::LidarMap& m,
                                const std::vector<uint8_t>& labels, quasi::QuasiRenderer& renderer,
                                const ModalityOptions& o, uint32_t seed)
{
    FrameModalityStats r;
    // Values: grey level against reflectivity.
    const cv::Mat grey8 = greyOf(frame.image);
    cv::Mat grey;
    grey8.convertTo(grey, CV_32F);
    std::vector<double> g_all, r_all, g_half[2], r_half[2];
    std::array<std::vector<double>, kClasses> g_cls, r_cls;
    for (const CellWinner& c : zBufferedCells(frame, cam, m, o))
    {
        const double g = bilinear(grey, c.px), refl = m.reflectivity(c.point);
        g_all.push_back(g), r_all.push_back(refl);
        const int lower = c.px.y() >= 0.5f * float(cam.height);
        g_half[lower].push_back(g), r_half[lower].push_back(refl);
        const int k = std::min<int>(labels[c.point], kClasses - 1);
        g_cls[k].push_back(g), r_cls[k].push_back(refl);
    }
    r.points_all = g_all.size();
    r.grey_refl_all = spearman(g_all, r_all, o.min_points);
    r.grey_refl_upper = spearman(g_half[0], r_half[0], o.min_points);
    r.grey_refl_lower = spearman(g_half[1], r_half[1], o.min_points);
    for (int k = 0; k < kClasses; ++k)
    {
        r.points_class[k] = g_cls[k].size();
        r.grey_refl_class[k] = spearman(g_cls[k], r_cls[k], o.min_points);
    }

    // Structure.
    const StructurePlanes s = structurePlanes(frame, cam, renderer, o);
    r.valid_fraction = double(s.px.size()) / double(s.mask.total());
    if (s.px.size() < 100) return r;
    std::vector<size_t> perm(s.px.size());
    std::iota(perm.begin(), perm.end(), size_t(0));
    std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
    r.orient_refl = orientationAgreement(s.cam, s.refl, s.px, nullptr);
    r.orient_refl_chance = orientationAgreement(s.cam, s.refl, s.px, &perm);
    r.orient_depth = orientationAgreement(s.cam, s.depth, s.px, nullptr);
    r.orient_depth_chance = orientationAgreement(s.cam, s.depth, s.px, &perm);
    r.magnitude_refl = magnitudeCorrelation(s.cam.mag, s.refl.mag, s.px, {0, 0});
    r.magnitude_depth = magnitudeCorrelation(s.cam.mag, s.depth.mag, s.px, {0, 0});
    r.magnitude_refl_shifted =
        meanOverShifts(o.shifts, [&](cv::Point d) { return magnitudeCorrelation(s.cam.mag, s.refl.mag, s.px, d); });
    r.magnitude_depth_shifted =
        meanOverShifts(o.shifts, [&](cv::Point d) { return magnitudeCorrelation(s.cam.mag, s.depth.mag, s.px, d); });

    const cv::Mat dist_depth = distanceTo(s.depth_disc), dist_refl = distanceTo(s.refl_edges);
    r.edges_depth = shareNear(s.cam_edges, dist_depth, s.px, {0, 0}, o.edge_radius_px, &r.camera_edges);
    r.edges_refl = shareNear(s.cam_edges, dist_refl, s.px, {0, 0}, o.edge_radius_px);
    r.edges_depth_shifted = meanOverShifts(
        o.shifts, [&](cv::Point d) { return shareNear(s.cam_edges, dist_depth, s.px, d, o.edge_radius_px); });
    r.edges_refl_shifted = meanOverShifts(
        o.shifts, [&](cv::Point d) { return shareNear(s.cam_edges, dist_refl, s.px, d, o.edge_radius_px); });
    r.depth_density = density(dist_depth, s.px, o.edge_radius_px);
    r.refl_density = density(dist_refl, s.px, o.edge_radius_px);
    return r;
}

void writePairsCsv(const std::string& path, const QueryFrame& frame, const core::CameraModel& cam,
                   const map::LidarMap& m, const std::vector<uint8_t>& labels, const ModalityOptions& o)
{
    cv::Mat grey;
    greyOf(frame.image).convertTo(grey, CV_32F);
    std::ostringstream csv;
    csv << "u,v,depth_m,grey,reflectivity,class,point\n";
    for (const CellWinner& c : zBufferedCells(frame, cam, m, o))
        csv << c.px.x() << "," << c.px.y() << "," << c.depth << "," << bilinear(grey, c.px) << ","
            << m.reflectivity(c.point) << "," << int(labels[c.point]) << "," << c.point << "\n";
    core::writeTextFileAtomically(path, csv.str());
}

cv::Scalar classColour(int c)
{
    static const cv::Scalar colours[kClasses] = {{128, 128, 128}, {255, 255, 255}, {0, 140, 255},
                                                 {0, 200, 0},     {255, 0, 255},   {255, 255, 0}};
    return colours[std::clamp(c, 0, kClasses - 1)];
}

void writeClassOverlay(const std::string& path, const QueryFrame& frame, const core::CameraModel& cam,
                       const map::LidarMap& m, const std::vector<uint8_t>& labels, quasi::QuasiRenderer& renderer,
                       const ModalityOptions& o)
{
    const cv::Mat grey8 = greyOf(frame.image);
    cv::Mat classes, structure;
    cv::cvtColor(grey8, classes, cv::COLOR_GRAY2BGR);
    for (const CellWinner& c : zBufferedCells(frame, cam, m, o))
        cv::circle(classes, cv::Point(int(c.px.x()), int(c.px.y())), 1, classColour(labels[c.point]), -1);
    const StructurePlanes s = structurePlanes(frame, cam, renderer, o);
    cv::Mat dim = grey8 / 2;
    cv::cvtColor(dim, structure, cv::COLOR_GRAY2BGR);
    structure.setTo(cv::Scalar(0, 200, 0), s.depth_disc);
    structure.setTo(cv::Scalar(255, 80, 0), s.refl_edges);
    structure.setTo(cv::Scalar(0, 0, 255), s.cam_edges & s.mask);
    cv::Mat out;
    cv::vconcat(classes, structure, out);
    cv::imwrite(path, out);
}

}  // namespace quasiloc::bench
