// Multi-frame stereo queries: the clouds of a span of frames joined into the newest camera (stereo_span.h).
#include <quasiloc/reloc/stereo_span.h>

#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace quasiloc::reloc
{
namespace
{
struct VoxelHash
{
    size_t operator()(const Eigen::Vector3i& v) const
    {
        return size_t(int64_t(v.x()) * 73856093 ^ int64_t(v.y()) * 19349663 ^ int64_t(v.z()) * 83492791);
    }
};
}  // namespace

std::vector<Eigen::Vector3f> joinClouds(const std::vector<const std::vector<Eigen::Vector3f>*>& clouds,
                                        const std::vector<Eigen::Isometry3d>& T_query_cloud, double voxel_m,
                                        size_t max_points)
{
    std::unordered_set<Eigen::Vector3i, VoxelHash> taken;
    std::vector<Eigen::Vector3f> out;
    const float inv = voxel_m > 0 ? float(1.0 / voxel_m) : 1.0f;
    for (size_t c = 0; c < clouds.size() && c < T_query_cloud.size(); ++c)
    {
        const Eigen::Matrix3f R = T_query_cloud[c].linear().cast<float>();
        const Eigen::Vector3f t = T_query_cloud[c].translation().cast<float>();
        for (const Eigen::Vector3f& p : *clouds[c])
        {
            const Eigen::Vector3f q = R * p + t;
            const Eigen::Vector3i key(int(std::floor(q.x() * inv)), int(std::floor(q.y() * inv)),
                                      int(std::floor(q.z() * inv)));
            if (voxel_m <= 0 || taken.insert(key).second) out.push_back(q);
        }
    }
    if (max_points > 0 && out.size() > max_points)
    {
        const size_t k = (out.size() + max_points - 1) / max_points;
        std::vector<Eigen::Vector3f> thinned;
        for (size_t i = 0; i < out.size(); i += k) thinned.push_back(out[i]);
        out.swap(thinned);
    }
    return out;
}

void StereoSpan::add(SpanFrame frame)
{
    frames_kept_.push_back(std::move(frame));
    while (frames_kept_.size() > size_t(frames_)) frames_kept_.pop_front();
}

JoinedClouds StereoSpan::join(double voxel_m, size_t max_points, size_t max_place_points) const
{
    JoinedClouds out;
    if (frames_kept_.empty()) return out;
    std::vector<const std::vector<Eigen::Vector3f>*> points, place_points;
    std::vector<Eigen::Isometry3d> poses;
    Eigen::Isometry3d T_newest_k = Eigen::Isometry3d::Identity();
    double oldest_t = frames_kept_.back().t;
    for (size_t i = frames_kept_.size(); i-- > 0;)
    {
        const SpanFrame& f = frames_kept_[i];
        ++out.linked_frames;
        if (f.has_clouds)
        {
            points.push_back(&f.points);
            place_points.push_back(&f.place_points);
            poses.push_back(T_newest_k);
            oldest_t = f.t;
            out.T_newest_oldest = T_newest_k;
            ++out.frames;
        }
        if (!f.linked || i == 0) break;
        out.path_m += f.T_prev_this.translation().norm();
        T_newest_k = T_newest_k * f.T_prev_this.inverse();  // the frame before, in the newest camera
    }
    out.oldest_t = oldest_t;
    out.span_s = frames_kept_.back().t - oldest_t;
    out.points = joinClouds(points, poses, voxel_m, max_points);
    out.place_points = joinClouds(place_points, poses, voxel_m, max_place_points);
    return out;
}

}  // namespace quasiloc::reloc
