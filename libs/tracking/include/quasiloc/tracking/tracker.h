#pragma once
// The tracker (first version): stereo-inertial tracking against the LiDAR map.
//
// Per frame:  IMU preintegration from the previous state -> predicted pose -> on keyframes, direct map
// alignment (estimation/direct_alignment.h) from the prediction, with the prediction's uncertainty as its
// prior -> a two-frame window (previous state with its marginal as prior, IMU factor, and the map: by default the
// alignment's edge residuals as a factor on the current pose, linearised from the aligned pose; or the aligned
// pose as a pose measurement; and, given the map's distance field, the frame's stereo points' distance to the
// map's surfaces, estimation/map_distance_factor.h) -> pose, velocity and biases -> the marginal for the next frame.
//
// IMU biases. Real IMUs start with a bias (EuRoC's gyroscope: 0.08 rad/s). The tracker starts from the bias prior
// it is given (initialize()): the calibration's (dataset/calibration.h; unmeasured: 0 +- 0.1 rad/s, 0 +- 0.2
// m/s^2) or a static initialization's (static_initialization.h). While the platform has stood still since the
// start, each frame's prior takes the standing span's gyroscope bias and a zero velocity (a zero-velocity update,
// as OpenVINS makes); once it moves, the window estimates the biases with their random walk. A start in motion
// learns the gyroscope bias from the map terms over the first ~2 s (simulated V1_01, 5 s from the ground truth:
// ATE 2.07 cm, against 1.34 cm with a zero-bias IMU).
//
// Why the direct term and not feature matches for the map: on the simulated world (and on KITTI) camera
// descriptors do not match quasi-image descriptors (bench_crossmodal: 0 of 75 ORB matches correct at the true
// pose), while map edges align with camera edges from a prediction within ~0.1 m / 1 deg (67 % success).
// The IMU keeps the prediction inside that basin between map updates. With temporal_landmarks, stereo
// points matched between the previous and the current left image (front-end: ORB/..., epipolar stereo
// matching, windowed temporal matching) add stereo reprojection factors in both frames (visual-inertial
// odometry between map updates). Optional structural map factors (off by default, see map_lines / map_points below):
// point-to-line factors from the quasi-image's geometric lines associated by geometry (map_lines.h), reweighted
// by [Reweighting], and point factors from quasi-image keypoints matched by descriptor within a few pixels of
// their projection at the aligned pose (map_points.h), and point-to-plane factors with an association distribution
// (map_planes.h, map_planes = true; the stereo-to-surface factor is the point-to-plane term without association).
// The start and the recovery after a loss are global localization by geometry (global_initialization.h), driven by
// quasiloc-track.
//
// Keyframe policy: map alignment every `keyframe_every` frames; between keyframes the IMU factor and the
// temporal stereo landmarks carry the state. A map correction larger than max_correction_* is rejected (counted
// as a miss: the alignment left its basin); `lost_after_misses` consecutive misses mark the track lost (reported
// per frame). The default (and config.ini) is keyframe_every = 1, a map alignment on every frame: with the
// cheaper camera side (fused distance transforms, points-only stereo extraction beside the alignment) every
// frame fits the 50 ms budget on 2 cores, so nothing is gained by skipping map updates, and each skipped one
// lets the IMU drift grow (the timing target is met with keyframes included).
//
// Per-frame cost (issue 9): the stereo extraction is points only (Frontend::extractPoints: the line branch
// feeds nothing here) and, with concurrent_stages, runs on the tracker's worker thread while this thread builds
// the camera edge field, renders the map and aligns.
//
//   [Tracking]
//   map_updates = true            ; false: no map alignment at all, the baselines of issue 9: visual-inertial
//                                 ;   odometry (with temporal_landmarks) or IMU-only propagation (without)
//   keyframe_every = 1
//   direct_sigma_m = 0.01         ; information of a map-alignment pose measurement
//   direct_sigma_deg = 0.2
//   map_information = fixed       ; fixed: those sigmas in every direction; observability: shaped by what the
//                                 ;   alignment's edges observe (estimation/map_measurement.h)
//   map_term = auto               ; auto: factor when the map's reflectivity varies, none when it is constant (a map
//                                 ;   without intensities, e.g. sampled from a GMM: its edges are only depth
//                                 ;   discontinuities, and on the real EuRoC micro set against the GMM map of the
//                                 ;   room they pulled the pose away: ATE 7.3 cm with them, 5.7 without, 8.8 with
//                                 ;   them alone; see the README's real-data table)
//                                 ; factor: the edge residuals themselves as a Ceres factor in the window
//                                 ;   (direct_factor.h), linearised from the alignment's pose; measurement: the
//                                 ;   alignment's pose as a Gaussian measurement (the sigmas above). 30 s of the six
//                                 ;   simulated sequences (ATE cm, with init_sigma_bg = 0.0005): factor 0.93 / 0.96 /
//                                 ;   9.22 / 0.78 / 2.26 / 0.92 (V1_01..V2_03), measurement 1.03 / 1.55 / 3.31 /
//                                 ;   59.4 / 3.57 / 1.42: the factor is the default; none: no edge alignment
//                                 ;   (the stereo map factor alone, an ablation)
//   direct_factor_sigma_px = 2    ; factor: pixel sigma of the edge residuals ...
//   direct_factor_effective_points = 25 ; ... which count as this many independent observations together. With
//                                 ;   the stereo map factor, 30 s from the ground truth (ATE cm, V1_01..V2_03): 25:
//                                 ;   1.03 / 0.83 / 2.57 / 1.37 / 1.60 / 1.21; 100: 1.06 / 0.76 / 5.76 / 0.93 / 1.68 /
//                                 ;   1.07 (V1_03's corner view biases the edges; trusted less, the surfaces hold)
//   min_prior_sigma_m = 0.05      ; the alignment's prior: the predicted covariance, at least these
//   min_prior_sigma_deg = 0.5
//   max_correction_m = 0.15       ; larger map corrections are rejected (the gate is 3 predicted sigmas when wider)
//   max_correction_deg = 1.5
//   lost_after_misses = 20
//   temporal_landmarks = true     ; stereo landmarks between consecutive frames
//   temporal_window_px = 60       ; a current keypoint's match lies within this of the previous one
//   max_landmarks = 150
//   init_sigma_m = 0.01           ; uncertainty of the given initial state
//   init_sigma_deg = 0.1
//   init_sigma_v = 0.05           ; m/s
//                                 ; the IMU biases' prior is not here: it comes from the calibration's [imu]
//                                 ;   (dataset/calibration.h: measured, or unknown at MEMS scale, 0.1 rad/s) or
//                                 ;   from a static initialization (static_initialization.h), see initialize()
//   init = groundtruth            ; global: start from global localization by geometry (global_initialization.h)
//   init_velocity_interval_s = 0.5 ; global: time between the two fixes that give the velocity
//   init_max_disagreement_deg = 2 ; global: the fixes' rotation must agree with the gyroscope's
//   init_max_speed_m_s = 4
//   init_global_sigma_m = 0.05    ; global: uncertainty of the start
//   init_global_sigma_deg = 1
//   init_global_sigma_v = 0.15
//   stereo_map_factor = true      ; the stereo points' distance to the map's surfaces as a factor on the current
//                                 ;   pose (map_distance_factor.h), when a distance field is given. 30 s of the six
//                                 ;   simulated sequences from the ground truth (ATE cm, V1_01..V2_03): with 1.06 /
//                                 ;   0.76 / 5.76 / 0.93 / 1.68 / 1.07, edges alone 0.93 / 0.96 / 9.22 / 0.78 /
//                                 ;   2.26 / 0.92, surfaces alone 4.14 / 3.63 / 3.53 / 4.40 / 8.73 / 4.99
//   stereo_map_sigma_m = 0.02     ; per point: the map's and the field's noise, and the depth noise of the
//   stereo_disparity_sigma_px = 0.5 ;   disparity (z^2 / (f b) times this)
//   stereo_map_effective_points = 50 ; all points together count as this many independent observations
//   stereo_map_truncation_m = 0.15 ; farther points from the map do not pull (occluders, clutter)
//   stereo_map_max_depth_m = 6
//   stereo_map_points = dense     ; dense: the frame's SGBM cloud (the global localization's and the loss check's,
//                                 ;   [GeometricLocalization] stereo keys); sparse: the ORB stereo matches. Chosen on
//                                 ;   the real EuRoC micro set: ATE 3.1 cm dense, 5.6 cm sparse (ORB keypoints cluster
//                                 ;   on textured clutter: the surfaces they touch leave directions unconstrained);
//                                 ;   simulated 30 s x 6: 1.25 cm mean dense, 1.29 sparse; +8 ms per frame
//   concurrent_stages = true      ; stereo point extraction on a worker thread beside the map alignment
//   static_initialization = true  ; a standing start measures the gyroscope bias (static_initialization.h)
//   map_lines = false             ; point-to-line map factors (map_lines.h) on keyframes: map lines of the
//                                 ;   quasi-image's normal shading associated by geometry with the camera's
//                                 ;   segments ([Lines] detector), reweighted by [Reweighting] ([Estimator]
//                                 ;   primitives must include L). 30 s of the six simulated sequences from the
//                                 ;   ground truth (scripts/track_lines_ablation.sh), ATE cm V1_01..V2_03: without
//                                 ;   1.03 / 0.83 / 2.57 / 1.37 / 1.60 / 1.21; with lines, [Reweighting] uniform
//                                 ;   0.94 / 0.74 / 2.42 / 1.16 / 1.09 / 0.95 (better on all six), full 1.05 /
//                                 ;   0.69 / 3.29 / 1.15 / 1.11 / 0.93. Off by default for now: the main job's
//                                 ;   median rises from 42 to 50-51 ms per frame (the camera's segments are
//                                 ;   detected on the worker thread; the map side costs ~8 ms), and full
//                                 ;   reweighting, the [Reweighting] default, takes V1_03 past 3 cm
//   line_sigma_px = 1.5           ; a camera segment's offset sigma (each support point: x sqrt(n / 2))
//   line_window_sigmas = 3        ; association window: this many predicted pixel sigmas (pose covariance at
//   line_window_min_px = 2        ;   the median map depth), clamped to [min, max]; the association is made at
//   line_window_max_px = 3        ;   the edge alignment's pose, far better than the prediction, so the cap
//                                 ;   binds: 10 s of V1_01 from the ground truth, ATE 1.21 cm without lines,
//                                 ;   with lines 4.49 (cap 15 px), 2.25 (5 px), 1.18 (3 px), 1.08 (3 px and the
//                                 ;   half-resolution shading); wider windows admit texture segments
//   line_max_angle_deg = 5
//   line_max_candidates = 3
//   map_points = false            ; point factors (map_points.h) on keyframes: the quasi-image's keypoints (on the
//                                 ;   [MapRefinement] quasi_gray image), lifted through provenance, matched by
//                                 ;   descriptor to the left image's keypoints within point_window_px of their
//                                 ;   projection at the edge alignment's pose ([Estimator] primitives must include P)
//   point_window_px = 3
//   point_sigma_px = 1.5
//   map_planes = false            ; point-to-plane factors with an association distribution (map_planes.h) on
//                                 ;   keyframes: each stereo point against the map planes fitted around its pixel
//                                 ;   in the quasi-image, at the edge alignment's pose; reweighted by [Reweighting]
//                                 ;   ([Estimator] primitives must include plane). Sigma per point as the stereo map
//                                 ;   factor's, and all together count as plane_effective_points observations
//   plane_effective_points = 50
#include <Eigen/Geometry>
#include <mrpt/config/CLoadableOptions.h>
#include <quasiloc/core/worker_thread.h>

