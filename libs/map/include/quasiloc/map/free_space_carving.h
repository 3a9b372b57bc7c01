#pragma once
// Free-space carving: a map point whose voxel other scans' rays passed through was not there when they passed, so
// it belongs to something that moved (a vehicle in a queue, a person), not to the static scene.
//
// The carving grid is coarser than the map's voxels (carve_voxel_m, e.g. 0.2 m against 0.05 m): a ray that grazes
// a surface must not count as passing through it, and pose noise of a few centimetres must not either. Only voxels
// that some scan hit are stored (a hash of occupied voxels); rays are walked through the grid voxel by voxel (3D DDA,
// Amanatides & Woo 1987) and look each voxel up.
// Care taken, each a rule:
//  - a ray stops short of its hit by clearance_m / max(|sin(incidence)|, min_sin): it ends clearance_m above the
//    surface it hits, measured along the surface's normal (from the points around the hit's voxel), so a ray that
//    reaches the road at a grazing angle does not cut through the road voxels in front of its hit;
//  - a ray passes through a voxel only where it crosses the voxel's occupied part: each voxel keeps which of its
//    4 x 4 x 4 sub-cells hold points (a 64-bit mask), and a ray that crosses the voxel through empty sub-cells only
//    (beside a pole) does not count; where the points around the voxel form a plane, the ray must also cross that
//    plane inside the voxel: a ray running along a surface (skimming a car's roof on its way to a wall) proves
//    nothing about it, a ray through it proves it absent; a ray that the same scan's hits share a voxel with counts
//    there as a hit, not a pass;
//  - each scan counts once per voxel (hits and passes are counted in distinct scans, not rays);
//  - a voxel is free (its points removed) when at least min_pass_scans scans passed through it and
//    passes >= pass_ratio * hits: a voxel seen occupied by many scans needs proportionally many passes.
//  - rays are cast one per grid voxel of their end points per scan (rays to one voxel are nearly the same ray), and
//    walked for at most max_range_m.
#include <Eigen/Core>
#include <cstdint>
#include <quasiloc/map/voxel_hash.h>
#include <quasiloc/map/world_scan.h>
#include <string>

namespace quasiloc::map
{
struct CarvingOptions
{
    double voxel_m = 0.2;
    double clearance_m = 0.3;
    double min_sin = 0.05;
    double max_range_m = 50.0;
    int min_pass_scans = 2;
    double pass_ratio = 0.25;
};

struct CarveVoxel
{
    uint16_t hit_scans = 0, pass_scans = 0;
    int32_t last_hit_scan = -1, last_pass_scan = -1;
    float moments[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};  ///< n, sum x y z, sum xx xy xz yy yz zz (offsets)
    float normal[3] = {0, 0, 0};                         ///< unit; zero: no plane around this voxel
    float plane_offset = 0;  ///< normal . (the voxel's own points' mean, relative to its corner)
    uint64_t cells = 0;      ///< bit (i * 4 + j) * 4 + k: sub-cell (i, j, k) of the 4 x 4 x 4 holds a point
};

struct CarvingStats
{
    size_t voxels = 0, free_voxels = 0;
    size_t rays = 0, steps = 0;  ///< rays cast and voxels walked
    size_t memory_bytes = 0;
};

class FreeSpaceCarver
{
   public:
    explicit FreeSpaceCarver(const CarvingOptions& options);
    /** Pass 1: the voxels scan `scan_id` hits (scan ids increase by one per scan, from 0). */
    void addHits(const WorldScan& scan, int scan_id);
    /** After the last addHits: each voxel's surface normal from the points of it and its 26 neighbours. */
    void finishHits();
    /** Pass 2: the scan's rays (same scan ids as pass 1). */
    void castRays(const WorldScan& scan, int scan_id);
    /** Was the voxel holding p passed through enough to be free (see the rules above)? */
    bool isFree(const Eigen::Vector3f& p) const;
    const CarveVoxel* find(const Eigen::Vector3f& p) const;
    CarvingStats stats() const;

   private:
    bool freeVoxel(const CarveVoxel& v) const;
    void walk(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float length, int scan_id);
    /** Does the segment origin + t dir, t in [t_in, t_out], cross voxel v's surface (its plane, if it has one)
     *  through an occupied sub-cell? */
    bool crossesOccupied(const CarveVoxel& c, const Eigen::Vector3i& v, const Eigen::Vector3f& origin,
                         const Eigen::Vector3f& dir, float t_in, float t_out) const;

    CarvingOptions options_;
    float inv_;
    VoxelHashMap<CarveVoxel> grid_;
    size_t rays_ = 0, steps_ = 0;
};

}  // namespace quasiloc::map
