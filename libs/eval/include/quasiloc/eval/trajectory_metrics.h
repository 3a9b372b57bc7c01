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

/** The RPE step: exactly one of them is > 0. */
struct RpeDelta
{
    double seconds = 0;  ///< partner = the pair whose time is nearest to t_i + seconds, within seconds/2
    int frames = 0;      ///< partner = the pair `frames` later in the list of associated pairs
};

struct RpeResult
{
    RpeDelta delta;
    ErrorStats trans_m, rot_deg;  ///< count = number of (i, j) pose pairs used
};

/** E_ij = (G_i^-1 G_j)^-1 (P_i^-1 P_j) for every i and its partner j; translation |t(E_ij)| in metres and
 *  rotation angle(E_ij) in degrees. Pairs must be sorted by time (makePairs does). */
RpeResult computeRpe(const std::vector<PosePair>& pairs, const RpeDelta& delta);

}  // namespace quasiloc::eval