#include <memory>
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
#include <quasiloc/tracking/map_lines.h>
#include <quasiloc/tracking/map_planes.h>
#include <quasiloc/tracking/static_initialization.h>
#include <string>

namespace quasiloc::tracking
{
struct TrackerOptions : public mrpt::config::CLoadableOptions
{
    bool map_updates = true;
    int keyframe_every = 1;
    double direct_sigma_m = 0.01, direct_sigma_deg = 0.2;
    std::string map_information = "fixed";
    std::string map_term = "auto";
    double direct_factor_sigma_px = 2.0, direct_factor_effective_points = 25;
    double min_prior_sigma_m = 0.05, min_prior_sigma_deg = 0.5;
    double max_correction_m = 0.15, max_correction_deg = 1.5;
    int lost_after_misses = 20;
    bool temporal_landmarks = true;
    double temporal_window_px = 60;
    int max_landmarks = 150;
    double init_sigma_m = 0.01, init_sigma_deg = 0.1, init_sigma_v = 0.05;
    /** groundtruth: the initial state is given (quasiloc-track: from the ground truth); global: from global
     *  localization by geometry (global_initialization.h), with the init_global_* keys. */
    std::string init = "groundtruth";
    double init_velocity_interval_s = 0.5, init_max_disagreement_deg = 2.0, init_max_speed_m_s = 4.0;
    double init_global_sigma_m = 0.05, init_global_sigma_deg = 1.0, init_global_sigma_v = 0.15;
    /** The frame's stereo points against the map's surfaces (estimation/map_distance_factor.h), when the tracker
     *  has a distance field (setMapDistanceField). */
    bool stereo_map_factor = true;
    double stereo_map_sigma_m = 0.02, stereo_disparity_sigma_px = 0.5, stereo_map_effective_points = 50;
    double stereo_map_truncation_m = 0.15, stereo_map_max_depth_m = 6;
    /** Which stereo points the surface factor uses: dense (the frame's SGBM cloud thinned per voxel,
     *  reloc/stereo_cloud.h, given by setStereoCloud; without one, sparse) or sparse (the ORB stereo matches of the
     *  temporal landmarks). */
    std::string stereo_map_points = "dense";
    /** Independent stages of a frame run concurrently (needs more than one OpenCV thread, cv::getNumThreads()): the
     *  stereo point extraction (images only, mostly single-threaded ORB) runs on the tracker's worker thread beside
     *  the map alignment (edge field, render, LM: the render and OpenCV's filters use OpenCV's pool). Same results
     *  either way. (Overlapping the edge field with the render too was slower: both already use the pool.) */
    bool concurrent_stages = true;
    /** A platform that stands still from the first IMU sample gives its gyroscope bias (static_initialization.h):
     *  the start's prior instead of the calibration's. */
    bool static_initialization = true;
    bool map_lines = false;
    double line_sigma_px = 1.5, line_window_sigmas = 3, line_window_min_px = 2, line_window_max_px = 3;
    double line_max_angle_deg = 5;
    int line_max_candidates = 3;
    bool map_points = false;
    double point_window_px = 3, point_sigma_px = 1.5;
    bool map_planes = false;
    double plane_effective_points = 50;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    void check(const std::string& input) const;
};

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
    /** Wall times [ms]. ms_image: the camera edge field; ms_align: render, map model and LM; ms_visual: stereo
     *  points and temporal matching (with concurrent_stages the extraction runs beside the alignment and only the
     *  wait for it and the matching count); ms_total: the whole frame. */
    double ms_predict = 0, ms_image = 0, ms_align = 0, ms_visual = 0, ms_window = 0, ms_total = 0;
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
    const std::string& mapTerm() const { return options_.map_term; }
    /** The biases now, with their marginal sigmas (the largest axis): what a restart after a loss starts from. */
    ImuBiasPrior biasPrior() const;
    /** The current estimate (body frame = IMU). */
    const estimation::FrameState& state() const { return state_; }
    bool initialized() const { return initialized_; }

