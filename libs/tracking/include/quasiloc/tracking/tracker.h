#pragma once
// The tracker: stereo-inertial tracking against the LiDAR map, one frame at a time.
//
// One step per frame: IMU preintegration from the previous state -> predicted pose -> on keyframes, direct map
// alignment (estimation/direct_alignment.h) from the prediction, with the prediction's uncertainty as its prior ->
// a two-frame window (the previous state with its marginal as prior, the IMU factor, the map edges' residuals as a
// factor linearised from the aligned pose, the frame's stereo points against the map's surfaces, temporal stereo
// landmarks, and the optional structural factors) -> pose, velocity and biases -> the marginal for the next frame.
// What the step derives from the frame's images comes from the measurement stage (frame_measurement.h), which runs
// beside the map's render and alignment on its own thread; the step itself reads sequentially.
//
// Why the direct term and not feature matches for the map: camera descriptors do not match quasi-image descriptors
// across the modality gap, while map edges align with camera edges from a prediction within ~0.1 m / 1 deg; the IMU
// keeps the prediction inside that basin between map updates (docs/experiments.md has the figures).
//
// IMU biases: the tracker starts from the prior it is given (the calibration's, or a static initialization's);
// while the platform has stood still since the start each frame's prior takes the standing span's gyroscope bias and
// a zero velocity (a zero-velocity update); once it moves (the IMU says so, or the image: a start or a restart during
// a steady run reads as standing to the IMU), the window estimates the biases with their random walk.
// With zero_velocity_updates, every later standstill the IMU and the image agree on zeroes the velocity too (after
// the frame's measurement, before the window); while the track is lost
// the gate may widen the velocity's uncertainty (zero_velocity_update.h).
//
// Keyframes: a map alignment every keyframe_every frames; a correction larger than the gate is a miss
// (FrameReport::alignment_misses counts them in a row).
//
// The tracker measures and estimates; it decides nothing about trust. Each step takes the frame and the stereo gate
// the track monitor set (stereo_gate.h) and returns its whole result by value (TrackStep). The start, the loss check,
// the relocalization and the policy are TrackingSession's and TrackMonitor's (tracking_session.h, track_monitor.h).
// Options: tracking_options.h.
#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <optional>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/estimation/estimator_options.h>
#include <quasiloc/estimation/imu_preintegration.h>
#include <quasiloc/estimation/map_refinement.h>
#include <quasiloc/estimation/tracking_window.h>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/tracking/frame_measurement.h>
#include <quasiloc/tracking/frame_report.h>
#include <quasiloc/tracking/map_lines.h>
#include <quasiloc/tracking/map_planes.h>
#include <quasiloc/tracking/static_initialization.h>
#include <quasiloc/tracking/stereo_gate.h>
#include <quasiloc/tracking/tracking_options.h>
#include <quasiloc/tracking/zero_velocity_update.h>
#include <string>

