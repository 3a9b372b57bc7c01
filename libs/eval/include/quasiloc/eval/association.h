#pragma once
// Timestamp association of two pose streams (estimate and ground truth), as TUM's associate.py does it:
// every pair (estimate i, ground truth j) with |t_i - t_j| <= max_dt_s is a candidate; candidates are
// taken greedily by increasing |dt| and each pose is used at most once (one-to-one). Unlike associate.py
// the bound is inclusive and ties are broken by index, so the result is deterministic.
#include <cstddef>
#include <quasiloc/core/trajectory_io.h>
#include <vector>

namespace quasiloc::eval
{
struct Match
{
    size_t est_index = 0;  ///< index into the estimate times
    size_t gt_index = 0;   ///< index into the ground-truth times
    double dt_s = 0;       ///< t_est - t_gt
};

struct Association
{
    std::vector<Match> matches;         ///< sorted by est_index
    std::vector<size_t> unmatched_est;  ///< estimate indices with no partner, sorted
    size_t unmatched_gt = 0;            ///< ground-truth poses not used by any match
    double max_abs_dt_s = 0;            ///< largest |dt| among the matches (0 when none)
};

/** Times need not be sorted. max_dt_s must be >= 0 (InputError otherwise). Cost O(N log N + K log K)
 *  with K the number of candidate pairs, small when max_dt_s is below the sampling period. */
Association associateByTime(const std::vector<double>& t_est, const std::vector<double>& t_gt, double max_dt_s);

/** Association of the poses of two trajectories. */
Association associate(const core::Trajectory& est, const core::Trajectory& gt, double max_dt_s);

/** Removes poses whose timestamp equals (to 1 ns) that of the previous pose in a time-sorted trajectory,
 *  keeping the first; returns how many were removed. EuRoC ground truth repeats its first and last rows. */
size_t dropDuplicateTimestamps(core::Trajectory& traj);

}  // namespace quasiloc::eval
