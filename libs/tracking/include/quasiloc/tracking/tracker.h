#pragma once
// The tracker: stereo-inertial tracking against the LiDAR map, one frame at a time.
//
// Per frame: IMU preintegration from the previous state -> predicted pose -> on keyframes, direct map alignment
// (estimation/direct_alignment.h) from the prediction, with the prediction's uncertainty as its prior -> a two-frame
// window (the previous state with its marginal as prior, the IMU factor, the map edges' residuals as a factor
// linearised from the aligned pose, the frame's stereo points against the map's surfaces, temporal stereo
// landmarks, and the optional structural factors) -> pose, velocity and biases -> the marginal for the next frame.
//
// Why the direct term and not feature matches for the map: camera descriptors do not match quasi-image descriptors
// across the modality gap, while map edges align with camera edges from a prediction within ~0.1 m / 1 deg; the IMU
// keeps the prediction inside that basin between map updates (docs/experiments.md has the figures).
//
// IMU biases: the tracker starts from the prior it is given (the calibration's, or a static initialization's);
// while the platform has stood still since the start each frame's prior takes the standing span's gyroscope bias and
// a zero velocity (a zero-velocity update); once it moves, the window estimates the biases with their random walk.
//
// Keyframes: a map alignment every keyframe_every frames; a correction larger than the gate is a miss, and
// lost_after_misses misses in a row mark the track lost (FrameReport::lost). The start, the loss check and the
// relocalization are TrackingSession's (tracking_session.h). Options: tracking_options.h.
#include <Eigen/Geometry>
#include <quasiloc/core/ordered_tasks.h>
#include <quasiloc/core/worker_thread.h>

#include <memory>
#include <optional>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/estimation/estimator_options.h>
#include <quasiloc/estimation/imu_preintegration.h>
#include <quasiloc/estimation/map_refinement.h>
#include <quasiloc/estimation/tracking_window.h>
#include <quasiloc/frontend/stereo_matcher.h>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/reloc/stereo_cloud.h>
#include <quasiloc/tracking/guided_stereo.h>
#include <quasiloc/tracking/map_lines.h>
#include <quasiloc/tracking/map_planes.h>
#include <quasiloc/tracking/static_initialization.h>
#include <quasiloc/tracking/tracking_options.h>
#include <string>

namespace quasiloc::tracking
{

/** What the tracker did on one frame (a row of the diagnostics CSV). */
struct FrameReport
{
    double t = 0;
    Eigen::Isometry3d T_world_cam0 = Eigen::Isometry3d::Identity();
    bool keyframe = false;
    bool map_update = false;       ///< the map alignment was accepted as a measurement
    double correction_m = 0, correction_deg = 0;  ///< map alignment minus prediction
    double edge_inlier_ratio = 0;
    int edge_points = 0;
    double prior_sigma_m = 0, prior_sigma_deg = 0;
    bool lost = false;
    int landmarks = 0;
    int stereo_map_points = 0;  ///< stereo points in the map-distance factor
    /** The stereo check on keyframes: the stereo points' median distance to the map's surfaces at the edge-aligned
     *  pose, in point sigmas (NaN: not checked). Above stereo_check_max_sigmas the stereo disagrees with the map
     *  (a left/right desync, a broken calibration): its factors are left out of the frame. */
    double stereo_map_sigmas = NAN;
    bool stereo_rejected = false;
    int camera_lines = 0, map_lines = 0, line_factors = 0;  ///< map_lines: segments, lifted map lines, factors
    double line_candidates = 0;  ///< mean candidates per line factor
    double line_window_px = 0;
    double ms_lines = 0;
    int quasi_keypoints = 0, point_factors = 0;  ///< map_points: the quasi-image's keypoints, point factors
    double ms_points = 0;
    int plane_factors = 0;  ///< map_planes
    double plane_candidates = 0;  ///< mean candidates per plane factor
    double ms_planes = 0;
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero(), acc_bias = Eigen::Vector3d::Zero();  ///< estimated
    bool standing = false;  ///< the platform has stood still since the start (static_initialization)
    /** Their marginal sigmas per axis after the frame (rad/s, m/s^2). */
    Eigen::Vector3d gyro_bias_sigma = Eigen::Vector3d::Zero(), acc_bias_sigma = Eigen::Vector3d::Zero();
    /** Wall times [ms]. ms_image: the camera edge field (on the tracking thread, after the render); ms_align:
     *  render, map model, edge field and LM, on the tracking thread, while the worker runs the stereo tasks;
     *  ms_visual: the wait for what is left of those (stereo points, dense stereo, their matching, segments) and
     *  the map factors on the points; ms_window: the window, of which ms_window_solve its Ceres solve and
     *  ms_window_marginal the marginal handed to the next frame; ms_total: the whole frame. */
    double ms_predict = 0, ms_image = 0, ms_align = 0, ms_visual = 0, ms_window = 0, ms_total = 0;
    double ms_window_solve = 0, ms_window_marginal = 0;
};

class Tracker
{
   public:
    /** `renderer` renders the map; `frontend` is unused by the direct method but owned by the refiner's
     *  interface. Both must outlive the tracker. InputError for bad options. */
    Tracker(const TrackerOptions& options, const estimation::MapRefinementOptions& refinement,
            const estimation::EstimatorOptions& estimator, const estimation::ReweightingOptions& reweighting,
            const core::StereoRig& rig, const estimation::ImuNoise& imu_noise, quasi::QuasiRenderer& renderer,
            frontend::Frontend& frontend);
    ~Tracker();

