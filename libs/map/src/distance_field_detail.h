#pragma once
// What the dense and the sparse distance field share: the exact 1-D squared distance transform.
#include <cstddef>
#include <vector>

namespace quasiloc::map::detail
{
constexpr float kFar = 1e20f;  ///< "no occupied voxel": larger than any squared distance

/** 1-D squared distance transform of f (n samples, stride apart) in place: f'(q) = min_p (q - p)^2 + f(p).
 *  The lower envelope of the parabolas rooted at every sample (Felzenszwalb & Huttenlocher, algorithm DT).
 *  v, z, tmp: scratch of size n, n + 1, n. */
inline void squaredDistance1d(float* f, int n, size_t stride, std::vector<int>& v, std::vector<float>& z, std::vector<float>& tmp)
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
}  // namespace quasiloc::map::detail
