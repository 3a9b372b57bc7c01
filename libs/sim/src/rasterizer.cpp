#include <algorithm>
#include <cmath>
#include <limits>
#include <quasiloc/sim/rasterizer.h>
#include <thread>

namespace quasiloc::sim
{
namespace
{
/** A vertex of a (possibly clipped) triangle: camera-frame position and barycentrics of the original. */
struct ClipVertex
{
    Eigen::Vector3f p;
    Eigen::Vector3f bary;
};

struct ScreenVertex
{
    float x, y, inv_z;
    Eigen::Vector3f bary_over_z;
};

void drawPiece(const ClipVertex& a, const ClipVertex& b, const ClipVertex& c, const PinholeIntrinsics& K,
               const RasterOptions& opt, int32_t id, VisibilityBuffer& buf)
{
    ScreenVertex s[3];
    const ClipVertex* in[3] = {&a, &b, &c};
    for (int i = 0; i < 3; ++i)
    {
        const float iz = 1.f / in[i]->p.z();
        s[i] = {K.fx * in[i]->p.x() * iz + K.cx, K.fy * in[i]->p.y() * iz + K.cy, iz, in[i]->bary * iz};
    }
    // Edge functions in double: coordinates reach ~1e3 px and products ~1e6, too close to float's precision.
    const double area =
        (double(s[1].x) - s[0].x) * (double(s[2].y) - s[0].y) - (double(s[1].y) - s[0].y) * (double(s[2].x) - s[0].x);
    if (std::abs(area) < 1e-12) return;
    const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({s[0].x, s[1].x, s[2].x}))));
    const int x1 = std::min(buf.width - 1, static_cast<int>(std::floor(std::max({s[0].x, s[1].x, s[2].x}))));
    const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({s[0].y, s[1].y, s[2].y}))));
    const int y1 = std::min(buf.height - 1, static_cast<int>(std::floor(std::max({s[0].y, s[1].y, s[2].y}))));
    if (x0 > x1 || y0 > y1) return;
    const double inv_area = 1.0 / area;
    const float near_lo = opt.near_m * 0.999f;
    // lambda_i(x, y) = (A_i x + B_i y + C_i) / area for the edge opposite vertex i.
    double A[3], B[3], C[3];
    for (int i = 0; i < 3; ++i)
    {
        const ScreenVertex& p = s[(i + 1) % 3];
        const ScreenVertex& q = s[(i + 2) % 3];
        A[i] = (double(p.y) - q.y) * inv_area;
        B[i] = (double(q.x) - p.x) * inv_area;
        C[i] = (double(p.x) * q.y - double(p.y) * q.x) * inv_area;
    }
    const double eps = 1e-9;  // inclusive edges: shared edges are covered by both neighbours, never by none
    for (int y = y0; y <= y1; ++y)
    {
        // The span of x where all three lambda_i = A_i x + (B_i y + C_i) are >= 0, solved per row.
        double xl = x0, xr = x1;
        double c[3];
        for (int i = 0; i < 3; ++i)
        {
            c[i] = B[i] * y + C[i];
            if (A[i] > 0)
                xl = std::max(xl, (-eps - c[i]) / A[i]);
            else if (A[i] < 0)
                xr = std::min(xr, (-eps - c[i]) / A[i]);
            else if (c[i] < -eps)
                xr = xl - 1;
        }
        const int xs = std::max(x0, static_cast<int>(std::ceil(xl))),
                  xe = std::min(x1, static_cast<int>(std::floor(xr)));
        if (xs > xe) continue;
        float l[3];
        for (int i = 0; i < 3; ++i) l[i] = static_cast<float>(A[i] * xs + c[i]);
        const float dl[3] = {static_cast<float>(A[0]), static_cast<float>(A[1]), static_cast<float>(A[2])};
        VisibilitySample* row = buf.px.data() + buf.index(0, y);
        for (int x = xs; x <= xe; ++x, l[0] += dl[0], l[1] += dl[1], l[2] += dl[2])
        {
            const float inv_z = l[0] * s[0].inv_z + l[1] * s[1].inv_z + l[2] * s[2].inv_z;
            // z >= stored depth  <=>  inv_z * depth <= 1: no division for hidden pixels.
            if (inv_z <= 0 || inv_z * row[x].depth <= 1.f) continue;
            const float z = 1.f / inv_z;
            if (z < near_lo || z > opt.far_m) continue;
            const Eigen::Vector3f bary =
                (l[0] * s[0].bary_over_z + l[1] * s[1].bary_over_z + l[2] * s[2].bary_over_z) * z;
            row[x] = {z, id, bary.y(), bary.z()};
        }
    }
}

