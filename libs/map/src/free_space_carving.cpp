#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <quasiloc/map/free_space_carving.h>

namespace quasiloc::map
{
namespace
{
/** The sub-cell bit of an offset q (metres from the voxel's corner) in a voxel of `size`. */
inline uint64_t cellBit(const Eigen::Vector3f& q, float size)
{
    int i[3];
    for (int a = 0; a < 3; ++a) i[a] = std::clamp(int(q[a] * 4.f / size), 0, 3);
    return uint64_t(1) << ((i[0] * 4 + i[1]) * 4 + i[2]);
}
}  // namespace

FreeSpaceCarver::FreeSpaceCarver(const CarvingOptions& options)
    : options_(options), inv_(float(1.0 / options.voxel_m)), grid_(1 << 14)
{}

void FreeSpaceCarver::addHits(const WorldScan& scan, int scan_id)
{
    for (const Eigen::Vector3f& p : scan.points)
    {
        const Eigen::Vector3i v = voxelOf(p, inv_);
        VoxelKey key = 0;
        if (!packVoxel(v, key)) continue;  // the fusion's finer grid rejects such points first
        CarveVoxel& c = grid_[key];
        if (c.last_hit_scan != scan_id)
        {
            c.last_hit_scan = scan_id;
            if (c.hit_scans < UINT16_MAX) ++c.hit_scans;
        }
        const Eigen::Vector3f q = p - v.cast<float>() * float(options_.voxel_m);
        c.cells |= cellBit(q, float(options_.voxel_m));
        float* m = c.moments;
        m[0] += 1, m[1] += q.x(), m[2] += q.y(), m[3] += q.z();
        m[4] += q.x() * q.x(), m[5] += q.x() * q.y(), m[6] += q.x() * q.z();
        m[7] += q.y() * q.y(), m[8] += q.y() * q.z(), m[9] += q.z() * q.z();
    }
}

void FreeSpaceCarver::finishHits()
{
    const double s = options_.voxel_m;
    grid_.forEach([&](VoxelKey key, CarveVoxel& c) {
        const Eigen::Vector3i v = unpackVoxel(key);
        // Moments of the 27 voxels about one common origin (this voxel's corner).
        double n = 0;
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        Eigen::Matrix3d sq = Eigen::Matrix3d::Zero();
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz)
                {
                    VoxelKey k = 0;
                    if (!packVoxel(v + Eigen::Vector3i(dx, dy, dz), k)) continue;
                    const CarveVoxel* o = grid_.find(k);
                    if (o == nullptr) continue;
                    const float* m = o->moments;
                    const Eigen::Vector3d d(dx * s, dy * s, dz * s);
                    const Eigen::Vector3d ms(m[1], m[2], m[3]);
                    Eigen::Matrix3d mq;
                    mq << m[4], m[5], m[6], m[5], m[7], m[8], m[6], m[8], m[9];
                    // sum (q + d)(q + d)^T = sum q q^T + ms d^T + d ms^T + n d d^T
                    n += m[0];
                    sum += ms + m[0] * d;
                    sq += mq + ms * d.transpose() + d * ms.transpose() + m[0] * d * d.transpose();
                }
        if (n < 5) return;
        const Eigen::Vector3d mean = sum / n;
        const Eigen::Matrix3d cov = sq / n - mean * mean.transpose();
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
        const Eigen::Vector3d ev = eig.eigenvalues();  // ascending
        // A plane: thin across (smallest << middle) and spread in two directions (middle not ~0, not a line).
        if (ev[0] < 0.1 * ev[1] && ev[1] > 0.05 * ev[2])
        {
            const Eigen::Vector3d nrm = eig.eigenvectors().col(0);
            for (int a = 0; a < 3; ++a) c.normal[a] = float(nrm[a]);
            const float* m = c.moments;
            c.plane_offset = float(nrm.dot(Eigen::Vector3d(m[1], m[2], m[3]) / double(m[0])));
        }
    });
}

