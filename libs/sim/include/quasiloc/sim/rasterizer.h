#pragma once
// A small software rasteriser: the visibility buffer ("which triangle, where on it") of a triangle mesh
// seen by an ideal pinhole camera, with a z-buffer and near-plane clipping.
//
// Decisions:
// - Deferred shading: the rasteriser only stores depth, the triangle id and perspective-correct barycentric
//   coordinates; texturing and lighting run once per visible pixel afterwards (no cost for overdraw),
//   and the same buffer serves the camera renderer, the LiDAR sampler (visibility from scanner stations,
//   beam casting) and tests (depth).
// - Pixel centres are at integer coordinates (CameraModel convention: pixel (u, v) covers
//   [u-0.5, u+0.5) x [v-0.5, v+0.5)). Coverage is inclusive on edges (no cracks between neighbours).
// - Triangles crossing the near plane are clipped in camera space; the clipped pieces still report the
//   barycentric coordinates of the ORIGINAL triangle, so shading does not care about clipping.
// - Depth is the camera z (not the range), as a float.
#include <Eigen/Geometry>
#include <cstdint>
#include <quasiloc/sim/world.h>
#include <vector>

namespace quasiloc::sim
{
struct PinholeIntrinsics
{
    int width = 0, height = 0;
    float fx = 0, fy = 0, cx = 0, cy = 0;
};

struct VisibilitySample
{
    float depth;   ///< camera z in metres; +inf where nothing was drawn
    int32_t tri;   ///< id_offset + triangle index; -1 where nothing was drawn
    float b1, b2;  ///< barycentrics of vertices 1 and 2 (vertex 0: 1 - b1 - b2)
};

/** Row-major samples (array of structs: raster and shading touch all fields of a pixel together). */
struct VisibilityBuffer
{
    int width = 0, height = 0;
    std::vector<VisibilitySample> px;

    /** Sizes the buffer and clears it (depth +inf, tri -1). */
    void reset(int w, int h);
    size_t index(int u, int v) const { return static_cast<size_t>(v) * width + u; }
    const VisibilitySample& at(int u, int v) const { return px[index(u, v)]; }
};

struct RasterOptions
{
    float near_m = 0.05f;
    float far_m = 1000.f;
    int32_t id_offset = 0;  ///< added to triangle indices (to draw several meshes into one buffer)
};

/** Draws `mesh` into `buf` (not cleared: call buf.reset() first; several meshes may share one buffer).
 *  T_cam_world maps world points into the camera frame (z forward, x right, y down). */
void rasterize(const Mesh& mesh, const PinholeIntrinsics& K, const Eigen::Isometry3f& T_cam_world,
               const RasterOptions& options, VisibilityBuffer& buf);

/** The six faces of a cube map around a point: rotations R_cam_world of 90-degree pinholes (+x, -x, +y,
 *  -y, +z, -z viewing directions) and the intrinsics of a face of side n pixels. */
std::vector<Eigen::Matrix3f> cubeFaceRotations();
PinholeIntrinsics cubeFaceIntrinsics(int n);

/** Visibility around a point: six 90-degree faces (LiDAR stations, light shadows). */
struct CubeMap
{
    int n = 0;
    Eigen::Vector3f centre = Eigen::Vector3f::Zero();
    std::vector<Eigen::Matrix3f> R;  ///< R_face_world
    VisibilityBuffer faces[6];

    /** The sample seen in world direction d (from the centre); z_face receives d's depth along that face's axis. */
    const VisibilitySample* lookup(const Eigen::Vector3f& d, float& z_face) const;
};

/** Renders the six faces of `mesh` around `centre` (n x n pixels each, two threads). */
void renderCubeMap(const Mesh& mesh, const Eigen::Vector3f& centre, int n, CubeMap& cube);
/** The same on the calling thread, with `also` drawn after `mesh` (its triangle ids offset by mesh's triangle
 *  count): the static world and the things moving in it at one instant. */
void renderCubeMap(const Mesh& mesh, const Mesh& also, const Eigen::Vector3f& centre, int n, CubeMap& cube);

}  // namespace quasiloc::sim