/** Sutherland-Hodgman against z >= near: 3 vertices in, 0, 3 or 4 out. */
int clipNear(const ClipVertex in[3], float near_m, ClipVertex out[4])
{
    int n = 0;
    for (int i = 0; i < 3; ++i)
    {
        const ClipVertex& p = in[i];
        const ClipVertex& q = in[(i + 1) % 3];
        const bool p_in = p.p.z() >= near_m, q_in = q.p.z() >= near_m;
        if (p_in) out[n++] = p;
        if (p_in != q_in)
        {
            const float t = (near_m - p.p.z()) / (q.p.z() - p.p.z());
            out[n++] = {p.p + t * (q.p - p.p), p.bary + t * (q.bary - p.bary)};
            out[n - 1].p.z() = near_m;
        }
    }
    return n;
}

/** True when all three points are on the outer side of one of the four side planes of the frustum. */
bool outsideFrustum(const Eigen::Vector3f* p, const PinholeIntrinsics& K)
{
    auto all = [&](auto pred) { return pred(p[0]) && pred(p[1]) && pred(p[2]); };
    const float left = K.cx + 0.5f, right = K.width - 0.5f - K.cx, top = K.cy + 0.5f, bottom = K.height - 0.5f - K.cy;
    return all([&](const Eigen::Vector3f& q) { return K.fx * q.x() + left * q.z() < 0; }) ||
           all([&](const Eigen::Vector3f& q) { return K.fx * q.x() - right * q.z() > 0; }) ||
           all([&](const Eigen::Vector3f& q) { return K.fy * q.y() + top * q.z() < 0; }) ||
           all([&](const Eigen::Vector3f& q) { return K.fy * q.y() - bottom * q.z() > 0; });
}
}  // namespace

void VisibilityBuffer::reset(int w, int h)
{
    width = w;
    height = h;
    px.assign(static_cast<size_t>(w) * h, VisibilitySample{std::numeric_limits<float>::infinity(), -1, 0.f, 0.f});
}

void rasterize(const Mesh& mesh, const PinholeIntrinsics& K, const Eigen::Isometry3f& T_cam_world,
               const RasterOptions& opt, VisibilityBuffer& buf)
{
    std::vector<Eigen::Vector3f> pc(mesh.vertices.size());
    const Eigen::Matrix3f R = T_cam_world.linear();
    const Eigen::Vector3f t = T_cam_world.translation();
    for (size_t i = 0; i < pc.size(); ++i) pc[i] = R * mesh.vertices[i].p + t;

    const Eigen::Vector3f unit[3] = {Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitY(), Eigen::Vector3f::UnitZ()};
    for (size_t ti = 0; ti < mesh.triangles.size(); ++ti)
    {
        const Triangle& tri = mesh.triangles[ti];
        const Eigen::Vector3f p[3] = {pc[tri.v[0]], pc[tri.v[1]], pc[tri.v[2]]};
        const float zmax = std::max({p[0].z(), p[1].z(), p[2].z()});
        const float zmin = std::min({p[0].z(), p[1].z(), p[2].z()});
        if (zmax < opt.near_m || zmin > opt.far_m || outsideFrustum(p, K)) continue;
        const auto id = static_cast<int32_t>(opt.id_offset + static_cast<int32_t>(ti));
        ClipVertex in[3] = {{p[0], unit[0]}, {p[1], unit[1]}, {p[2], unit[2]}};
        if (zmin >= opt.near_m)
        {
            drawPiece(in[0], in[1], in[2], K, opt, id, buf);
            continue;
        }
        ClipVertex out[4];
        const int n = clipNear(in, opt.near_m, out);
        for (int k = 1; k + 1 < n; ++k) drawPiece(out[0], out[k], out[k + 1], K, opt, id, buf);
    }
}