    /** Starts at time t with the left camera at T_world_cam0, the body moving at v_world and the IMU biases of
     *  `biases` (the calibration's prior, a static initialization's, or a track's before a relocalization);
     *  `frame` (optional, the frame at t) gives the first stereo points for temporal landmarks. */
    void initialize(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                    const ImuBiasPrior& biases, const dataset::StereoFrame* frame = nullptr);
    /** The same with the uncertainty of a globally localized start (init_global_sigma_*) instead of init_sigma_*. */
    void initializeFromGlobal(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
                              const ImuBiasPrior& biases, const dataset::StereoFrame* frame);
    /** The map term in use: map_term, with auto resolved by the map (factor with reflectivity, else none). */
    MapTerm mapTerm() const { return options_.map_term; }
    /** The biases now, with their marginal sigmas (the largest axis): what a restart after a loss starts from. */
    ImuBiasPrior biasPrior() const;
    /** The current estimate (body frame = IMU). */
    const estimation::FrameState& state() const { return state_; }
    bool initialized() const { return initialized_; }

    /** The map's distance field (must outlive the tracker; nullptr: none): enables stereo_map_factor. */
    void setMapDistanceField(const map::DistanceField* field) { distance_field_ = field; }
    /** The dense stereo of stereo_map_points = dense (must outlive the tracker); with stereo_matching = guided
     *  the right image's matches are searched around its disparity. */
    void setStereoCloud(const reloc::StereoCloud* cloud);

    /** The stereo check's bound for the next frames, in point sigmas (0: the stereo is never rejected); by default
     *  stereo_check_max_sigmas. The session sets it: the check trusts the edge-aligned pose, which after a gap or a
     *  restart can be the wrong one while the stereo is what brings the track back. */
    void setStereoCheckBound(double max_sigmas) { stereo_check_bound_ = max_sigmas; }

    /** Whether the frame's map alignment fits the camera's edges as well as they usually do (edge inlier ratio at
     *  least stereo_check_min_edge_ratio of the running mean over frames whose stereo agreed; true before there is
     *  a mean). Aligned from a wrong pose (a restart, a kidnap, the end of a gap) the edges settle in a poorer
     *  optimum. */
    bool edgesAsUsual(const FrameReport& r) const;

    /** Tracks one stereo frame (its IMU samples since the previous frame included). */
    FrameReport track(const dataset::StereoFrame& frame);
    /** The last tracked frame's dense stereo cloud (left camera frame; empty unless stereo_map_points = dense): the
     *  loss check reuses it instead of running the same SGBM again. */
    const std::vector<Eigen::Vector3f>& lastDenseCloud() const { return last_dense_; }