    /** The map's distance field (must outlive the tracker; nullptr: none): enables stereo_map_factor. */
    void setMapDistanceField(const map::DistanceField* field) { distance_field_ = field; }
    /** The dense stereo of stereo_map_points = dense (must outlive the tracker). */
    void setStereoCloud(const reloc::StereoCloud* cloud) { stereo_cloud_ = cloud; }

    /** Tracks one stereo frame (its IMU samples since the previous frame included). */
    FrameReport track(const dataset::StereoFrame& frame);

   private:
    /** The stereo points of one frame: left and right points (points-only extraction) and their stereo matches. */
    struct StereoPoints
    {
        frontend::FrameFeatures left, right;
        std::vector<frontend::StereoPoint> stereo;
        std::vector<int> stereo_of_left;  ///< left keypoint -> index in stereo (-1: none)
        std::vector<Eigen::Vector3f> dense;  ///< stereo_map_points = dense: the SGBM cloud (left camera frame)
    };
    /** Depends on the images alone (and the front-end, used by no other stage): may run on a second thread. */
    StereoPoints extractStereo(const dataset::StereoFrame& frame);
    void start(double t, const Eigen::Isometry3d& T_world_cam0, const Eigen::Vector3d& v_world,
               const dataset::StereoFrame* frame, double sigma_m, double sigma_deg, double sigma_v,
               const ImuBiasPrior& biases);
    /** The surface factor takes the dense SGBM cloud (stereo_map_points = dense and a cloud given). */
    bool denseStereo() const { return stereo_cloud_ && options_.stereo_map_points == "dense"; }
    /** The stereo points' distance to the map's surfaces as a window factor (stereo_map_factor). */
    void addStereoMapTerm(const StereoPoints& points, estimation::WindowInput& in) const;
    /** The stereo points that the map terms use (depth 0.2 .. stereo_map_max_depth_m) and their sigma against the
     *  map: stereo_map_sigma_m and the disparity's depth noise (z^2 / (f b) stereo_disparity_sigma_px). */
    void mapPointsWithSigma(const StereoPoints& points, std::vector<Eigen::Vector3d>& p_cam,
                            std::vector<double>& sigma_m) const;
    /** Landmarks between the previous frame's stereo points and `current`, which are then kept for the next frame. */
    void temporalLandmarks(StereoPoints current, std::vector<estimation::TemporalLandmark>& out);

    TrackerOptions options_;
    estimation::EstimatorOptions estimator_;
    estimation::ReweightingOptions reweighting_;
    estimation::StereoGeometry stereo_;
    estimation::ImuNoise imu_noise_;
    estimation::MapRefiner refiner_;
    const map::LidarMap& map_;  ///< the renderer's (map_points: lifting through provenance)
    frontend::Frontend& frontend_;
    frontend::StereoMatcher stereo_matcher_;
    frontend::FrameFeatures prev_left_;
    std::vector<cv::KeyPoint> prev_right_keypoints_;
    std::vector<frontend::StereoPoint> prev_stereo_;
    std::vector<int> prev_stereo_of_left_;  ///< previous left keypoint -> index in prev_stereo_ (-1: none)
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
    bool initialized_ = false;
    estimation::FrameState state_;
    estimation::StatePrior prior_;
    size_t frames_ = 0;
    int misses_ = 0;
};

}  // namespace quasiloc::tracking
