#pragma once
// Virtual viewpoints over the map's free space, for the database of rendered views (issue 8, PAPER_NOTES
// "Global localization"): a horizontal position grid, each position at the platform's heights above the floor
// under it, kept only when it is clear of geometry (and, indoors, enclosed by it), then several headings and
// pitches per position.
//
//   [ViewSampling]
//   grid_spacing_m = 0.5        ; spacing of the horizontal position grid
//   heights_m = 1.0 1.6         ; camera heights above the floor below the position (the platform's heights)
//   num_headings = 8            ; headings evenly spread over 360 deg (the first along +x)
//   pitches_deg = 0             ; camera pitch(es), positive = looking up
//   clearance_m = 0.3           ; no map point within this distance of a viewpoint
//   voxel_m = 0.1               ; occupancy grid of the map used for the clearance / floor / enclosure tests
//   require_enclosed = true     ; indoors: rays in 8 horizontal directions and straight up must all hit the
//                               ;   map within max_ray_m (rejects positions outside the room); false outdoors
//   max_ray_m = 30
//   region = []                 ; optional [xmin ymin xmax ymax] (world metres): sample only there
//   margin_m = 0.3              ; distance kept from the map's horizontal bounds
//
// Frames: world z is up (gravity along -z), as in the EuRoC/Vicon and KITTI map frames. A view's camera looks
// along its heading, x right, y down (the camera convention of core::CameraModel).
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose3D.h>

#include <quasiloc/map/lidar_map.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
struct ViewSamplingOptions : public mrpt::config::CLoadableOptions
{
    double grid_spacing_m = 0.5;
    std::vector<double> heights_m{1.0, 1.6};
    int num_headings = 8;
    std::vector<double> pitches_deg{0.0};
    double clearance_m = 0.3;
    double voxel_m = 0.1;
    bool require_enclosed = true;
    double max_ray_m = 30;
    std::vector<double> region;  ///< empty or {xmin, ymin, xmax, ymax}
    double margin_m = 0.3;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    /** InputError naming `input` and the key for a value that cannot be used. */
    void check(const std::string& input) const;
};

struct ViewSamplingStats
{
    size_t grid_positions = 0;    ///< horizontal grid cells tried
    size_t no_floor = 0;          ///< no map point below the cell
    size_t not_clear = 0;         ///< (position, height) too close to geometry
    size_t not_enclosed = 0;      ///< (position, height) outside the map's enclosure
    size_t positions = 0;         ///< (position, height) kept
    size_t views = 0;             ///< positions x headings x pitches
};

/** T_world_cam of a camera at p_world looking along heading (rad, about world +z, 0 = +x) and pitch (rad,
 *  positive up), with no roll. */
mrpt::poses::CPose3D viewPose(double x, double y, double z, double heading_rad, double pitch_rad);

/** The viewpoints (T_world_cam), positions in grid order, headings then pitches within a position.
 *  InputError for an empty map or bad options. */
std::vector<mrpt::poses::CPose3D> sampleViewpoints(const map::LidarMap& map, const ViewSamplingOptions& options,
                                                   ViewSamplingStats* stats = nullptr);

}  // namespace quasiloc::reloc
