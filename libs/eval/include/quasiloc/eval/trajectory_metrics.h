#pragma once
// Absolute trajectory error (ATE) and relative pose error (RPE) of associated pose pairs.
// Map-based localization is judged in the map frame: the unaligned ATE is the primary figure; an
// SE(3) or Sim(3) Umeyama alignment is optional and only shows how much of the error is a global offset.
#include <mrpt/poses/CPose3D.h>

#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/eval/association.h>
#include <quasiloc/eval/error_stats.h>
#include <quasiloc/eval/umeyama.h>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::eval
{
enum class Alignment
{
    None,
    SE3,
    Sim3
};
/** The INI names of the alignments ([Eval] align): none, se3, sim3. */
const std::vector<std::pair<std::string, Alignment>>& alignmentNames();
std::string toString(Alignment a);

/** One associated pair: T_world_frame of the estimate and of the ground truth. */
struct PosePair
{
    double t_est = 0, t_gt = 0;
    mrpt::poses::CPose3D est, gt;
};

std::vector<PosePair> makePairs(const core::Trajectory& est, const core::Trajectory& gt, const Association& assoc);

/** Every estimate pose paired with the ground truth interpolated at its time (linear in position, slerp in rotation,
 *  between the two samples around it; the end sample just outside the ground truth), when the nearer sample lies
 *  within max_dt_s: the lookup quasiloc-track makes for its frames (dataset::poseAt). `gt` sorted by time. `assoc`
 *  receives the bookkeeping: one match per paired estimate with gt_index = the nearer sample, unmatched estimates,
 *  and the samples nearest to no paired estimate as unmatched_gt. Sorted by time. */
std::vector<PosePair> makeInterpolatedPairs(const core::Trajectory& est, const core::Trajectory& gt, double max_dt_s,
                                            Association& assoc);

/** S * T: the rotation becomes R_S R, the translation s R_S t + t_S. */
mrpt::poses::CPose3D applySimilarity(const Similarity3& S, const mrpt::poses::CPose3D& T);
/** Every estimate pose mapped by S (ground truth untouched). */
std::vector<PosePair> applySimilarity(const Similarity3& S, const std::vector<PosePair>& pairs);

struct AteResult
{
    Alignment alignment = Alignment::None;
    Similarity3 transform;  ///< T_gtworld_estworld applied to the estimate (identity for None)
    ErrorStats trans_m, rot_deg;
    std::vector<double> trans_errors_m, rot_errors_deg;  ///< per pair, in the order of the pairs
};

/** Translation error |t_est - t_gt| and rotation error angle(R_gt^T R_est) after the alignment.
 *  SE3/Sim3 need >= 3 pairs (InputError otherwise); the alignment uses positions only. */
AteResult computeAte(const std::vector<PosePair>& pairs, Alignment alignment);

/** How the RPE chooses its pose pairs (i, j), on the estimate's poses in time order, as evo does (pairs from the
 *  estimate, not the reference). */
enum class RpeUnit
{
    Metres,   ///< evo_rpe --delta d --delta_unit m: consecutive pairs of the poses where the estimate's travelled
              ///< path since the previous such pose first reaches d (evo filters.filter_pairs_by_path)
    Seconds,  ///< TUM evaluate_rpe.py --fixed_delta --delta d --delta_unit s (evo has no time unit): every pose i
              ///< with the pose j nearest in time to t_i + d, kept when |t_j - t_i - d| <= d / 10
    Frames    ///< evo_rpe --delta d --delta_unit f --all_pairs: every i with j = i + d
};
std::string toString(RpeUnit u);  ///< "m", "s", "frames"

struct RpeDelta
{
    double value = 1;  ///< > 0; a whole number for Frames
    RpeUnit unit = RpeUnit::Metres;
};

struct RpeResult
{
    RpeDelta delta;
    ErrorStats trans_m, rot_deg;  ///< count = number of (i, j) pose pairs used
};

/** The (i, j) index pairs of `delta` (see RpeUnit), i < j. Pairs must be sorted by time (makePairs does). */
std::vector<std::pair<size_t, size_t>> rpeIndexPairs(const std::vector<PosePair>& pairs, const RpeDelta& delta);

/** E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) (Q ground truth, P estimate, evo's and TUM's relative pose error) for every
 *  index pair of rpeIndexPairs; translation |t(E_ij)| in metres ("translation part") and rotation angle(E_ij) in
 *  degrees. */
RpeResult computeRpe(const std::vector<PosePair>& pairs, const RpeDelta& delta);

}  // namespace quasiloc::eval