   private:
    /** What the map alignment of a keyframe gives the window: the edge model (alive until the window has used it),
     *  the aligned pose its factor is linearised from, and the pose the structural factors associate at. */
    struct MapAlignment
    {
        std::shared_ptr<const estimation::DirectAlignmentModel> model;
        std::optional<Eigen::Isometry3d> T_map_body;
        std::optional<Eigen::Isometry3d> T_world_cam;  ///< map_lines / map_points / map_planes
    };
    /** The stereo points of one frame: left and right points (points-only extraction) and their stereo matches. */
    struct StereoPoints
    {
        frontend::FrameFeatures left, right;
        std::vector<frontend::StereoPoint> stereo;
        std::vector<int> stereo_of_left;  ///< left keypoint -> index in stereo (-1: none)
        std::vector<Eigen::Vector3f> dense;  ///< stereo_map_points = dense: the SGBM cloud (left camera frame)
        reloc::StereoDisparity disparity;    ///< the same: its disparity (guided stereo matching)
        /** The previous frame's left points matched to these (query: previous, train: these); empty across a gap
         *  longer than temporal_max_gap_s. */
        std::vector<frontend::PointMatch> temporal;
    };
    /** The standstill since the start (static_initialization): true while it lasts (the prior is then updated). */
    bool updateStandstill(const dataset::StereoFrame& frame);
    /** The IMU's prediction of the frame's state, and the alignment prior's sigmas into `rep`. */
    estimation::FrameState predict(const dataset::StereoFrame& frame, estimation::ImuPreintegration& imu,
                                   FrameReport& rep) const;
    /** Direct map alignment of `frame` from the prediction (the render, the camera's edge field, the LM), gated; the
     *  edge factor into `in` when accepted. */
    MapAlignment alignToMap(const estimation::FrameState& predicted, const dataset::StereoFrame& frame,
                            estimation::WindowInput& in, FrameReport& rep);
    /** The factors on the frame's stereo points and segments: planes, points, lines, surfaces, landmarks. Without
     *  `stereo_ok` the stereo's factors (planes, surfaces, landmarks) are left out, and so is the frame's stereo as
     *  the next frame's landmarks. */
    void addVisualTerms(StereoPoints stereo_points, const std::vector<frontend::LineSegment>& camera_lines,
                        const std::vector<MapLine>& map_lines, const MapAlignment& a, bool stereo_ok,
                        estimation::WindowInput& in, FrameReport& rep);
    /** The stereo check (stereo_check_max_sigmas): false when the stereo points disagree with the map at the
     *  edge-aligned pose, which depends on the left image alone. Fills rep.stereo_map_sigmas / stereo_rejected. */
    bool checkStereoAgainstMap(const StereoPoints& points, const MapAlignment& a, FrameReport& rep);
    /** The two-frame window: the new state and marginal (or the prediction when it fails). */
    void solveWindow(const estimation::FrameState& predicted, const estimation::ImuPreintegration& imu,
                     const MapAlignment& a, estimation::WindowInput& in, FrameReport& rep);
    /** Depends on the images alone (and the front-end, used by no other stage): may run on a second thread. */
    StereoPoints extractStereo(const dataset::StereoFrame& frame);
    /** Its parts. Independent tasks of a frame: the left points (frontend_), the right points (right_frontend_;
     *  not with guided matching) and the dense cloud. Then, with them: the stereo matches. */
    void extractLeftPoints(const dataset::StereoFrame& frame, StereoPoints& sp);
    void extractRightPoints(const dataset::StereoFrame& frame, StereoPoints& sp);
    void matchStereoPoints(StereoPoints& sp) const;
    /** sp.temporal from the previous frame's points (sp taken at time t). Reads only what the frame's tasks leave
     *  alone (the previous frame's points): a task of its own, beside the alignment. */
    void matchTemporal(StereoPoints& sp, double t) const;
    /** Both matchings of the frame's points (taken at time t), once its stereo inputs are there. */
    void matchFramePoints(StereoPoints& sp, double t) const;
    /** The dense stereo (stereo_map_points = dense; nothing otherwise) in two steps, two tasks of a frame:
     *  sp.disparity, then sp.dense from it. */
    void extractDisparity(const dataset::StereoFrame& frame, StereoPoints& sp) const;
    void extractDenseCloud(StereoPoints& sp) const;
    void start(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
               const dataset::StereoFrame* frame, double sigma_m, double sigma_deg, double sigma_v,
               const ImuBiasPrior& biases);
    /** The surface factor takes the dense SGBM cloud (stereo_map_points = dense and a cloud given). */
    bool denseStereo() const { return stereo_cloud_ && options_.factors.stereo_map_points == StereoMapPoints::Dense; }
    /** The right image's matches come from the dense disparity (stereo_matching = guided, with the dense stereo). */
    bool guidedStereo() const { return guided_stereo_ && denseStereo(); }
    /** The stereo points' distance to the map's surfaces as a window factor (stereo_map_factor). */
    void addStereoMapTerm(const StereoPoints& points, estimation::WindowInput& in) const;
    /** The points that term and the stereo check use (the dense cloud, or the sparse matches) with their sigmas. */
    void stereoMapPoints(const StereoPoints& points, std::vector<Eigen::Vector3d>& p_cam,
                         std::vector<double>& sigma_m) const;
    /** The stereo points that the map terms use (depth 0.2 .. stereo_map_max_depth_m) and their sigma against the
     *  map: stereo_map_sigma_m and the disparity's depth noise (z^2 / (f b) stereo_disparity_sigma_px). */
    void mapPointsWithSigma(const StereoPoints& points, std::vector<Eigen::Vector3d>& p_cam,
                            std::vector<double>& sigma_m) const;
    /** Landmarks between the previous frame's stereo points and `current` (of time t; its temporal matches), which
     *  are then kept for the next frame. */
    void temporalLandmarks(StereoPoints current, double t, std::vector<estimation::TemporalLandmark>& out);