namespace quasiloc::tracking
{

/** The tracker's estimate at a time: the state and its marginal (what the next step starts from). */
struct TrackEstimate
{
    estimation::FrameState state;  ///< body frame = IMU
    estimation::StatePrior marginal;
    /** The biases with their marginal sigmas (the largest axis): what a restart starts from. */
    ImuBiasPrior biasPrior() const;
};

/** Everything one step of the tracker gives: the frame's report, the estimate after it, and the frame's
 *  measurement (its dense stereo cloud is what the loss check weighs against the map). */
struct TrackStep
{
    FrameReport report;
    TrackEstimate estimate;
    std::shared_ptr<const FrameMeasurement> measurement;
    /** The frame's dense stereo cloud (left camera frame; empty unless stereo_map_points = dense). */
    const std::vector<Eigen::Vector3f>& denseCloud() const;
};

/** The stereo surface term's points as window terms, one per truncation (a window term has one truncation for all
 *  its points): a point's truncation is truncation_m, or with truncation_sigmas > 0 at least that many of its sigma,
 *  rounded up to truncation_m times a power of sqrt(2). The terms share effective_points in proportion to their
 *  points, so that together they weigh what one term of all the points would. Fields left unset. */
std::vector<estimation::MapDistanceTerm> stereoMapTermsByTruncation(const std::vector<Eigen::Vector3d>& p_cam,
                                                                    const std::vector<double>& sigma_m,
                                                                    double truncation_m, double truncation_sigmas,
                                                                    double effective_points);

/** A stereo point's sigma against the map with its depth noise along the map's normal only: sigma_m =
 *  hypot(map_sigma_m, depth sigma) becomes hypot(map_sigma_m, depth sigma x |cos|) of the angle between the point's
 *  ray and the map's normal at T_world_cam * p_cam (the steepest of the distance field's gradients probed 0.12 m off
 *  the point along each axis; a depth error moves a point along its ray); sigma_m where no surface is that near. */
double sigmaAlongNormal(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam,
                        const Eigen::Vector3d& p_cam, double sigma_m, double map_sigma_m);

class Tracker
{
   public:
    /** `renderer` renders the map and must outlive the tracker. InputError for bad options. */
    Tracker(const TrackerOptions& options, const estimation::MapRefinementOptions& refinement,
            const estimation::EstimatorOptions& estimator, const estimation::ReweightingOptions& reweighting,
            const core::StereoRig& rig, const estimation::ImuNoise& imu_noise, quasi::QuasiRenderer& renderer,
            const frontend::FrontendOptions& frontend);
    ~Tracker();

    /** Starts at time t with the left camera at T_world_cam0, the body moving at v_world and the IMU biases of
     *  `biases` (the calibration's prior, a static initialization's, or a track's before a relocalization);
     *  `frame` (optional, the frame at t) gives the first stereo points for temporal landmarks. */
    TrackEstimate initialize(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                             const ImuBiasPrior& biases, const dataset::StereoFrame* frame = nullptr);
    /** The same with the uncertainty of a globally localized start (init_global_sigma_*) instead of init_sigma_*. */
    TrackEstimate initializeFromGlobal(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                                       const ImuBiasPrior& biases, const dataset::StereoFrame* frame);
    /** The map term in use: map_term, with auto resolved by the map (factor on a thin map with reflectivity). */
    MapTerm mapTerm() const { return options_.map_term; }
    /** Why auto resolved as it did ("" when map_term was given): what the session prints. */
    const std::string& mapTermReason() const { return map_term_reason_; }

    /** The map's distance field (must outlive the tracker; nullptr: none): enables stereo_map_factor. */
    void setMapDistanceField(const map::DistanceField* field) { distance_field_ = field; }
    /** The dense stereo of stereo_map_points = dense (must outlive the tracker); with stereo_matching = guided
     *  the right image's matches are searched around its disparity. */
    void setStereoCloud(const reloc::StereoCloud* cloud) { measurer_.setStereoCloud(cloud); }

    /** Tracks one stereo frame (its IMU samples since the previous frame included); `gate` decides whether the
     *  frame's stereo factors enter the window, from how well the stereo agrees with the map. */
    TrackStep step(const dataset::StereoFrame& frame, const StereoGate& gate);

