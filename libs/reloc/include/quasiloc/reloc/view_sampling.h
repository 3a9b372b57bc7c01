#pragma once
// Virtual viewpoints over the map's free space, for the database of rendered views (PAPER_NOTES
// "Global localization"): a horizontal position grid, each position at the platform's heights above the floor
// under it, kept only when it is clear of geometry (and, indoors, enclosed by it), then several headings and
// pitches per position.
//
// Options: [ViewSampling] (ViewSamplingOptions::declare, view_sampling.cpp).
//
// Frames: world z is up (gravity along -z), as in the EuRoC/Vicon and KITTI map frames. A view's camera looks
// along its heading, x right, y down (the camera convention of core::CameraModel).
#include <mrpt/poses/CPose3D.h>

#include <quasiloc/core/declared_options.h>
#include <quasiloc/map/lidar_map.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
struct ViewSamplingOptions : public core::DeclaredOptions
{
    double grid_spacing_m = 0.5;
    std::vector<double> heights_m{1.0, 1.6};
    int num_headings = 8;
    std::vector<double> pitches_deg{0.0};
    double clearance_m = 0.3;
    double voxel_m = 0.1;
    bool require_enclosed = true;
    double ceiling_min_share = 0;
    double max_ray_m = 30;
    std::vector<double> region;  ///< empty or {xmin, ymin, xmax, ymax}
    double margin_m = 0.3;

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range, an empty list of heights or
     *  pitches, or a malformed region. */
    void check(const std::string& input) const;
};

struct ViewSamplingStats
{
    size_t grid_positions = 0;  ///< horizontal grid cells tried
    size_t no_floor = 0;        ///< no map point below the cell
    size_t not_clear = 0;       ///< (position, height) too close to geometry
    size_t not_enclosed = 0;    ///< (position, height) outside the map's enclosure
    size_t positions = 0;       ///< (position, height) kept
    double ceiling_share = 0;   ///< of the positions enclosed by walls, those with a ceiling above
    bool ceiling_required = false;
    size_t views = 0;  ///< positions x headings x pitches
};

/** T_world_cam of a camera at p_world looking along heading (rad, about world +z, 0 = +x) and pitch (rad,
 *  positive up), with no roll. */
mrpt::poses::CPose3D viewPose(double x, double y, double z, double heading_rad, double pitch_rad);

/** The viewpoints (T_world_cam), positions in grid order, headings then pitches within a position.
 *  InputError for an empty map or bad options. */
std::vector<mrpt::poses::CPose3D> sampleViewpoints(const map::LidarMap& map, const ViewSamplingOptions& options,
                                                   ViewSamplingStats* stats = nullptr);

}  // namespace quasiloc::reloc
