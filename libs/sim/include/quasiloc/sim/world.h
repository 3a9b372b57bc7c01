#pragma once
// The simulated world as the renderer and the LiDAR sampler see it: one triangle mesh whose triangles
// carry a material and texture coordinates (in metres along the surface, so a texture's physical size
// does not depend on the triangle), point lights, and per-vertex irradiance of every light.
//
// Decisions:
// - Surfaces are subdivided into triangles of at most ~0.3 m so that per-vertex (Gouraud) lighting looks
//   smooth and near-plane clipping stays local. Every surface is double-sided (GMM patches have no
//   inside/outside).
// - Lighting is Lambertian with hard per-vertex shadows (a cube-map z-buffer around every light), precomputed
//   per vertex and per light, so that a time-varying light intensity (illumination-change episode) costs one
//   weighted sum per vertex and frame. Shadows exist for the camera only: the LiDAR sees none (its own
//   "shadows" are occlusions from its stations), one more honest difference between the modalities.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <quasiloc/sim/materials.h>
#include <string>
#include <vector>

namespace quasiloc::sim
{
struct Vertex
{
    Eigen::Vector3f p = Eigen::Vector3f::Zero();   ///< world frame, metres
    Eigen::Vector2f uv = Eigen::Vector2f::Zero();  ///< texture coordinates, metres along the surface
    Eigen::Vector3f n = Eigen::Vector3f::UnitZ();  ///< surface normal (sign irrelevant: double-sided)
};

struct Triangle
{
    uint32_t v[3] = {0, 0, 0};
    uint16_t material = 0;
};

struct Mesh
{
    std::vector<Vertex> vertices;
    std::vector<Triangle> triangles;

    /** Appends a planar quad origin + s*axis_u + t*axis_v, s,t in [0,1], subdivided into cells of at most
     *  max_cell_m; texture coordinates are metres along axis_u / axis_v plus uv_offset. */
    void addQuad(const Eigen::Vector3f& origin, const Eigen::Vector3f& axis_u, const Eigen::Vector3f& axis_v,
                 uint16_t material, float max_cell_m, const Eigen::Vector2f& uv_offset = Eigen::Vector2f::Zero());
    /** Appends a flat elliptical disc (centre, unit axes, semi-axes in metres) as rings of triangles. */
    void addEllipse(const Eigen::Vector3f& centre, const Eigen::Vector3f& axis_u, const Eigen::Vector3f& axis_v,
                    float semi_u, float semi_v, uint16_t material, float max_cell_m,
                    const Eigen::Vector2f& uv_offset = Eigen::Vector2f::Zero());
    /** Appends the 6 faces of an oriented box (centre, rotation world<-box, full sizes). */
    void addBox(const Eigen::Vector3f& centre, const Eigen::Matrix3f& R_world_box, const Eigen::Vector3f& size,
                uint16_t material, float max_cell_m, const Eigen::Vector2f& uv_offset = Eigen::Vector2f::Zero());
    /** Appends a closed vertical cylinder (axis along z) with n_sides facets and caps. */
    void addCylinder(const Eigen::Vector3f& base_centre, float radius, float height, int n_sides, uint16_t material,
                     float max_cell_m);
    void append(const Mesh& other);

    double area() const;
    double triangleArea(size_t t) const;
};

struct PointLight
{
    Eigen::Vector3f position = Eigen::Vector3f::Zero();
    float intensity = 1;  ///< irradiance at 1 m, normal incidence (relative units)
};

/** Squared distance from p to triangle (a, b, c); exact (Ericson, Real-Time Collision Detection 5.1.5). */
float pointTriangleDistanceSquared(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                                   const Eigen::Vector3f& c);

struct World
{
    std::string name;
    Mesh mesh;
    MaterialLibrary materials;
    std::vector<PointLight> lights;
    float ambient = 0.15f;
    /** vertex_irradiance[v * lights.size() + l]: Lambertian irradiance of light l at vertex v, unit intensity. */
    std::vector<float> vertex_irradiance;
    Eigen::AlignedBox3f room;  ///< inner extent of walls, floor and ceiling

    /** (Re)computes vertex_irradiance from the lights (called by the builder; call again after edits).
     *  shadow_map_px > 0: vertices a light cannot see (cube map of that size around the light) get none of it. */
    void computeIrradiance(int shadow_map_px = 0);
    /** Per-vertex shading for light intensity scales (one per light, or empty = all 1). */
    void vertexShading(const std::vector<float>& light_scale, std::vector<float>& shade) const;
};

}  // namespace quasiloc::sim
