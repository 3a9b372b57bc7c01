#include <algorithm>
#include <cctype>
#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/eval/trajectory_metrics.h>

namespace quasiloc::eval
{
namespace
{
constexpr double kRadToDeg = 180.0 / M_PI;

Eigen::Vector3d positionOf(const mrpt::poses::CPose3D& T) { return {T.x(), T.y(), T.z()}; }
}  // namespace

const std::vector<std::pair<std::string, Alignment>>& alignmentNames()
{
    static const std::vector<std::pair<std::string, Alignment>> names = {
        {"none", Alignment::None}, {"se3", Alignment::SE3}, {"sim3", Alignment::Sim3}};
    return names;
}

std::string toString(Alignment a)
{
    for (const auto& [name, value] : alignmentNames())
        if (value == a) return name;
    return "?";
}

std::vector<PosePair> makePairs(const core::Trajectory& est, const core::Trajectory& gt, const Association& assoc)
{
    std::vector<PosePair> pairs;
    pairs.reserve(assoc.matches.size());
    for (const Match& m : assoc.matches)
    {
        const auto& e = est.poses.at(m.est_index);
        const auto& g = gt.poses.at(m.gt_index);
        pairs.push_back({e.t, g.t, e.pose, g.pose});
    }
    std::stable_sort(pairs.begin(), pairs.end(), [](const PosePair& a, const PosePair& b) { return a.t_est < b.t_est; });
    return pairs;
}

mrpt::poses::CPose3D applySimilarity(const Similarity3& S, const mrpt::poses::CPose3D& T)
{
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear() = S.R * T.getRotationMatrix().asEigen();
    out.translation() = S.apply(positionOf(T));
    return core::fromIsometry(out);
}

std::vector<PosePair> applySimilarity(const Similarity3& S, const std::vector<PosePair>& pairs)
{
    std::vector<PosePair> out = pairs;
    for (auto& p : out) p.est = applySimilarity(S, p.est);
    return out;
}

AteResult computeAte(const std::vector<PosePair>& pairs, Alignment alignment)
{
    AteResult r;
    r.alignment = alignment;
    if (alignment != Alignment::None)
    {
        core::require(pairs.size() >= 3, "ATE with " + toString(alignment) + " alignment",
                      "needs at least 3 associated poses, got " + std::to_string(pairs.size()));
        Eigen::Matrix3Xd src(3, pairs.size()), dst(3, pairs.size());
        for (size_t i = 0; i < pairs.size(); ++i)
        {
            src.col(i) = positionOf(pairs[i].est);
            dst.col(i) = positionOf(pairs[i].gt);
        }
        r.transform = umeyamaAlignment(src, dst, alignment == Alignment::Sim3);
    }
    r.trans_errors_m.reserve(pairs.size());
    r.rot_errors_deg.reserve(pairs.size());
    for (const auto& p : pairs)
    {
        const mrpt::poses::CPose3D est = alignment == Alignment::None ? p.est : applySimilarity(r.transform, p.est);
        r.trans_errors_m.push_back(core::translationDistance(est, p.gt));
        r.rot_errors_deg.push_back(core::rotationDistanceRad(p.gt, est) * kRadToDeg);
    }
    r.trans_m = computeStats(r.trans_errors_m);
    r.rot_deg = computeStats(r.rot_errors_deg);
    return r;
}

namespace
{
/** Index of the partner of pair i, or -1. */
long partnerOf(const std::vector<PosePair>& pairs, size_t i, const RpeDelta& d)
{
    if (d.frames > 0)
    {
        const size_t j = i + static_cast<size_t>(d.frames);
        return j < pairs.size() ? static_cast<long>(j) : -1;
    }
    const double target = pairs[i].t_gt + d.seconds;
    const auto it = std::lower_bound(pairs.begin() + static_cast<long>(i), pairs.end(), target,
                                     [](const PosePair& p, double t) { return p.t_gt < t; });
    const long k = static_cast<long>(it - pairs.begin());
    long best = -1;
    double best_gap = 0.5 * d.seconds;  // farther than half a step: a gap in the data, not a partner
    for (long c : {k - 1, k})
    {
        if (c <= static_cast<long>(i) || c >= static_cast<long>(pairs.size())) continue;
        const double gap = std::abs(pairs[static_cast<size_t>(c)].t_gt - target);
        if (gap <= best_gap)
        {
            best_gap = gap;
            best = c;
        }
    }
    return best;
}
}  // namespace

RpeResult computeRpe(const std::vector<PosePair>& pairs, const RpeDelta& delta)
{
    core::require((delta.seconds > 0) != (delta.frames > 0), "RPE delta",
                  "exactly one of the delta in seconds and the delta in frames must be > 0");
    RpeResult r;
    r.delta = delta;
    std::vector<double> trans, rot;
    for (size_t i = 0; i < pairs.size(); ++i)
    {
        const long j = partnerOf(pairs, i, delta);
        if (j < 0) continue;
        const auto& a = pairs[i];
        const auto& b = pairs[static_cast<size_t>(j)];
        const mrpt::poses::CPose3D rel_gt = b.gt - a.gt;     // G_i^-1 G_j
        const mrpt::poses::CPose3D rel_est = b.est - a.est;  // P_i^-1 P_j
        const mrpt::poses::CPose3D E = rel_est - rel_gt;     // rel_gt^-1 rel_est
        trans.push_back(E.translation().norm());
        rot.push_back(core::rotationDistanceRad(mrpt::poses::CPose3D(), E) * kRadToDeg);
    }
    r.trans_m = computeStats(trans);
    r.rot_deg = computeStats(rot);
    return r;
}

}  // namespace quasiloc::eval
