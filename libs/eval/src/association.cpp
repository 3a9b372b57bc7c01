#include <algorithm>
#include <cmath>
#include <numeric>
#include <quasiloc/core/error.h>
#include <quasiloc/eval/association.h>
#include <string>

namespace quasiloc::eval
{
namespace
{
std::vector<size_t> sortedOrder(const std::vector<double>& t)
{
    std::vector<size_t> order(t.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return t[a] < t[b]; });
    return order;
}
}  // namespace

Association associateByTime(const std::vector<double>& t_est, const std::vector<double>& t_gt, double max_dt_s)
{
    core::require(std::isfinite(max_dt_s) && max_dt_s >= 0, "association max_dt_s",
                  "must be a finite value >= 0, got " + std::to_string(max_dt_s));
    // Candidate pairs: for each estimate, the ground-truth poses in [t - max_dt, t + max_dt]
    // (binary search in the sorted ground-truth times).
    const std::vector<size_t> gt_order = sortedOrder(t_gt);
    std::vector<double> gt_sorted(t_gt.size());
    for (size_t k = 0; k < gt_order.size(); ++k) gt_sorted[k] = t_gt[gt_order[k]];
    std::vector<Match> candidates;
    for (size_t i = 0; i < t_est.size(); ++i)
    {
        auto it = std::lower_bound(gt_sorted.begin(), gt_sorted.end(), t_est[i] - max_dt_s);
        for (; it != gt_sorted.end() && *it <= t_est[i] + max_dt_s; ++it)
        {
            const size_t j = gt_order[static_cast<size_t>(it - gt_sorted.begin())];
            candidates.push_back({i, j, t_est[i] - t_gt[j]});
        }
    }
    std::sort(candidates.begin(), candidates.end(), [](const Match& a, const Match& b) {
        const double da = std::abs(a.dt_s), db = std::abs(b.dt_s);
        if (da != db) return da < db;
        if (a.est_index != b.est_index) return a.est_index < b.est_index;
        return a.gt_index < b.gt_index;
    });
    std::vector<char> est_used(t_est.size(), 0), gt_used(t_gt.size(), 0);
    Association out;
    for (const Match& c : candidates)
    {
        if (est_used[c.est_index] || gt_used[c.gt_index]) continue;
        est_used[c.est_index] = gt_used[c.gt_index] = 1;
        out.matches.push_back(c);
        out.max_abs_dt_s = std::max(out.max_abs_dt_s, std::abs(c.dt_s));
    }
    std::sort(out.matches.begin(), out.matches.end(),
              [](const Match& a, const Match& b) { return a.est_index < b.est_index; });
    for (size_t i = 0; i < t_est.size(); ++i)
        if (!est_used[i]) out.unmatched_est.push_back(i);
    out.unmatched_gt = t_gt.size() - out.matches.size();
    return out;
}

Association associate(const core::Trajectory& est, const core::Trajectory& gt, double max_dt_s)
{
    std::vector<double> te, tg;
    te.reserve(est.poses.size());
    tg.reserve(gt.poses.size());
    for (const auto& p : est.poses) te.push_back(p.t);
    for (const auto& p : gt.poses) tg.push_back(p.t);
    return associateByTime(te, tg, max_dt_s);
}

size_t dropDuplicateTimestamps(core::Trajectory& traj)
{
    auto& P = traj.poses;
    const size_t before = P.size();
    P.erase(std::unique(P.begin(), P.end(),
                        [](const core::TimedPose& a, const core::TimedPose& b) { return std::abs(a.t - b.t) < 1e-9; }),
            P.end());
    return before - P.size();
}

}  // namespace quasiloc::eval
