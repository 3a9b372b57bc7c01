#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
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
    std::stable_sort(pairs.begin(), pairs.end(),
                     [](const PosePair& a, const PosePair& b) { return a.t_est < b.t_est; });
    return pairs;
}

std::vector<PosePair> makeInterpolatedPairs(const core::Trajectory& est, const core::Trajectory& gt, double max_dt_s,
                                            Association& assoc)
{
    core::require(std::isfinite(max_dt_s) && max_dt_s >= 0, "association max_dt_s",
                  "must be a finite value >= 0, got " + std::to_string(max_dt_s));
    assoc = Association();
    const auto& G = gt.poses;
    std::vector<char> gt_used(G.size(), 0);
    std::vector<PosePair> pairs;
    for (size_t i = 0; i < est.poses.size(); ++i)
    {
        const double t = est.poses[i].t;
        const auto it =
            std::lower_bound(G.begin(), G.end(), t, [](const core::TimedPose& p, double tt) { return p.t < tt; });
        // The nearer of the samples around t (the later one on a tie).
        size_t nearest = G.size();
        double gap = std::numeric_limits<double>::infinity();
        if (it != G.end()) nearest = static_cast<size_t>(it - G.begin()), gap = it->t - t;
        if (it != G.begin() && t - (it - 1)->t < gap)
            nearest = static_cast<size_t>(it - G.begin()) - 1, gap = t - (it - 1)->t;
        mrpt::poses::CPose3D truth;
        if (!(gap <= max_dt_s) || !core::interpolatePose(gt, t, truth, max_dt_s))
        {
            assoc.unmatched_est.push_back(i);
            continue;
        }
        gt_used[nearest] = 1;
        const double dt = t - G[nearest].t;
        assoc.matches.push_back({i, nearest, dt});
        assoc.max_abs_dt_s = std::max(assoc.max_abs_dt_s, std::abs(dt));
        pairs.push_back({t, t, est.poses[i].pose, truth});
    }
    assoc.unmatched_gt = static_cast<size_t>(std::count(gt_used.begin(), gt_used.end(), 0));
    std::stable_sort(pairs.begin(), pairs.end(),
                     [](const PosePair& a, const PosePair& b) { return a.t_est < b.t_est; });
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

std::string toString(RpeUnit u)
{
    switch (u)
    {
        case RpeUnit::Metres: return "m";
        case RpeUnit::Seconds: return "s";
        case RpeUnit::Frames: return "frames";
    }
    return "?";
}

namespace
{
/** evo's consecutive pairs by path length: the indices where the path travelled since the previous such index (or
 *  since the first pose) first reaches `delta`, paired one after the other. */
std::vector<std::pair<size_t, size_t>> pairsByPath(const std::vector<PosePair>& pairs, double delta)
{
    std::vector<size_t> ids;
    double path = 0;
    for (size_t i = 0; i < pairs.size(); ++i)
    {
        if (i > 0) path += core::translationDistance(pairs[i].est, pairs[i - 1].est);
        if (path >= delta)
        {
            ids.push_back(i);
            path = 0;
        }
    }
    std::vector<std::pair<size_t, size_t>> out;
    for (size_t k = 1; k < ids.size(); ++k) out.emplace_back(ids[k - 1], ids[k]);
    return out;
}

/** Every i with the pose nearest in time to t_i + delta, within a tenth of delta (a gap in the data is no partner). */
std::vector<std::pair<size_t, size_t>> pairsByTime(const std::vector<PosePair>& pairs, double delta)
{
    std::vector<std::pair<size_t, size_t>> out;
    for (size_t i = 0; i < pairs.size(); ++i)
    {
        const double target = pairs[i].t_est + delta;
        const auto it = std::lower_bound(pairs.begin() + static_cast<long>(i), pairs.end(), target,
                                         [](const PosePair& p, double t) { return p.t_est < t; });
        const size_t k = static_cast<size_t>(it - pairs.begin());
        size_t best = 0;
        double best_gap = 0.1 * delta;
        bool found = false;
        for (size_t c : {k - 1, k})  // k >= i; when k == 0, k - 1 wraps and fails c < size
        {
            if (c <= i || c >= pairs.size()) continue;
            const double gap = std::abs(pairs[c].t_est - target);
            if (gap <= best_gap)
            {
                best_gap = gap;
                best = c;
                found = true;
            }
        }
        if (found) out.emplace_back(i, best);
    }
    return out;
}
}  // namespace

std::vector<std::pair<size_t, size_t>> rpeIndexPairs(const std::vector<PosePair>& pairs, const RpeDelta& delta)
{
    core::require(std::isfinite(delta.value) && delta.value > 0, "RPE delta",
                  "must be > 0, got " + std::to_string(delta.value));
    switch (delta.unit)
    {
        case RpeUnit::Metres: return pairsByPath(pairs, delta.value);
        case RpeUnit::Seconds: return pairsByTime(pairs, delta.value);
        case RpeUnit::Frames:
        {
            core::require(delta.value == std::floor(delta.value), "RPE delta in frames",
                          "must be a whole number, got " + std::to_string(delta.value));
            const size_t d = static_cast<size_t>(delta.value);
            std::vector<std::pair<size_t, size_t>> out;
            for (size_t i = 0; i + d < pairs.size(); ++i) out.emplace_back(i, i + d);
            return out;
        }
    }
    return {};
}

RpeResult computeRpe(const std::vector<PosePair>& pairs, const RpeDelta& delta)
{
    RpeResult r;
    r.delta = delta;
    std::vector<double> trans, rot;
    for (const auto& [i, j] : rpeIndexPairs(pairs, delta))
    {
        const auto& a = pairs[i];
        const auto& b = pairs[j];
        const mrpt::poses::CPose3D rel_gt = b.gt - a.gt;     // Q_i^-1 Q_j
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