    TrackerOptions options_;
    estimation::EstimatorOptions estimator_;
    estimation::ReweightingOptions reweighting_;
    estimation::StereoGeometry stereo_;
    estimation::ImuNoise imu_noise_;
    estimation::MapRefiner refiner_;
    const map::LidarMap& map_;  ///< the renderer's (map_points: lifting through provenance)
    frontend::Frontend& frontend_;
    /** The right image's points (stereo_matching = descriptors), so that the two images are extracted concurrently
     *  (a Frontend is not reentrant): same options as frontend_. */
    std::unique_ptr<frontend::Frontend> right_frontend_;
    frontend::StereoMatcher stereo_matcher_;
    core::StereoRig rig_;
    std::unique_ptr<GuidedStereo> guided_stereo_;  ///< stereo_matching = guided, once a stereo cloud is set
    frontend::FrameFeatures prev_left_;
    std::vector<cv::KeyPoint> prev_right_keypoints_;
    std::vector<frontend::StereoPoint> prev_stereo_;
    std::vector<int> prev_stereo_of_left_;  ///< previous left keypoint -> index in prev_stereo_ (-1: none)
    double prev_stereo_t_ = 0;              ///< the time of prev_stereo_'s frame
    Eigen::Isometry3d T_body_cam_ = Eigen::Isometry3d::Identity();

    /** The map lines of the refiner's last quasi-image (map_lines), lifted at its pose. */
    std::vector<MapLine> quasiImageLines(FrameReport& rep) const;
    /** Point-to-line map factors of a keyframe (map_lines): `map_lines` against the camera's segments, associated
     *  at T_world_cam. */
    void addMapLines(const std::vector<frontend::LineSegment>& camera_lines, const std::vector<MapLine>& map_lines,
                     const Eigen::Isometry3d& T_world_cam, double sigma_m, double sigma_rad,
                     estimation::WindowInput& in, FrameReport& rep);
    MapLineOptions mapLineOptions() const;
    /** Point factors of a keyframe (map_points): the keypoints of the refiner's quasi-image (its quasiFeatureImage)
     *  against the left image's (`camera`), associated at T_world_cam. Uses the front-end: not while the worker
     *  extracts. */
    void addMapPoints(const frontend::FrameFeatures& camera, const Eigen::Isometry3d& T_world_cam,
                      estimation::WindowInput& in, FrameReport& rep);
    /** The left image's segments (map_lines); with concurrent_stages on the worker thread beside the alignment. */
    std::vector<frontend::LineSegment> cameraLines(const cv::Mat& image) const;

    /** Point-to-plane factors of a keyframe (map_planes): the frame's stereo points at T_world_cam. */
    void addMapPlanes(const StereoPoints& points, const Eigen::Isometry3d& T_world_cam, estimation::WindowInput& in,
                      FrameReport& rep) const;
    std::unique_ptr<MapPlaneAssociator> plane_associator_;  ///< map_planes
    std::unique_ptr<MapLineExtractor> line_extractor_;  ///< map_lines
    std::unique_ptr<frontend::LineDetector> line_detector_;  ///< map_lines: the camera side
    std::unique_ptr<core::WorkerThread> worker_;  ///< concurrent_stages: the stereo extraction's thread

    /** While the platform has stood still since the start (static_initialization): the previous state's prior takes
     *  the standing span's gyroscope bias and a zero velocity (as OpenVINS's zero-velocity update), so a start
     *  that is tracked from its first frame still gets what a static initialization gives. */
    void applyStandstill(const StaticImuEstimate& still);
    std::optional<StaticInitializer> standstill_;

    const map::DistanceField* distance_field_ = nullptr;
    const reloc::StereoCloud* stereo_cloud_ = nullptr;
    double stereo_check_bound_ = 0;
    /** The edge alignment's usual inlier ratio (a running mean over frames whose stereo agreed): the stereo check's
     *  trust in the edge-aligned pose. */
    double edge_inlier_ratio_usual_ = NAN;
    std::vector<Eigen::Vector3f> last_dense_;
    bool initialized_ = false;
    estimation::FrameState state_;
    estimation::StatePrior prior_;
    size_t frames_ = 0;
    int misses_ = 0;
};

}  // namespace quasiloc::tracking
