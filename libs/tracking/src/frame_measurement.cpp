#include <mrpt/system/CTicTac.h>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/point_matcher.h>
#include <quasiloc/tracking/frame_measurement.h>

namespace quasiloc::tracking
{
cv::Mat grayImage(const cv::Mat& image)
{
    cv::Mat gray = image;
    if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    return gray;
}

PendingMeasurement::~PendingMeasurement()
{
    // The worker's tasks write into this measurement: they end before it does, whatever happened.
    if (worker_) worker_->waitForError();
}

const estimation::CameraEdgeField& PendingMeasurement::edgeField()
{
    core::require(has_edge_field_, "PendingMeasurement::edgeField", "the edge field was not requested");
    tasks_.runOrWait(edge_field_task_);
    return m_->edge_field;
}

std::shared_ptr<const FrameMeasurement> PendingMeasurement::get()
{
    core::require(m_ != nullptr, "PendingMeasurement::get", "the measurement was taken already");
    tasks_.waitAll();
    if (worker_)
    {
        core::WorkerThread* w = worker_;
        worker_ = nullptr;
        w->wait();
    }
    return std::move(m_);
}

FrameMeasurer::FrameMeasurer(const core::StereoRig& rig, const TrackerOptions& options,
                             const frontend::FrontendOptions& frontend,
                             const estimation::DirectAlignmentOptions& direct)
    : options_(options),
      rig_(rig),
      direct_(direct),
      left_frontend_(frontend),
      right_frontend_(frontend),
      stereo_matcher_(rig, frontend.stereo)
{
    if (options_.factors.map_lines) line_detector_ = std::make_unique<frontend::LineDetector>(frontend.lines);
}

FrameMeasurer::~FrameMeasurer() = default;

void FrameMeasurer::setStereoCloud(const reloc::StereoCloud* cloud)
{
    stereo_cloud_ = cloud;
    guided_stereo_.reset();
    if (cloud && options_.stereo_matching == StereoMatching::Guided)
        guided_stereo_ = std::make_unique<GuidedStereo>(rig_, cloud->rectification(), left_frontend_.options().stereo,
                                                        options_.guided);
}

void FrameMeasurer::matchStereo(FrameMeasurement& m) const
{
    if (guidedStereo())
        m.stereo = guided_stereo_->match(m.left.points.keypoints, m.disparity, m.right.points.keypoints);
    else
        m.stereo = stereo_matcher_.match(m.left.points, m.right.points);
    m.stereo_of_left.assign(m.left.points.size(), -1);
    for (size_t k = 0; k < m.stereo.size(); ++k) m.stereo_of_left[size_t(m.stereo[k].left)] = int(k);
}

std::vector<cv::Point2f> predictedKeypoints(const FrameMeasurement& previous, const core::CameraModel& camera,
                                            const Eigen::Isometry3d& T_cam_prevcam)
{
    const std::vector<cv::KeyPoint>& keypoints = previous.left.points.keypoints;
    std::vector<cv::Point2f> centers(keypoints.size());
    for (size_t i = 0; i < keypoints.size(); ++i)
    {
        const cv::Point2f& k = keypoints[i].pt;
        centers[i] = k;
        const int s = i < previous.stereo_of_left.size() ? previous.stereo_of_left[i] : -1;
        Eigen::Vector2d px;
        if (s >= 0 && camera.project(T_cam_prevcam * previous.stereo[size_t(s)].p_left, px))
            centers[i] = cv::Point2f(float(px.x()), float(px.y()));
        else if (camera.project(T_cam_prevcam.linear() * camera.unproject(Eigen::Vector2d(k.x, k.y)), px))
            centers[i] = cv::Point2f(float(px.x()), float(px.y()));
    }
    return centers;
}

void FrameMeasurer::matchTemporal(FrameMeasurement& m, const FrameMeasurement* previous, double previous_t,
                                  const std::optional<Eigen::Isometry3d>& T_cam_prevcam) const
{
    // The temporal matching looks for a keypoint within temporal_window_px of where it was (or of where the
    // predicted motion moves it): across a gap (dropped frames) the camera has moved farther than that, and what it
    // matches there are other points.
    if (!previous || previous->stereo.empty() || m.t - previous_t > options_.temporal_max_gap_s) return;
    frontend::PointMatchingOptions pm = left_frontend_.options().point_matching;
    pm.window_px = options_.temporal_window_px;
    if (!T_cam_prevcam)
    {
        m.temporal = frontend::matchPoints(previous->left.points, m.left.points, pm);
        return;
    }
    frontend::SearchRegion region;
    region.centers = predictedKeypoints(*previous, rig_.left, *T_cam_prevcam);
    region.radius_px = options_.temporal_window_px;
    m.temporal = frontend::matchPoints(previous->left.points, m.left.points, pm, &region);
}

void FrameMeasurer::edgeField(const cv::Mat& image, FrameMeasurement& m) const
{
    mrpt::system::CTicTac tic;
    const core::CameraModel& camera = rig_.left;
    core::require(
        image.cols == camera.width && image.rows == camera.height, "camera image",
        "size " + std::to_string(image.cols) + "x" + std::to_string(image.rows) + " differs from the camera model's");
    m.edge_field = estimation::buildCameraEdgeField(direct_, image);  // checks the type, converts BGR to gray
    m.ms_edge_field = tic.Tac() * 1e3;
}

void FrameMeasurer::addPointTasks(const dataset::StereoFrame& frame, PendingMeasurement& p,
                                  std::shared_ptr<const FrameMeasurement> previous, double previous_t,
                                  const std::optional<Eigen::Isometry3d>& motion)
{
    // In the order they are claimed: the left image's points, the dense disparity, the right image's points
    // (descriptor matching), then the matchings and the dense cloud, each after its inputs. Small tasks, so that
    // whichever thread is free first takes the next: ORB and the dense stereo are single-threaded for the most part.
    FrameMeasurement& m = *p.m_;
    core::OrderedTasks& tasks = p.tasks_;
    // Points only: the stereo and temporal matching use no line, so the front-end's line branch is skipped.
    const size_t left = tasks.add([this, &frame, &m] { left_frontend_.extractPoints(frame.left, cv::Mat(), m.left); });
    std::vector<size_t> stereo_inputs{left};
    const bool dense = denseStereo();
    size_t disparity = 0;
    if (dense)
    {
        disparity = tasks.add([this, &frame, &m] {
            m.disparity = stereo_cloud_->disparity(frame.left, frame.right, "frame " + std::to_string(frame.index));
        });
        stereo_inputs.push_back(disparity);
    }
    if (!guidedStereo())
        stereo_inputs.push_back(
            tasks.add([this, &frame, &m] { right_frontend_.extractPoints(frame.right, cv::Mat(), m.right); }));
    tasks.add([this, &tasks, &m, left, previous, previous_t, motion] {
        tasks.wait(left);
        matchTemporal(m, previous.get(), previous_t, motion);
    });
    tasks.add([this, &tasks, &m, stereo_inputs] {
        for (size_t i : stereo_inputs) tasks.wait(i);
        matchStereo(m);
    });
    if (dense)
        tasks.add([this, &tasks, &m, disparity] {
            tasks.wait(disparity);
            m.dense = stereo_cloud_->points(m.disparity);
        });
}

std::unique_ptr<PendingMeasurement> FrameMeasurer::start(const dataset::StereoFrame& frame,
                                                         const MeasurementRequest& request,
                                                         std::shared_ptr<const FrameMeasurement> previous,
                                                         double previous_t)
{
    return start(frame, request, std::move(previous), previous_t,
                 options_.concurrent_stages && cv::getNumThreads() > 1);
}

std::shared_ptr<const FrameMeasurement> FrameMeasurer::measure(const dataset::StereoFrame& frame,
                                                               const MeasurementRequest& request,
                                                               std::shared_ptr<const FrameMeasurement> previous,
                                                               double previous_t)
{
    return start(frame, request, std::move(previous), previous_t, false)->get();
}

std::unique_ptr<PendingMeasurement> FrameMeasurer::start(const dataset::StereoFrame& frame,
                                                         const MeasurementRequest& request,
                                                         std::shared_ptr<const FrameMeasurement> previous,
                                                         double previous_t, bool concurrent)
{
    std::unique_ptr<PendingMeasurement> p(new PendingMeasurement());
    FrameMeasurement& m = *p->m_;
    m.t = frame.timestamp;
    if (request.points) addPointTasks(frame, *p, std::move(previous), previous_t, request.T_cam_prevcam);
    if (request.lines) p->tasks_.add([this, &frame, &m] { m.lines = line_detector_->detect(grayImage(frame.left)); });
    if (request.edge_field)
    {
        // Last in claiming order: the estimator claims it ahead of its turn once the map's render is done.
        p->edge_field_task_ = p->tasks_.add([this, &frame, &m] { edgeField(frame.left, m); });
        p->has_edge_field_ = true;
    }
    if (concurrent)
    {
        if (!worker_) worker_ = std::make_unique<core::WorkerThread>();
        core::OrderedTasks& tasks = p->tasks_;
        worker_->start([&tasks] {
            while (tasks.runNext())
            {}
        });
        p->worker_ = worker_.get();
    }
    return p;
}
}  // namespace quasiloc::tracking
