// Keypoint budget with spatial spreading: a per-cell quota first (so texture-rich regions cannot take the
// whole budget, which matters for pose conditioning), then the best leftovers fill what empty cells left.
#include <algorithm>
#include <numeric>
#include <quasiloc/frontend/features.h>

namespace quasiloc::frontend
{
std::vector<int> spreadKeypointIndices(const std::vector<cv::KeyPoint>& kps, cv::Size size, int budget, int grid_cols,
                                       int grid_rows)
{
    if (budget <= 0 || kps.empty()) return {};
    std::vector<int> order(kps.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return kps[a].response > kps[b].response; });
    if (int(kps.size()) <= budget) return order;
    const int cells = grid_cols * grid_rows;
    const int quota = std::max(1, budget / cells);
    std::vector<int> used(cells, 0);
    std::vector<char> taken(kps.size(), 0);
    std::vector<int> out;
    out.reserve(budget);
    for (int i : order)
    {
        const int cx = std::clamp(int(kps[i].pt.x * grid_cols / std::max(1, size.width)), 0, grid_cols - 1);
        const int cy = std::clamp(int(kps[i].pt.y * grid_rows / std::max(1, size.height)), 0, grid_rows - 1);
        int& u = used[cy * grid_cols + cx];
        if (u < quota && int(out.size()) < budget)
        {
            ++u;
            taken[i] = 1;
            out.push_back(i);
        }
    }
    for (int i : order)
    {
        if (int(out.size()) >= budget) break;
        if (!taken[i]) out.push_back(i);
    }
    return out;
}

std::vector<cv::KeyPoint> spreadKeypoints(const std::vector<cv::KeyPoint>& kps, cv::Size size, int budget,
                                          int grid_cols, int grid_rows)
{
    std::vector<cv::KeyPoint> out;
    for (int i : spreadKeypointIndices(kps, size, budget, grid_cols, grid_rows)) out.push_back(kps[size_t(i)]);
    return out;
}
}  // namespace quasiloc::frontend