   private:
    /** map_term = auto: factor when the map's reflectivity varies and its surfaces are thin, else none. */
    void resolveAutoMapTerm();
    std::string map_term_reason_;
    /** What the map alignment of a keyframe gives the window: the edge model (alive until the window has used it),
     *  the aligned pose its factor is linearised from, and the pose the structural factors associate at. */
    struct MapAlignment
    {
        std::shared_ptr<const estimation::DirectAlignmentModel> model;
        std::optional<Eigen::Isometry3d> T_map_body;
        std::optional<Eigen::Isometry3d> T_world_cam;  ///< map_lines / map_points / map_planes
        std::vector<MapLine> map_lines;                ///< map_lines: the quasi-image's, lifted
    };
    TrackEstimate start(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                        const dataset::StereoFrame* frame, double sigma_m, double sigma_deg, double sigma_v,
                        const ImuBiasPrior& biases);
    /** The standstill since the start (static_initialization): true while it lasts (the prior is then updated).
     *  It ends when the IMU or the image (the previous frame's keypoint motion) says the platform moves. */
    bool updateStandstill(const dataset::StereoFrame& frame);
    /** While the platform has stood still since the start (static_initialization): the previous state's prior takes
     *  the standing span's gyroscope bias and a zero velocity (as OpenVINS's zero-velocity update), so a start
     *  that is tracked from its first frame still gets what a static initialization gives. */
    void applyStandstill(const StaticImuEstimate& still);
    /** How far the left image's keypoints moved (medians, NaN: too few): from the previous frame, and since their
     *  first sighting for those followed over at least 3 and at least 10 frames. */
    struct ImageMotion
    {
        double frame_px = NAN, short_tracked_px = NAN, tracked_px = NAN;
        bool moving(double max_px) const;
    };
    /** The frame's image motion against the previous frame (before the frame becomes the previous one). */
    void measureImageMotion(const FrameMeasurement& m);
    /** zero_velocity_updates: when the IMU says the platform stands now and the image agrees (the median motion of
     *  the keypoints followed over the last frames is at most zero_velocity_max_motion_px), the previous state's
     *  velocity is zero to within zero_velocity_sigma_m_s; true then. */
    bool zeroVelocityUpdate(bool imu_standing);
    /** The gate's velocity_random_walk over the time since the previous state (while lost). */
    void widenVelocityWhileLost(const dataset::StereoFrame& frame, const StereoGate& gate);
    /** The IMU's prediction of the frame's state, and the alignment prior's sigmas into `rep`. */
    estimation::FrameState predict(const dataset::StereoFrame& frame, estimation::ImuPreintegration& imu,
                                   FrameReport& rep) const;
    /** The measurement stage's request for this frame (temporal_predicted_window: with the camera motion from the
     *  previous state to `predicted`). */
    MeasurementRequest request(bool keyframe, const estimation::FrameState& predicted) const;

    // Map terms (tracker_map_terms.cpp).
    /** Direct map alignment from the prediction: the map rendered at the prediction and its edge model, aligned to
     *  the measurement's edge field by LM, gated; the edge factor into `in` when accepted. */
    MapAlignment alignToMap(const estimation::FrameState& predicted, PendingMeasurement& measurement,
                            estimation::WindowInput& in, FrameReport& rep);
    /** How well the stereo points agree with the map at the edge-aligned pose, which depends on the left image
     *  alone (rep.stereo_map_sigmas), and whether `gate` admits them (false: rep.stereo_rejected). */
    bool gateStereo(const FrameMeasurement& m, const MapAlignment& a, const StereoGate& gate, FrameReport& rep) const;
    /** The factors on the frame's measurement: planes, points, lines, surfaces, landmarks. Without `stereo_ok` the
     *  stereo's factors (planes, surfaces, landmarks) are left out, and the frame's stereo is not the next frame's
     *  landmarks either; without `map_terms` the stereo's distance to the map is left out. */
    void addVisualTerms(const dataset::StereoFrame& frame, const std::shared_ptr<const FrameMeasurement>& m,
                        const MapAlignment& a, bool stereo_ok, bool map_terms, estimation::WindowInput& in,
                        FrameReport& rep);
    /** The stereo points' distance to the map's surfaces as window factors (stereo_map_factor). */
    void addStereoMapTerm(const FrameMeasurement& m, estimation::WindowInput& in) const;
    /** The points that term and the stereo gate use (the dense cloud, or the sparse matches) with their sigmas. */
    void stereoMapPoints(const FrameMeasurement& m, std::vector<Eigen::Vector3d>& p_cam,
                         std::vector<double>& sigma_m) const;
    /** The stereo points that the map terms use (depth 0.2 .. stereo_map_max_depth_m) and their sigma against the
     *  map: stereo_map_sigma_m and the disparity's depth noise (z^2 / (f b) stereo_disparity_sigma_px). */
    void mapPointsWithSigma(const FrameMeasurement& m, std::vector<Eigen::Vector3d>& p_cam,
                            std::vector<double>& sigma_m) const;
    /** The map lines of the quasi-image rendered at the prediction (map_lines), lifted at its pose. */
    std::vector<MapLine> quasiImageLines(FrameReport& rep) const;
    /** Point-to-line map factors of a keyframe (map_lines): `map_lines` against the camera's segments, associated
     *  at T_world_cam. */
    void addMapLines(const std::vector<frontend::LineSegment>& camera_lines, const std::vector<MapLine>& map_lines,
                     const Eigen::Isometry3d& T_world_cam, double sigma_m, double sigma_rad,
                     estimation::WindowInput& in, FrameReport& rep);
    MapLineOptions mapLineOptions() const;
    /** Point factors of a keyframe (map_points): the keypoints of the quasi-image rendered at the prediction against
     *  the left image's (`camera`), associated at T_world_cam. */
    void addMapPoints(const dataset::StereoFrame& frame, const frontend::FrameFeatures& camera,
                      const Eigen::Isometry3d& T_world_cam, estimation::WindowInput& in, FrameReport& rep);
    /** Point-to-plane factors of a keyframe (map_planes): the frame's stereo points at T_world_cam. */
    void addMapPlanes(const FrameMeasurement& m, const Eigen::Isometry3d& T_world_cam, estimation::WindowInput& in,
                      FrameReport& rep) const;

