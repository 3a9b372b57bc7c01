#include <algorithm>
#include <cmath>
#include <quasiloc/sim/rasterizer.h>
#include <quasiloc/sim/world.h>

namespace quasiloc::sim
{
namespace
{
int cellsFor(float length_m, float max_cell_m)
{
    return std::max(1, static_cast<int>(std::ceil(length_m / max_cell_m)));
}
}  // namespace

void Mesh::addQuad(const Eigen::Vector3f& origin, const Eigen::Vector3f& axis_u, const Eigen::Vector3f& axis_v,
                   uint16_t material, float max_cell_m, const Eigen::Vector2f& uv_offset)
{
    const float lu = axis_u.norm(), lv = axis_v.norm();
    const int nu = cellsFor(lu, max_cell_m), nv = cellsFor(lv, max_cell_m);
    const Eigen::Vector3f n = axis_u.cross(axis_v).normalized();
    const auto base = static_cast<uint32_t>(vertices.size());
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i)
        {
            const float s = static_cast<float>(i) / nu, t = static_cast<float>(j) / nv;
            vertices.push_back({origin + s * axis_u + t * axis_v, uv_offset + Eigen::Vector2f(s * lu, t * lv), n});
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i)
        {
            const uint32_t a = base + j * (nu + 1) + i, b = a + 1, c = a + (nu + 1), d = c + 1;
            triangles.push_back({{a, b, d}, material});
            triangles.push_back({{a, d, c}, material});
        }
}

void Mesh::addEllipse(const Eigen::Vector3f& centre, const Eigen::Vector3f& axis_u, const Eigen::Vector3f& axis_v,
                      float semi_u, float semi_v, uint16_t material, float max_cell_m, const Eigen::Vector2f& uv_offset)
{
    const float r_max = std::max(semi_u, semi_v);
    const int rings = cellsFor(r_max, max_cell_m);
    const int sectors = std::clamp(static_cast<int>(std::ceil(2 * M_PI * r_max / max_cell_m)), 8, 48);
    const Eigen::Vector3f n = axis_u.cross(axis_v).normalized();
    const auto base = static_cast<uint32_t>(vertices.size());
    vertices.push_back({centre, uv_offset, n});
    for (int r = 1; r <= rings; ++r)
        for (int s = 0; s < sectors; ++s)
        {
            const float f = static_cast<float>(r) / rings, a = static_cast<float>(2 * M_PI * s / sectors);
            const float du = f * semi_u * std::cos(a), dv = f * semi_v * std::sin(a);
            vertices.push_back({centre + du * axis_u + dv * axis_v, uv_offset + Eigen::Vector2f(du, dv), n});
        }
    auto ring_vertex = [&](int r, int s) { return base + 1 + (r - 1) * sectors + (s % sectors); };
    for (int s = 0; s < sectors; ++s) triangles.push_back({{base, ring_vertex(1, s), ring_vertex(1, s + 1)}, material});
    for (int r = 2; r <= rings; ++r)
        for (int s = 0; s < sectors; ++s)
        {
            const uint32_t a = ring_vertex(r - 1, s), b = ring_vertex(r - 1, s + 1), c = ring_vertex(r, s),
                           d = ring_vertex(r, s + 1);
            triangles.push_back({{a, c, d}, material});
            triangles.push_back({{a, d, b}, material});
        }
}

void Mesh::addBox(const Eigen::Vector3f& centre, const Eigen::Matrix3f& R_world_box, const Eigen::Vector3f& size,
                  uint16_t material, float max_cell_m, const Eigen::Vector2f& uv_offset)
{
    const Eigen::Vector3f ex = R_world_box.col(0) * size.x(), ey = R_world_box.col(1) * size.y(),
                          ez = R_world_box.col(2) * size.z();
    const Eigen::Vector3f c0 = centre - 0.5f * (ex + ey + ez);  // corner (-,-,-)
    addQuad(c0, ex, ez, material, max_cell_m, uv_offset);       // y- face
    addQuad(c0 + ey, ex, ez, material, max_cell_m, uv_offset);  // y+ face
    addQuad(c0, ey, ez, material, max_cell_m, uv_offset);       // x- face
    addQuad(c0 + ex, ey, ez, material, max_cell_m, uv_offset);  // x+ face
    addQuad(c0, ex, ey, material, max_cell_m, uv_offset);       // bottom
    addQuad(c0 + ez, ex, ey, material, max_cell_m, uv_offset);  // top
}