std::vector<Eigen::Matrix3f> cubeFaceRotations()
{
    // Rows of R_cam_world are the camera axes (x right, y down, z forward) in world coordinates.
    auto face = [](const Eigen::Vector3f& fwd, const Eigen::Vector3f& down) {
        Eigen::Matrix3f R;
        R.row(2) = fwd.transpose();
        R.row(1) = down.transpose();
        R.row(0) = down.cross(fwd).transpose();
        return R;
    };
    const Eigen::Vector3f X = Eigen::Vector3f::UnitX(), Y = Eigen::Vector3f::UnitY(), Z = Eigen::Vector3f::UnitZ();
    return {face(X, -Z), face(-X, -Z), face(Y, -Z), face(-Y, -Z), face(Z, Y), face(-Z, -Y)};
}

PinholeIntrinsics cubeFaceIntrinsics(int n)
{
    const float f = 0.5f * n;
    return {n, n, f, f, 0.5f * (n - 1), 0.5f * (n - 1)};
}

const VisibilitySample* CubeMap::lookup(const Eigen::Vector3f& d, float& z_face) const
{
    const Eigen::Vector3f a = d.cwiseAbs();
    int face;
    if (a.x() >= a.y() && a.x() >= a.z())
        face = d.x() > 0 ? 0 : 1;
    else if (a.y() >= a.z())
        face = d.y() > 0 ? 2 : 3;
    else
        face = d.z() > 0 ? 4 : 5;
    const Eigen::Vector3f q = R[face] * d;
    z_face = q.z();
    const PinholeIntrinsics K = cubeFaceIntrinsics(n);
    const int u = std::clamp(static_cast<int>(std::lround(K.fx * q.x() / q.z() + K.cx)), 0, n - 1);
    const int v = std::clamp(static_cast<int>(std::lround(K.fy * q.y() / q.z() + K.cy)), 0, n - 1);
    return &faces[face].at(u, v);
}

namespace
{
void prepareCubeMap(const Eigen::Vector3f& centre, int n, CubeMap& cube)
{
    cube.n = n;
    cube.centre = centre;
    cube.R = cubeFaceRotations();
}

/** Faces [first, last) of `cube` (prepared): `mesh`, then `also` if given, its ids after mesh's. */
void renderCubeFaces(const Mesh& mesh, const Mesh* also, int first, int last, CubeMap& cube)
{
    const PinholeIntrinsics K = cubeFaceIntrinsics(cube.n);
    for (int f = first; f < last; ++f)
    {
        Eigen::Isometry3f T = Eigen::Isometry3f::Identity();
        T.linear() = cube.R[f];
        T.translation() = -cube.R[f] * cube.centre;
        cube.faces[f].reset(cube.n, cube.n);
        RasterOptions ro;
        ro.near_m = 0.02f;
        rasterize(mesh, K, T, ro, cube.faces[f]);
        if (!also) continue;
        ro.id_offset = int32_t(mesh.triangles.size());
        rasterize(*also, K, T, ro, cube.faces[f]);
    }
}
}  // namespace

void renderCubeMap(const Mesh& mesh, const Eigen::Vector3f& centre, int n, CubeMap& cube)
{
    prepareCubeMap(centre, n, cube);
    std::thread other([&] { renderCubeFaces(mesh, nullptr, 3, 6, cube); });
    renderCubeFaces(mesh, nullptr, 0, 3, cube);
    other.join();
}

void renderCubeMap(const Mesh& mesh, const Mesh& also, const Eigen::Vector3f& centre, int n, CubeMap& cube)
{
    prepareCubeMap(centre, n, cube);
    renderCubeFaces(mesh, &also, 0, 6, cube);
}

}  // namespace quasiloc::sim
