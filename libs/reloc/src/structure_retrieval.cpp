#include "structure_retrieval.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace quasiloc::reloc
{
OrientationGrid orientationGrid(const cv::Mat& image, const cv::Mat& valid, int cell_px,
                                const frontend::CrossModalDescriptorOptions& descriptors, double min_valid_share)
{
    OrientationGrid g;
    g.cols = image.cols / cell_px;
    g.rows = image.rows / cell_px;
    g.bins = descriptors.orientation_bins;
    if (g.cols <= 0 || g.rows <= 0) return g;
    const cv::Rect used(0, 0, g.cols * cell_px, g.rows * cell_px);
    const frontend::DescriptorField field =
        frontend::computeDescriptorField(image, frontend::DescriptorKind::OrientationField, descriptors);
    std::vector<cv::Mat> pooled(field.channels.size());
    for (size_t b = 0; b < pooled.size(); ++b)
        cv::resize(field.channels[b](used), pooled[b], cv::Size(g.cols, g.rows), 0, 0, cv::INTER_AREA);
    cv::Mat valid_share;
    if (!valid.empty()) cv::resize(valid(used) > 0, valid_share, cv::Size(g.cols, g.rows), 0, 0, cv::INTER_AREA);
    g.vectors.assign(size_t(g.cols * g.rows * g.bins), 0.f);
    g.valid.assign(size_t(g.cols * g.rows), 0);
    for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c < g.cols; ++c)
        {
            if (!valid_share.empty() && valid_share.at<uint8_t>(r, c) < min_valid_share * 255) continue;
            float* v = g.vectors.data() + size_t(r * g.cols + c) * size_t(g.bins);
            double sum = 0;
            for (int b = 0; b < g.bins; ++b) sum += v[b] = pooled[size_t(b)].at<float>(r, c);
            if (sum <= 1e-9) continue;
            const double mean = sum / g.bins;
            for (int b = 0; b < g.bins; ++b) v[b] = float((v[b] - mean) / sum);
            g.valid[size_t(r * g.cols + c)] = 1;
        }
    return g;
}

namespace
{
/** Normalised correlation of the camera grid with one view channel at one shift; false below the overlap. */
bool shiftCorrelation(const OrientationGrid& cam, const OrientationGrid& view, int dx, int dy, int min_cells,
                      double& correlation)
{
    double dot = 0, na = 0, nb = 0;
    int cells = 0;
    for (int r = std::max(0, -dy); r < std::min(cam.rows, view.rows - dy); ++r)
        for (int c = std::max(0, -dx); c < std::min(cam.cols, view.cols - dx); ++c)
        {
            if (!cam.isValid(c, r) || !view.isValid(c + dx, r + dy)) continue;
            const float *a = cam.cell(c, r), *b = view.cell(c + dx, r + dy);
            for (int k = 0; k < cam.bins; ++k) dot += a[k] * b[k], na += a[k] * a[k], nb += b[k] * b[k];
            ++cells;
        }
    if (cells < min_cells || na <= 0 || nb <= 0) return false;
    correlation = dot / std::sqrt(na * nb);
    return true;
}
}  // namespace

GridShift bestGridShift(const OrientationGrid& camera, const std::vector<const OrientationGrid*>& view_channels,
                        int max_dx, int max_dy, double min_overlap)
{
    int camera_cells = 0;
    for (uint8_t v : camera.valid) camera_cells += v;
    const int min_cells = std::max(1, int(std::ceil(min_overlap * camera_cells)));
    GridShift best;
    double sum_scores = 0, sum_squares = 0;
    int shifts = 0;
    for (int dy = -max_dy; dy <= max_dy; ++dy)
        for (int dx = -max_dx; dx <= max_dx; ++dx)
        {
            double sum = 0;
            int channels = 0;
            for (const OrientationGrid* view : view_channels)
            {
                double corr = 0;
                if (shiftCorrelation(camera, *view, dx, dy, min_cells, corr)) sum += corr, ++channels;
            }
            if (channels == 0) continue;
            const float score = float(sum / double(view_channels.size()));
            sum_scores += score, sum_squares += double(score) * score, ++shifts;
            if (score > best.score) best.score = score, best.dx = dx, best.dy = dy;
        }
    if (shifts > 1)
    {
        const double mean = sum_scores / shifts, var = std::max(0.0, sum_squares / shifts - mean * mean);
        best.peak = float((best.score - mean) / std::sqrt(var + 1e-6));
    }
    return best;
}

}  // namespace quasiloc::reloc