void FreeSpaceCarver::castRays(const WorldScan& scan, int scan_id)
{
    // Every voxel this scan hits, marked so that its own rays do not count as passing through them.
    VoxelHashMap<uint32_t> ray_ends(scan.size() / 2 + 16);
    for (size_t k = 0; k < scan.size(); ++k)
    {
        VoxelKey key = 0;
        if (!packVoxel(voxelOf(scan.points[k], inv_), key)) continue;
        if (CarveVoxel* c = grid_.find(key)) c->last_pass_scan = scan_id;  // "passed" already: counts nothing
        uint32_t& first = ray_ends[key];
        if (first == 0) first = uint32_t(k) + 1;
    }
    const float clearance = float(options_.clearance_m), min_sin = float(options_.min_sin);
    ray_ends.forEach([&](VoxelKey key, uint32_t first) {
        const size_t k = first - 1;
        const Eigen::Vector3f& o = scan.origins[k];
        Eigen::Vector3f dir = scan.points[k] - o;
        const float range = dir.norm();
        if (range <= 0) return;
        dir /= range;
        // No plane around the hit (an edge, a corner, sparse points): its incidence is unknown, so the ray stops as
        // short as at the most grazing incidence.
        float stop = clearance / min_sin;
        if (const CarveVoxel* c = grid_.find(key); c != nullptr && (c->normal[0] || c->normal[1] || c->normal[2]))
        {
            const float sin_incidence = std::abs(dir.dot(Eigen::Vector3f(c->normal[0], c->normal[1], c->normal[2])));
            stop = clearance / std::max(sin_incidence, min_sin);
        }
        const float length = std::min(range - stop, float(options_.max_range_m));
        if (length > 0) walk(o, dir, length, scan_id);
    });
}

void FreeSpaceCarver::walk(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float length, int scan_id)
{
    ++rays_;
    const float s = float(options_.voxel_m);
    Eigen::Vector3i v = voxelOf(origin, inv_);
    int step[3];
    float t_max[3], t_delta[3];
    for (int a = 0; a < 3; ++a)
    {
        step[a] = dir[a] > 0 ? 1 : -1;
        if (dir[a] == 0)
        {
            t_max[a] = t_delta[a] = std::numeric_limits<float>::infinity();
            continue;
        }
        const float boundary = (float(v[a]) + (dir[a] > 0 ? 1.f : 0.f)) * s;
        t_max[a] = (boundary - origin[a]) / dir[a];
        t_delta[a] = s / std::abs(dir[a]);
    }
    float t_in = 0;
    while (true)
    {
        VoxelKey key = 0;
        if (!packVoxel(v, key)) return;
        ++steps_;
        const int a = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
        const float t_out = std::min(t_max[a], length);
        if (CarveVoxel* c = grid_.find(key);
            c != nullptr && c->last_pass_scan != scan_id && crossesOccupied(*c, v, origin, dir, t_in, t_out))
        {
            c->last_pass_scan = scan_id;
            if (c->pass_scans < UINT16_MAX) ++c->pass_scans;
        }
        if (t_max[a] > length) return;
        t_in = t_max[a];
        v[a] += step[a];
        t_max[a] += t_delta[a];
    }
}

bool FreeSpaceCarver::crossesOccupied(const CarveVoxel& c, const Eigen::Vector3i& v, const Eigen::Vector3f& origin,
                                      const Eigen::Vector3f& dir, float t_in, float t_out) const
{
    // Samples every half sub-cell along the segment: a crossing of a sub-cell's corner shorter than that is missed,
    // which errs on the side of keeping the point.
    const float size = float(options_.voxel_m);
    const Eigen::Vector3f corner = v.cast<float>() * size;
    if (c.normal[0] != 0 || c.normal[1] != 0 || c.normal[2] != 0)
    {
        const Eigen::Vector3f n(c.normal[0], c.normal[1], c.normal[2]);
        const float side_in = n.dot(origin + t_in * dir - corner) - c.plane_offset;
        const float side_out = n.dot(origin + t_out * dir - corner) - c.plane_offset;
        if ((side_in > 0) == (side_out > 0)) return false;  // along the surface, not through it
    }
    const float step = size / 8.f;
    for (float t = t_in + 0.5f * step; t < t_out; t += step)
        if (c.cells & cellBit(origin + t * dir - corner, size)) return true;
    return false;
}

bool FreeSpaceCarver::freeVoxel(const CarveVoxel& c) const
{
    return c.pass_scans >= options_.min_pass_scans && c.pass_scans >= options_.pass_ratio * c.hit_scans;
}

const CarveVoxel* FreeSpaceCarver::find(const Eigen::Vector3f& p) const
{
    VoxelKey key = 0;
    return packVoxel(voxelOf(p, inv_), key) ? grid_.find(key) : nullptr;
}

bool FreeSpaceCarver::isFree(const Eigen::Vector3f& p) const
{
    const CarveVoxel* c = find(p);
    return c != nullptr && freeVoxel(*c);
}

CarvingStats FreeSpaceCarver::stats() const
{
    CarvingStats st;
    st.voxels = grid_.size();
    grid_.forEach([&](VoxelKey, const CarveVoxel& c) { st.free_voxels += freeVoxel(c); });
    st.rays = rays_;
    st.steps = steps_;
    st.memory_bytes = grid_.memoryBytes();
    return st;
}

}  // namespace quasiloc::map