    /** Landmarks between the previous frame's stereo points and `current`'s (its temporal matches); `current`
     *  becomes the previous frame of the next step. */
    void temporalLandmarks(std::shared_ptr<const FrameMeasurement> current, double t,
                           std::vector<estimation::TemporalLandmark>& out);
    /** The two-frame window: the new state and marginal (or the prediction when it fails). */
    void solveWindow(const estimation::FrameState& predicted, const estimation::ImuPreintegration& imu,
                     const MapAlignment& a, estimation::WindowInput& in, FrameReport& rep);

    TrackerOptions options_;
    estimation::MapRefinementOptions refinement_;
    estimation::EstimatorOptions estimator_;
    estimation::ReweightingOptions reweighting_;
    estimation::StereoGeometry stereo_;
    estimation::ImuNoise imu_noise_;
    quasi::QuasiRenderer& renderer_;
    const map::LidarMap& map_;  ///< the renderer's (map_points: lifting through provenance)
    frontend::FrontendOptions frontend_options_;
    core::StereoRig rig_;
    Eigen::Isometry3d T_body_cam_ = Eigen::Isometry3d::Identity();
    FrameMeasurer measurer_;
    quasi::QuasiImage quasi_;                               ///< the map rendered at the last keyframe's prediction
    std::unique_ptr<frontend::Frontend> quasi_frontend_;    ///< map_points: the quasi-image's keypoints
    std::unique_ptr<MapPlaneAssociator> plane_associator_;  ///< map_planes
    std::unique_ptr<MapLineExtractor> line_extractor_;      ///< map_lines
    std::optional<StaticInitializer> standstill_;
    std::optional<StandstillWatch> standstill_watch_;  ///< zero_velocity_updates
    KeypointTracks keypoint_tracks_, short_keypoint_tracks_;
    ImageMotion image_motion_;  ///< the last frame's
    const map::DistanceField* distance_field_ = nullptr;

    /** The last frame whose stereo entered the window, at previous_t_: the temporal landmarks' other end. */
    std::shared_ptr<const FrameMeasurement> previous_;
    double previous_t_ = 0;
    bool initialized_ = false;
    estimation::FrameState state_;
    estimation::StatePrior prior_;
    size_t frames_ = 0;
    int misses_ = 0;
};

}  // namespace quasiloc::tracking
