#pragma once
// Builds the simulated EuRoC Vicon rooms ("v1", "v2") from the data that describes them:
//  - the room shell (floor, ceiling, four walls) is an axis-aligned box whose extent comes from the GMM
//    component means (0.5 / 99.5 percentiles of x, y and the floor z) and the 3D line map (ceiling: the
//    99.5 percentile of line end-point heights: the Leica GMM stops below the ceiling, the wall-ceiling
//    edges in the line map do not);
//  - every GMM component that is not part of the shell becomes a flat elliptical patch (normal = smallest
//    eigenvector, semi-axes = sigma_scale * sqrt of the two larger eigenvalues): the clutter of the real
//    rooms at its real place;
//  - procedural objects (boxes, mattress-like slabs, poles, wall posters and calibration boards) add
//    structure of known shape;
//  - clearance: every trajectory sample given (the ground truth of all sequences of the room) must stay at
//    least clearance_m from every triangle: a GMM patch too close is shrunk (x0.6, up to 3 times) and then
//    dropped; a procedural object too close is not placed.
#include <quasiloc/core/declared_options.h>
#include <quasiloc/sim/campus_world.h>
#include <quasiloc/sim/euroc_room_data.h>
#include <quasiloc/sim/floor_world.h>
#include <quasiloc/sim/world.h>
#include <random>
#include <string>
#include <vector>

namespace quasiloc::sim
{
/** The world: a EuRoC Vicon room, the ground robot's office floor (floor_world.h), or the outdoor campus
 *  (campus_world.h). */
enum class ViconRoom
{
    v1,
    v2,
    office_floor,
    campus
};
/** "v1", "v2" (how the room's data files and sequences are named), "floor", "campus". */
std::string roomName(ViconRoom room);

/** Section [World]; each key's unit, range and meaning: declare() (sim_options.cpp). */
struct WorldOptions : public core::DeclaredOptions
{
    ViconRoom world = ViconRoom::v1;
    bool gmm_patches = true;
    double gmm_sigma_scale = 2.0;
    double gmm_min_semi_axis_m = 0.04;
    double gmm_max_semi_axis_m = 1.2;
    double shell_margin_m = 0.15;
    int num_boxes = 10;
    int num_slabs = 4;
    int num_poles = 6;
    int num_wall_posters = 10;
    double clearance_m = 0.3;
    double max_cell_m = 0.3;
    int num_lights = 6;
    double light_intensity = 1.2;
    double ambient = 0.05;
    int texture_size_px = 512;
    MaterialSet materials = MaterialSet::procedural;
    int shadow_map_px = 512;
    FloorOptions floor;    ///< world = floor only (keys floor_*)
    CampusOptions campus;  ///< world = campus only (keys campus_*)

    void declare(core::OptionTable& t) override;
    /** The declared ranges, then the rules a range cannot say (InputError naming `input` and the key). */
    void check(const std::string& input) const;
};

struct WorldStats
{
    size_t gmm_components = 0, gmm_shell = 0, gmm_small = 0, gmm_patches = 0, gmm_shrunk = 0, gmm_dropped = 0;
    size_t objects_placed = 0, objects_rejected = 0;
    size_t triangles = 0, vertices = 0;
    double area_m2 = 0;
    double min_clearance_m = 0;  ///< over all given trajectory samples and all triangles (capped at 5 m)
};

/** Paths of the EuRoC room data below shared_dir: data/euroc/maps/gmm/<world>.gmm, .../lines/<world>_line_3d.txt. */
std::string gmmPath(const std::string& shared_dir, const std::string& world);
std::string linesPath(const std::string& shared_dir, const std::string& world);
/** The three EuRoC sequences flown in a room ("v1" -> V1_01_easy, V1_02_medium, V1_03_difficult). */
std::vector<std::string> roomSequences(const std::string& world);
/** cam0 positions of all ground-truth samples of the room's sequences (shared_dir/data/euroc/groundtruth/cam0). */
std::vector<Eigen::Vector3f> loadRoomTrajectoryPositions(const std::string& shared_dir, const std::string& world);

/** Builds the world; `keep_clear` are positions every triangle must stay clearance_m away from. */
World buildWorld(const WorldOptions& options, const std::string& shared_dir, uint64_t seed,
                 const std::vector<Eigen::Vector3f>& keep_clear, WorldStats* stats = nullptr);

class ClearanceGrid;

/** Appends `piece` to `mesh` when every triangle of it stays `clearance` away from the grid's positions (always, with
 *  no positions). */
bool placeIfClear(const Mesh& piece, const ClearanceGrid& grid, float clearance, Mesh& mesh);
/** The same, counted in st.objects_placed or st.objects_rejected. */
bool placeIfClear(const Mesh& piece, const ClearanceGrid& grid, float clearance, Mesh& mesh, WorldStats& st);
/** The first step of every world: its name, materials (seeded by `seed`) and ambient light from `o`. */
World startWorld(const WorldOptions& o, uint64_t seed, const std::string& name);
/** The random stream a world's layout draws from (a different stream from its materials'). */
std::mt19937_64 worldRng(uint64_t seed);
/** The last step of every world: its irradiance (lights and shadows), then st's mesh figures and the clearance of
 *  every triangle from the grid's positions; st is copied to *stats_out when given. */
void finishWorld(World& w, const ClearanceGrid& grid, int shadow_map_px, WorldStats& st, WorldStats* stats_out);

/** Minimum distance between any position and any triangle, searched up to max_search_m (returned if none closer). */
double minClearance(const Mesh& mesh, const std::vector<Eigen::Vector3f>& positions, double max_search_m = 5.0);

}  // namespace quasiloc::sim
