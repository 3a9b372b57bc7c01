#pragma once
// Stereo queries of quasiloc-localize: "where am I?" from one raw stereo pair against the LiDAR map, by the geometric
// localizer that starts the tracker (reloc/geometric_localizer.h: the pair's depth against the map's distance field,
// place retrieval first on a large map). No database and no image appearance: the pair's geometry only.
//
// The up direction comes from the IMU (the mean accelerometer over the last gravity_window_s before the frame) or,
// with no IMU, from the assumption that the camera is level (image rows horizontal, optical axis horizontal: a
// ground robot's or a car's forward camera).
#include <cmath>
#include <deque>
#include <memory>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <string>

#include "localize_report.h"

namespace quasiloc::app
{
enum class QueryGravity
{
    Imu,
    Level
};

class StereoQueries
{
   public:
    /** Loads the map and sets up the localizer (distance field, candidate positions, places). InputError naming
     *  map_file for a map that does not load or has no free position. */
    StereoQueries(const std::string& map_file, const core::StereoRig& rig,
                  const reloc::GeometricLocalizationOptions& options, QueryGravity gravity, double gravity_window_s);
    ~StereoQueries();

    /** Every frame passes here (its IMU samples feed the up direction); only queried frames are localized. */
    void observe(const dataset::StereoFrame& frame);
    /** Localizes the frame's raw pair. A frame without the IMU samples the up direction needs is "not localized"
     *  with that reason. */
    QueryRow localize(const dataset::StereoFrame& frame);
    /** One line of diagnostics for the last query: the decision, how far its best pose is from the ground truth
     *  (answer or not), inliers, candidates, places retrieved, the rival place. */
    std::string describeLast() const;
    /** Map points, candidate positions and places, for the console. */
    std::string summary() const;

   private:
    std::optional<Eigen::Vector3d> upInCamera() const;

    map::LidarMap map_;
    core::StereoRig rig_;
    std::unique_ptr<reloc::GeometricLocalizer> localizer_;
    QueryGravity gravity_;
    double gravity_window_s_;
    std::deque<dataset::ImuSample> recent_imu_;
    reloc::GeometricLocalization last_;
    double last_best_error_m_ = NAN;
    double setup_s_ = 0;
};

}  // namespace quasiloc::app
