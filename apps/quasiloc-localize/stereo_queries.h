#pragma once
// Stereo queries of quasiloc-localize: "where am I?" from one raw stereo pair against the LiDAR map, by the geometric
// localizer that starts the tracker (reloc/geometric_localizer.h: the pair's depth against the map's distance field,
// place retrieval first on a large map). No database and no image appearance: the pair's geometry only.
//
// The up direction comes from the IMU (the mean accelerometer over the last gravity_window_s before the frame) or,
// with no IMU, from the assumption that the camera is level (image rows horizontal, optical axis horizontal: a
// ground robot's or a car's forward camera).
//
// A multi-frame query (span.frames > 1) joins the stereo clouds of the last frames into the queried frame's camera
// (reloc/stereo_span.h), placed by a frame-to-frame stereo odometry with the gyroscope as a check
// (reloc/stereo_odometry.h), and localizes that cloud: where places repeat, more of the place is seen.
#include <cmath>
#include <deque>
#include <memory>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <quasiloc/reloc/stereo_odometry.h>
#include <quasiloc/reloc/stereo_span.h>
#include <string>

#include "localize_report.h"

namespace quasiloc::app
{
enum class QueryGravity
{
    Imu,
    Level
};

/** Multi-frame stereo queries ([Localize] stereo_span_*). frames = 1: the queried pair alone. */
struct StereoSpanSettings
{
    int frames = 1;         ///< frames joined, the queried one included
    int cloud_step = 1;     ///< of those, every cloud_step-th (counted back from the query) gives its cloud
    int max_points = 4000;  ///< the joined cloud's points at most
};

class StereoQueries
{
   public:
    /** Loads the map and sets up the localizer (distance field, candidate positions, places). InputError naming
     *  map_file for a map that does not load or has no free position. */
    StereoQueries(const std::string& map_file, const core::StereoRig& rig,
                  const reloc::GeometricLocalizationOptions& options, QueryGravity gravity, double gravity_window_s,
                  const StereoSpanSettings& span = {});
    ~StereoQueries();

    /** Every frame passes here (its IMU samples feed the up direction); only queried frames are localized.
     *  frames_to_query: how many frames until the next query (0: this one is queried). Within the span before a
     *  query the frame's odometry step and stereo clouds are computed. */
    void observe(const dataset::StereoFrame& frame, size_t frames_to_query = 0);
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
    void addToSpan(const dataset::StereoFrame& frame, size_t frames_to_query);
    reloc::GeometricLocalization localizeSpan(const dataset::StereoFrame& frame, const Eigen::Vector3d& up);

    map::LidarMap map_;
    core::StereoRig rig_;
    std::unique_ptr<reloc::GeometricLocalizer> localizer_;
    QueryGravity gravity_;
    double gravity_window_s_;
    std::deque<dataset::ImuSample> recent_imu_;
    reloc::GeometricLocalization last_;
    double last_best_error_m_ = NAN;
    double setup_s_ = 0;

    StereoSpanSettings span_settings_;
    double span_voxel_m_;  ///< the joined cloud's voxel: the single frame's ([GeometricLocalization] query_voxel_m)
    std::unique_ptr<reloc::StereoOdometry> odometry_;
    std::unique_ptr<reloc::StereoSpan> span_;
    std::deque<std::pair<double, std::optional<mrpt::poses::CPose3D>>> span_truth_;  ///< t, ground truth
    std::optional<size_t> last_span_index_;
    double last_span_t_ = 0;
    double span_work_ms_ = 0;                ///< odometry and clouds since the last query
    double last_span_work_ms_ = 0;           ///< that work, of the last query
    int span_steps_ = 0, span_refused_ = 0;  ///< odometry steps since the last query, and those refused
    std::string last_span_;                  ///< the last query's span, for describeLast
    std::string last_refusal_;               ///< why the odometry last refused a step since the last query
};

}  // namespace quasiloc::app
