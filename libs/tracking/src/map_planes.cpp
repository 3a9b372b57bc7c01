// Map planes for the point-to-plane factor (map_planes.h).
#include <quasiloc/tracking/map_planes.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <quasiloc/core/pose.h>

namespace quasiloc::tracking
{
MapPlaneAssociator::MapPlaneAssociator(const core::CameraModel& camera, const MapPlaneOptions& options)
    : camera_(camera), options_(options), rays_(camera)
{}

bool MapPlaneAssociator::fitPlane(const cv::Mat& depth, const Eigen::Isometry3d& T_world_q, int u, int v,
                                  Eigen::Vector3d& n, double& d) const
{
    const int w = options_.window_px;
    if (u - w < 0 || v - w < 0 || u + w >= depth.cols || v + w >= depth.rows) return false;
    std::vector<Eigen::Vector3d> pts;
    for (int y = v - w; y <= v + w; y += 2)
        for (int x = u - w; x <= u + w; x += 2)
        {
            const float z = depth.at<float>(y, x);
            if (z > 0) pts.emplace_back(rays_.x.at<float>(y, x) * z, rays_.y.at<float>(y, x) * z, z);
        }
    // PCA, then again on the points within max_rms_m of that plane: a window across a crease is mostly one
    // surface, whose plane the second fit finds (the first one is tilted by the other surface's points).
    Eigen::Vector3d mean, n_q;
    Eigen::Vector3d eigenvalues;
    for (int pass = 0; pass < 2; ++pass)
    {
        if (int(pts.size()) < options_.min_points) return false;
        mean.setZero();
        for (const auto& p : pts) mean += p;
        mean /= double(pts.size());
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
        cov /= double(pts.size());
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);  // ascending eigenvalues
        eigenvalues = es.eigenvalues();
        n_q = es.eigenvectors().col(0);
        if (pass == 0)
        {
            std::vector<Eigen::Vector3d> kept;
            for (const auto& p : pts)
                if (std::abs(n_q.dot(p - mean)) <= options_.max_rms_m) kept.push_back(p);
            pts.swap(kept);
        }
    }
    if (std::sqrt(std::max(0.0, eigenvalues(0))) > options_.max_rms_m) return false;
    // A line-like support (a thin strip of points) does not fix a plane's normal.
    if (eigenvalues(1) < 0.1 * eigenvalues(2)) return false;
    n = T_world_q.linear() * n_q;
    d = -n.dot(T_world_q * mean);
    return true;
}

std::vector<estimation::PlaneFactorInput> MapPlaneAssociator::associate(const std::vector<Eigen::Vector3d>& points_cam,
                                                                        const std::vector<double>& sigma_m,
                                                                        const quasi::QuasiImage& q,
                                                                        const Eigen::Isometry3d& T_world_cam) const
{
    std::vector<estimation::PlaneFactorInput> out;
    const Eigen::Isometry3d T_world_q = core::toIsometry(q.T_world_cam);
    const Eigen::Isometry3d T_q_world = T_world_q.inverse();
    const double merge_cos = std::cos(options_.merge_deg * M_PI / 180);
    const int o = options_.offset_px;
    const int offsets[5][2] = {{0, 0}, {-o, 0}, {o, 0}, {0, -o}, {0, o}};
    for (size_t i = 0; i < points_cam.size(); ++i)
    {
        const Eigen::Vector3d p_world = T_world_cam * points_cam[i];
        Eigen::Vector2d px;
        if (!camera_.project(T_q_world * p_world, px)) continue;
        const int u = int(std::lround(px.x())), v = int(std::lround(px.y()));
        estimation::PlaneFactorInput f;
        f.points_cam = {points_cam[i]};
        f.sigma_m = sigma_m[i];
        std::vector<double> distances;
        for (const auto& off : offsets)
        {
            Eigen::Vector3d n;
            double d = 0;
            if (!fitPlane(q.depth, T_world_q, u + off[0], v + off[1], n, d)) continue;
            const double dist = n.dot(p_world) + d;
            if (std::abs(dist) > options_.max_distance_m) continue;
            bool same = false;
            for (const auto& c : f.candidates)
                same |= std::abs(c.n_map.dot(n)) >= merge_cos &&
                        std::abs(c.n_map.dot(p_world) + c.d - dist) <= options_.merge_m;
            if (same) continue;
            estimation::PlaneCandidate c;
            c.n_map = n, c.d = d;
            f.candidates.push_back(c);
            distances.push_back(dist);
        }
        if (f.candidates.empty()) continue;
        double sum = 0;
        for (size_t c = 0; c < f.candidates.size(); ++c)
        {
            const double r = distances[c] / f.sigma_m;
            f.candidates[c].probability = std::exp(-0.5 * r * r) + 1e-12;
            sum += f.candidates[c].probability;
        }
        for (auto& c : f.candidates) c.probability /= sum;
        out.push_back(std::move(f));
    }
    return out;
}

}  // namespace quasiloc::tracking
