#pragma once
// The measurement stage: everything the tracker derives from one frame's images, computed once into an immutable
// FrameMeasurement: the left (and right) points, their stereo matches and their matches to the previous frame's
// points, the dense disparity and cloud, the camera's edge field and line segments. The threads live here: a
// measurement is a set of tasks (core::OrderedTasks) that a worker thread starts on while the estimator renders the
// map at its prediction; the estimator claims the edge field when it needs it (PendingMeasurement::edgeField) and
// the whole measurement when it needs the rest (PendingMeasurement::get), helping with what is left meanwhile. Who
// runs a task changes only its timing.
#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <quasiloc/core/ordered_tasks.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/core/worker_thread.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/estimation/direct_alignment.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/frontend/lines.h>
#include <quasiloc/frontend/stereo_matcher.h>
#include <quasiloc/reloc/stereo_cloud.h>
#include <quasiloc/tracking/guided_stereo.h>
#include <quasiloc/tracking/tracking_options.h>
#include <vector>

namespace quasiloc::tracking
{
/** An 8-bit image as gray (BGR converted; gray as it is, not copied). */
cv::Mat grayImage(const cv::Mat& image);

/** What one frame's images give the estimator. Immutable once measured. */
struct FrameMeasurement
{
    double t = 0;
    frontend::FrameFeatures left, right;        ///< ORB points (right: stereo_matching = descriptors only)
    std::vector<frontend::StereoPoint> stereo;  ///< left-right matches
    std::vector<int> stereo_of_left;            ///< left keypoint -> index in stereo (-1: none)
    reloc::StereoDisparity disparity;           ///< stereo_map_points = dense: the SGBM disparity
    std::vector<Eigen::Vector3f> dense;         ///< ... and its cloud (left camera frame)
    /** The previous frame's left points matched to these (query: previous, train: these); empty across a gap longer
     *  than temporal_max_gap_s. */
    std::vector<frontend::PointMatch> temporal;
    estimation::CameraEdgeField edge_field;    ///< requested: the camera side of the direct map alignment
    std::vector<frontend::LineSegment> lines;  ///< requested: the left image's segments (map_lines)
    double ms_edge_field = 0;                  ///< its wall time
};

/** What a frame's measurement includes beyond its points. */
struct MeasurementRequest
{
    bool points = true;       ///< stereo and temporal points, dense stereo (temporal_landmarks)
    bool edge_field = false;  ///< a keyframe aligned to the map
    bool lines = false;       ///< a keyframe with map_lines
    /** temporal_predicted_window: the previous frame's left camera in this frame's left camera frame, as predicted
     *  (T_cam_prevcam); the temporal matching looks for each previous keypoint where this motion moves it. */
    std::optional<Eigen::Isometry3d> T_cam_prevcam;
};

/** Where the camera motion T_cam_prevcam moves each of `previous`'s left keypoints in the current left image: its
 *  stereo point moved and projected; a keypoint without a stereo point (or one that leaves the front of the camera)
 *  moved as a point at infinity (rotation only); one that projects nowhere stays where it was. */
std::vector<cv::Point2f> predictedKeypoints(const FrameMeasurement& previous, const core::CameraModel& camera,
                                            const Eigen::Isometry3d& T_cam_prevcam);

/** A measurement under way. Destroyed before it is taken, it still waits for the worker's tasks. */
class PendingMeasurement
{
   public:
    ~PendingMeasurement();
    /** The camera's edge field: computed now on this thread unless the worker has it already. */
    const estimation::CameraEdgeField& edgeField();
    /** Runs what is left here, waits for the rest, and hands over the measurement. Once only. */
    std::shared_ptr<const FrameMeasurement> get();

   private:
    friend class FrameMeasurer;
    PendingMeasurement() = default;
    std::shared_ptr<FrameMeasurement> m_ = std::make_shared<FrameMeasurement>();
    core::OrderedTasks tasks_;
    size_t edge_field_task_ = 0;
    bool has_edge_field_ = false;
    core::WorkerThread* worker_ = nullptr;  ///< running the tasks too (nullptr: this thread alone)
};

class FrameMeasurer
{
   public:
    /** InputError for bad options. */
    FrameMeasurer(const core::StereoRig& rig, const TrackerOptions& options, const frontend::FrontendOptions& frontend,
                  const estimation::DirectAlignmentOptions& direct);
    ~FrameMeasurer();

    /** The dense stereo (stereo_map_points = dense; must outlive the measurer; nullptr: none); with stereo_matching
     *  = guided the right image's matches are searched around its disparity. */
    void setStereoCloud(const reloc::StereoCloud* cloud);
    /** The surface factor takes the dense SGBM cloud. */
    bool denseStereo() const { return stereo_cloud_ && options_.factors.stereo_map_points == StereoMapPoints::Dense; }
    const reloc::StereoCloud* stereoCloud() const { return stereo_cloud_; }

    /** Starts measuring `frame` (its images must outlive the pending measurement); `previous` (may be null): the
     *  measurement whose left points the temporal matching looks for, taken at previous_t. */
    std::unique_ptr<PendingMeasurement> start(const dataset::StereoFrame& frame, const MeasurementRequest& request,
                                              std::shared_ptr<const FrameMeasurement> previous, double previous_t);
    /** The same, measured on this thread and taken at once. */
    std::shared_ptr<const FrameMeasurement> measure(const dataset::StereoFrame& frame,
                                                    const MeasurementRequest& request,
                                                    std::shared_ptr<const FrameMeasurement> previous,
                                                    double previous_t);

   private:
    std::unique_ptr<PendingMeasurement> start(const dataset::StereoFrame& frame, const MeasurementRequest& request,
                                              std::shared_ptr<const FrameMeasurement> previous, double previous_t,
                                              bool concurrent);
    bool guidedStereo() const { return guided_stereo_ && denseStereo(); }
    void addPointTasks(const dataset::StereoFrame& frame, PendingMeasurement& p,
                       std::shared_ptr<const FrameMeasurement> previous, double previous_t,
                       const std::optional<Eigen::Isometry3d>& motion);
    void matchStereo(FrameMeasurement& m) const;
    void matchTemporal(FrameMeasurement& m, const FrameMeasurement* previous, double previous_t,
                       const std::optional<Eigen::Isometry3d>& T_cam_prevcam) const;
    void edgeField(const cv::Mat& image, FrameMeasurement& m) const;

    TrackerOptions options_;
    core::StereoRig rig_;
    estimation::DirectAlignmentOptions direct_;
    frontend::Frontend left_frontend_, right_frontend_;  ///< one per image: a Frontend is not reentrant
    frontend::StereoMatcher stereo_matcher_;
    std::unique_ptr<frontend::LineDetector> line_detector_;  ///< map_lines
    const reloc::StereoCloud* stereo_cloud_ = nullptr;
    std::unique_ptr<GuidedStereo> guided_stereo_;  ///< stereo_matching = guided, once a stereo cloud is set
    std::unique_ptr<core::WorkerThread> worker_;   ///< concurrent_stages
};
}  // namespace quasiloc::tracking
