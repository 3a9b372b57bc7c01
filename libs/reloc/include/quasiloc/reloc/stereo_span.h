#pragma once
// The stereo clouds of the last frames joined into the newest frame's left camera: a multi-frame stereo query for the
// geometric localizer (GeometricLocalizer::localizePoints). Where places repeat, one frame's few metres of geometry
// fit several of them; the clouds of a second of motion, placed by the camera's own motion (stereo_odometry.h), cover
// more of the place.
//
// StereoSpan keeps up to `frames` frames, each with its clouds and the odometry's motion from the frame before. The
// join walks back from the newest frame while the motion links hold (a step the odometry refused ends the chain),
// moves each frame's points into the newest camera, and thins the union to one point per voxel_m voxel of that
// camera (the newest frame's points first, so that they win their voxels) and then to max_points (every k-th).
#include <Eigen/Geometry>
#include <cstddef>
#include <deque>
#include <vector>

namespace quasiloc::reloc
{
/** One frame of a span: its clouds (left camera frame) and where it is relative to the frame before. */
struct SpanFrame
{
    double t = 0;
    std::vector<Eigen::Vector3f> points;        ///< the geometric check's cloud
    std::vector<Eigen::Vector3f> place_points;  ///< the place profile's cloud (may be empty)
    bool linked = false;  ///< the motion from the frame before is known (the odometry's step was ok)
    Eigen::Isometry3d T_prev_this = Eigen::Isometry3d::Identity();
    bool has_clouds = true;  ///< false: a frame that only carries the motion (its clouds were not computed)
};

/** The joined query. */
struct JoinedClouds
{
    std::vector<Eigen::Vector3f> points, place_points;  ///< in the newest frame's left camera
    int frames = 0;                                     ///< frames whose clouds were joined (the newest included)
    int linked_frames = 0;  ///< frames reached through the motion links (the newest included)
    double span_s = 0;      ///< time from the oldest joined frame to the newest
    double path_m = 0;      ///< camera path over the joined frames (sum of the links' translations)
    double oldest_t = 0;    ///< time of the oldest joined frame
    Eigen::Isometry3d T_newest_oldest = Eigen::Isometry3d::Identity();  ///< that frame's camera in the newest
};

/** Joins clouds given with their poses in the query frame: each moved by its pose, in the order given, thinned to
 *  one point per voxel_m voxel (the first point wins; voxel_m 0: no voxels), then to at most max_points (every k-th).
 */
std::vector<Eigen::Vector3f> joinClouds(const std::vector<const std::vector<Eigen::Vector3f>*>& clouds,
                                        const std::vector<Eigen::Isometry3d>& T_query_cloud, double voxel_m,
                                        size_t max_points);

class StereoSpan
{
   public:
    explicit StereoSpan(int frames) : frames_(frames < 1 ? 1 : frames) {}

    /** Adds the newest frame; the oldest beyond `frames` is dropped. */
    void add(SpanFrame frame);
    void clear() { frames_kept_.clear(); }
    size_t size() const { return frames_kept_.size(); }
    const SpanFrame& newest() const { return frames_kept_.back(); }

    /** The clouds of the newest frame and of those linked to it, in its camera (see the file comment). */
    JoinedClouds join(double voxel_m, size_t max_points, size_t max_place_points) const;

   private:
    int frames_;
    std::deque<SpanFrame> frames_kept_;
};

}  // namespace quasiloc::reloc
