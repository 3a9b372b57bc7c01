#pragma once
// What the dense and the sparse distance field share: the exact squared distance transform of a box of voxels and
// the exact distances near the surface.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace quasiloc::map::detail
{
constexpr float kFar = 1e20f;  ///< "no occupied voxel": larger than any squared distance

/** 1-D squared distance transform of f (n samples, stride apart) in place: f'(q) = min_p (q - p)^2 + f(p).
 *  The lower envelope of the parabolas rooted at every sample (Felzenszwalb & Huttenlocher, algorithm DT).
 *  v, z, tmp: scratch of size n, n + 1, n. */
inline void squaredDistance1d(float* f, int n, size_t stride, std::vector<int>& v, std::vector<float>& z,
                              std::vector<float>& tmp)
{
    for (int q = 0; q < n; ++q) tmp[q] = f[size_t(q) * stride];
    int k = 0;
    v[0] = 0;
    z[0] = -kFar;
    z[1] = kFar;
    for (int q = 1; q < n; ++q)
    {
        if (tmp[q] >= kFar) continue;  // no parabola rooted here
        if (tmp[v[k]] >= kFar)
        {  // the envelope so far holds only "infinitely far" roots: start it here
            v[0] = q, k = 0, z[0] = -kFar, z[1] = kFar;
            continue;
        }
        float s;
        while (true)
        {
            const int p = v[k];
            s = ((tmp[q] + float(q) * float(q)) - (tmp[p] + float(p) * float(p))) / (2.f * float(q - p));
            if (s > z[k] || k == 0) break;
            --k;
        }
        if (s <= z[k])
        {  // k == 0 and the new parabola is lower everywhere
            v[0] = q, z[0] = -kFar, z[1] = kFar;
            continue;
        }
        ++k;
        v[k] = q, z[k] = s, z[k + 1] = kFar;
    }
    if (tmp[v[0]] >= kFar) return;  // no occupied sample on this line: it stays far
    k = 0;
    for (int q = 0; q < n; ++q)
    {
        while (z[k + 1] < float(q)) ++k;
        const float d = float(q - v[k]);
        f[size_t(q) * stride] = d * d + tmp[v[k]];
    }
}
struct Box
{
    Eigen::Vector3i lo, hi;  ///< voxel bounds, hi exclusive
    Eigen::Vector3i size() const { return hi - lo; }
    size_t index(int i, int j, int k) const
    {
        const Eigen::Vector3i s = size();
        return (size_t(k - lo.z()) * size_t(s.y()) + size_t(j - lo.y())) * size_t(s.x()) + size_t(i - lo.x());
    }
    bool contains(int i, int j, int k) const
    {
        return i >= lo.x() && j >= lo.y() && k >= lo.z() && i < hi.x() && j < hi.y() && k < hi.z();
    }
};

/** The 3-pass exact squared distance transform of a box's buffer (occupied: 0, else kFar), x fastest. */
inline void transform(std::vector<float>& d, const Eigen::Vector3i& n)
{
    const int longest = n.maxCoeff();
    std::vector<int> v(static_cast<size_t>(longest));
    std::vector<float> z(static_cast<size_t>(longest) + 1), tmp(static_cast<size_t>(longest));
    const size_t sy = size_t(n.x()), sz = size_t(n.x()) * size_t(n.y());
    auto at = [&](int i, int j, int k) { return &d[size_t(k) * sz + size_t(j) * sy + size_t(i)]; };
    for (int k = 0; k < n.z(); ++k)
        for (int j = 0; j < n.y(); ++j) squaredDistance1d(at(0, j, k), n.x(), 1, v, z, tmp);
    for (int k = 0; k < n.z(); ++k)
        for (int i = 0; i < n.x(); ++i) squaredDistance1d(at(i, 0, k), n.y(), sy, v, z, tmp);
    for (int j = 0; j < n.y(); ++j)
        for (int i = 0; i < n.x(); ++i) squaredDistance1d(at(i, j, 0), n.z(), sz, v, z, tmp);
}

/** The squared distances (voxel units) from the point at continuous voxel coordinates g to the voxels of its
 *  3 x 3 x 3 neighbourhood that lie in `box`, into `near` (the box's buffer) where smaller: near the surface the
 *  distance to occupied voxel centres is biased by up to half a voxel, the exact distance to the points is not. */
inline void nearestInNeighbourhood(const Eigen::Vector3f& g, const Box& box, std::vector<float>& near)
{
    const int x = int(std::lround(g.x())), y = int(std::lround(g.y())), z = int(std::lround(g.z()));
    for (int k = std::max(box.lo.z(), z - 1); k <= std::min(box.hi.z() - 1, z + 1); ++k)
        for (int j = std::max(box.lo.y(), y - 1); j <= std::min(box.hi.y() - 1, y + 1); ++j)
            for (int i = std::max(box.lo.x(), x - 1); i <= std::min(box.hi.x() - 1, x + 1); ++i)
            {
                const float d2 = (Eigen::Vector3f(float(i), float(j), float(k)) - g).squaredNorm();
                float& best = near[box.index(i, j, k)];
                best = std::min(best, d2);
            }
}

/** A voxel's stored distance [m]: the exact one near the surface, else the transform's, truncated. */
inline float finalDistance(float near_d2, float transform_d2, float voxel_m, float max_distance_m)
{
    return std::min(max_distance_m, std::sqrt(near_d2 < kFar ? near_d2 : transform_d2) * voxel_m);
}

}  // namespace quasiloc::map::detail
