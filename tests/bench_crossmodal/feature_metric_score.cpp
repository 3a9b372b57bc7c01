#include "feature_metric_score.h"

#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>

namespace quasiloc::bench
{
frontend::DenseMap centredDenseMap(const frontend::DenseMap& map, const std::vector<uint8_t>& valid_cells)
{
    core::require(!map.empty(), "feature-metric score", "the dense feature map is empty (enable [Features] dense_map)");
    frontend::DenseMap out = map;
    out.data = map.data.clone();
    const int C = out.data.cols;
    std::vector<double> mean(size_t(C), 0.0);
    int n = 0;
    for (int r = 0; r < out.data.rows; ++r)
    {
        if (!valid_cells.empty() && !valid_cells[size_t(r)]) continue;
        const float* v = out.data.ptr<float>(r);
        for (int c = 0; c < C; ++c) mean[size_t(c)] += v[c];
        ++n;
    }
    for (double& m : mean) m /= std::max(1, n);
    for (int r = 0; r < out.data.rows; ++r)
    {
        float* v = out.data.ptr<float>(r);
        double norm = 0;
        for (int c = 0; c < C; ++c) v[c] = float(v[c] - mean[size_t(c)]), norm += double(v[c]) * v[c];
        const float s = norm > 1e-12 ? float(1.0 / std::sqrt(norm)) : 0.f;
        for (int c = 0; c < C; ++c) v[c] *= s;
    }
    return out;
}

FeatureMetricModel buildFeatureMetricModel(const frontend::DenseMap& quasi_dense, const cv::Mat& depth,
                                           const cv::Mat& valid, const core::CameraModel& camera,
                                           const Eigen::Isometry3d& T_world_cam)
{
    core::require(!quasi_dense.empty(), "feature-metric model", "the quasi-image has no dense feature map");
    core::require(depth.type() == CV_32FC1 && valid.type() == CV_8UC1 && depth.size() == valid.size(),
                  "feature-metric model", "depth must be CV_32FC1 and valid CV_8UC1 of the same size");
    // Cells whose centre pixel has a depth: the map is seen there.
    std::vector<uint8_t> cell_valid(size_t(quasi_dense.data.rows), 0);
    std::vector<int> cells;
    for (int cy = 0; cy < quasi_dense.rows_cells; ++cy)
        for (int cx = 0; cx < quasi_dense.cols_cells; ++cx)
        {
            const int x = int(std::lround(cx * quasi_dense.stride + quasi_dense.offset));
            const int y = int(std::lround(cy * quasi_dense.stride + quasi_dense.offset));
            if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows || !valid.at<uint8_t>(y, x)) continue;
            cell_valid[size_t(cy * quasi_dense.cols_cells + cx)] = 1;
            cells.push_back(cy * quasi_dense.cols_cells + cx);
        }
    FeatureMetricModel m;
    if (cells.empty()) return m;
    const frontend::DenseMap centred = centredDenseMap(quasi_dense, cell_valid);
    m.descriptors.create(int(cells.size()), centred.data.cols, CV_32F);
    int row = 0;
    for (size_t i = 0; i < cells.size(); ++i)
    {
        const int cell = cells[i], cx = cell % quasi_dense.cols_cells, cy = cell / quasi_dense.cols_cells;
        const double u = cx * quasi_dense.stride + quasi_dense.offset, v = cy * quasi_dense.stride + quasi_dense.offset;
        const float z = depth.at<float>(int(std::lround(v)), int(std::lround(u)));
        m.points_world.push_back(T_world_cam * (double(z) * camera.unproject({u, v})));
        centred.data.row(cell).copyTo(m.descriptors.row(row++));
    }
    return m;
}

double featureMetricScore(const frontend::DenseMap& D, const FeatureMetricModel& model, const core::CameraModel& camera,
                          const Eigen::Isometry3d& T_world_cam)
{
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    const int C = D.data.cols;
    double sum = 0;
    for (size_t i = 0; i < model.points_world.size(); ++i)
    {
        Eigen::Vector2d u;
        if (!camera.project(T_cam_world * model.points_world[i], u, nullptr, 0.1)) continue;
        const double gx = (u.x() - D.offset) / D.stride, gy = (u.y() - D.offset) / D.stride;
        if (gx < 0 || gy < 0 || gx > D.cols_cells - 1 || gy > D.rows_cells - 1) continue;
        const int x0 = std::min(int(gx), D.cols_cells - 2), y0 = std::min(int(gy), D.rows_cells - 2);
        const float ax = float(gx - x0), ay = float(gy - y0);
        const float w[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
        const int rows[4] = {y0 * D.cols_cells + x0, y0 * D.cols_cells + x0 + 1, (y0 + 1) * D.cols_cells + x0,
                             (y0 + 1) * D.cols_cells + x0 + 1};
        // Interpolate the camera's descriptor, then renormalise: a blend of unit vectors is shorter than a unit
        // vector, which without this would favour poses that put the points on cell centres (the model's own pose).
        const float* d = model.descriptors.ptr<float>(int(i));
        float dot = 0, norm2 = 0;
        for (int c = 0; c < C; ++c)
        {
            const float v = w[0] * D.data.ptr<float>(rows[0])[c] + w[1] * D.data.ptr<float>(rows[1])[c] +
                            w[2] * D.data.ptr<float>(rows[2])[c] + w[3] * D.data.ptr<float>(rows[3])[c];
            dot += d[c] * v;
            norm2 += v * v;
        }
        const float s = norm2 > 1e-12f ? dot / std::sqrt(norm2) : 0.f;
        sum += s;
    }
    return model.points_world.empty() ? 0.0 : sum / double(model.points_world.size());
}

}  // namespace quasiloc::bench