void Mesh::addCylinder(const Eigen::Vector3f& base_centre, float radius, float height, int n_sides, uint16_t material,
                       float max_cell_m)
{
    for (int s = 0; s < n_sides; ++s)
    {
        const float a0 = static_cast<float>(2 * M_PI * s / n_sides),
                    a1 = static_cast<float>(2 * M_PI * (s + 1) / n_sides);
        const Eigen::Vector3f p0 = base_centre + radius * Eigen::Vector3f(std::cos(a0), std::sin(a0), 0);
        const Eigen::Vector3f p1 = base_centre + radius * Eigen::Vector3f(std::cos(a1), std::sin(a1), 0);
        const auto first = static_cast<uint32_t>(vertices.size());
        addQuad(p0, p1 - p0, Eigen::Vector3f(0, 0, height), material, max_cell_m, Eigen::Vector2f(radius * a0, 0));
        // Smooth shading around the pole: the facet's vertices get radial normals.
        for (size_t v = first; v < vertices.size(); ++v)
        {
            Eigen::Vector3f radial = vertices[v].p - base_centre;
            radial.z() = 0;
            vertices[v].n = radial.normalized();
        }
    }
    for (float z : {0.f, height})
        addEllipse(base_centre + Eigen::Vector3f(0, 0, z), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitY(), radius,
                   radius, material, max_cell_m);
}

void Mesh::append(const Mesh& other)
{
    const auto base = static_cast<uint32_t>(vertices.size());
    vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
    for (Triangle t : other.triangles)
    {
        for (auto& v : t.v) v += base;
        triangles.push_back(t);
    }
}

double Mesh::triangleArea(size_t t) const
{
    const Triangle& tri = triangles[t];
    const Eigen::Vector3f a = vertices[tri.v[0]].p, b = vertices[tri.v[1]].p, c = vertices[tri.v[2]].p;
    return 0.5 * static_cast<double>((b - a).cross(c - a).norm());
}

double Mesh::area() const
{
    double sum = 0;
    for (size_t t = 0; t < triangles.size(); ++t) sum += triangleArea(t);
    return sum;
}

float pointTriangleDistanceSquared(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                                   const Eigen::Vector3f& c)
{
    const Eigen::Vector3f ab = b - a, ac = c - a, ap = p - a;
    const float d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();
    const Eigen::Vector3f bp = p - b;
    const float d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).squaredNorm();
    const Eigen::Vector3f cp = p - c;
    const float d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).squaredNorm();
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).squaredNorm();
    const float denom = 1.f / (va + vb + vc);
    const float v = vb * denom, w = vc * denom;
    return (p - (a + ab * v + ac * w)).squaredNorm();
}

void World::computeIrradiance(int shadow_map_px)
{
    const size_t nl = lights.size();
    vertex_irradiance.assign(mesh.vertices.size() * nl, 0.f);
    std::vector<std::vector<uint8_t>> lit(nl);
    for (size_t l = 0; l < nl && shadow_map_px > 0; ++l)
    {
        CubeMap cube;
        renderCubeMap(mesh, lights[l].position, shadow_map_px, cube);
        const float pixel = 2.f / static_cast<float>(shadow_map_px);
        lit[l].resize(mesh.vertices.size());
        for (size_t v = 0; v < mesh.vertices.size(); ++v)
        {
            float z_face;
            const VisibilitySample* s = cube.lookup(mesh.vertices[v].p - lights[l].position, z_face);
            // Lit unless something is clearly in front of the vertex (tolerance: a few pixel footprints).
            lit[l][v] = s->tri < 0 || z_face <= s->depth + 0.03f + 4.f * pixel * z_face;
        }
    }
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
        for (size_t l = 0; l < nl; ++l)
        {
            const Eigen::Vector3f d = lights[l].position - mesh.vertices[v].p;
            const float r2 = d.squaredNorm();
            // |cos| because surfaces are double-sided; +0.25 m^2 keeps lamps from burning nearby surfaces out.
            const float cos_in = std::abs(mesh.vertices[v].n.dot(d)) / std::sqrt(r2 + 1e-12f);
            const float shadow = lit[l].empty() || lit[l][v] ? 1.f : 0.f;
            vertex_irradiance[v * nl + l] = shadow * lights[l].intensity * cos_in / (r2 + 0.25f);
        }
}

void World::vertexShading(const std::vector<float>& light_scale, std::vector<float>& shade) const
{
    const size_t nl = lights.size();
    shade.resize(mesh.vertices.size());
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
    {
        float s = ambient;
        const float* e = vertex_irradiance.data() + v * nl;
        for (size_t l = 0; l < nl; ++l) s += e[l] * (light_scale.empty() ? 1.f : light_scale[l]);
        shade[v] = s;
    }
}

}  // namespace quasiloc::sim
