#pragma once
// GlobalInitializer: the tracker's initial state (pose and velocity) with no initial guess, from global
// localization by geometry (reloc/geometric_localizer.h) of two frames and the IMU between them.
//
// Frames are fed in order. A frame that localizes becomes the anchor a; the frames after it are kept. The first
// later frame b at least init_velocity_interval_s after a that also localizes closes the pair when
//   - the rotation between the two localizations agrees with the bias-corrected gyroscope's within
//     max_disagreement_deg (the fixes' own errors) plus three sigmas of the gyroscope bias times the interval
//     (two independent answers and the IMU confirm each other: a wrong place almost never passes), and
//   - the velocity they imply is below init_max_speed_m_s;
// the velocity at a is then the one that carries the IMU from a to b (Forster preintegration at the bias prior):
//   p_b = p_a + v_a dt + g dt^2 / 2 + R_a dp   =>   v_a = (p_b - p_a - g dt^2 / 2 - R_a dp) / dt.
// The position errors of the two fixes (a few cm) make an error of about sqrt(2) * 3 cm / 0.5 s = 8 cm/s: the
// tracker starts with init_global_sigma_v and the map terms of the first frames correct the rest.
// The gyroscope bias: real IMUs have one (EuRoC: 0.08 rad/s, 2.3 deg over 0.5 s, beyond the fixes' 2 deg). While
// the platform stands still from the first sample on (static_initialization.h), the mean rate measures it to a
// few 1e-4 rad/s; otherwise the calibration's prior holds (an unknown bias: 0.1 rad/s, so the bound widens by
// 8.6 deg over 0.5 s, which still rejects a room's 90-degree-turned twin). The static span's mean specific force
// also gives the localization its up direction (otherwise the last gravity_window_s of the accelerometer).
// A fix that geometry alone finds ambiguous (a corner of a box-shaped room fits a 90-degree turned pose nearly as
// well: simulated rooms, 20 of 30 fixes) is settled by the image when an appearance score is given
// (setAppearanceScore): the pose whose score is highest, if it beats the next by appearance_margin. A closing fix
// b that stays ambiguous is settled by the anchor when exactly one of its places closes the pair with it (gyroscope
// and speed as above) and the image, if scored, ranks that place first too: the anchor, the IMU and the image agree
// (the margin, meant for a fix on its own, is not asked: observed scores 0.47 vs 0.38 at the right place).
// The search's answer for one frame is not always the place that explains the frame best: its coarse grid and few
// refined candidates miss the true place at some frames and return a worse one (a swept map's room: 82 % explained
// against 94 % at the truth, at 9 of 10 frames of one view). So the places of earlier attempts are remembered
// (remembered_places, the best by their inlier share; their orientation carried by the gyroscope) and refined
// against each new frame's stereo points; one that explains clearly more than the search's answer (the answer
// below place_ambiguity_ratio of it, the localizer's own ambiguity test) replaces the answer
// (preferredRememberedPlace). A pair that fails replaces the anchor by b (when b localized) or drops it. The tracker
// then starts at a and tracks the kept frames. A relocalization can take the first fix alone (single_fix: the tracker
// supplies the velocity), which saves the wait for the second fix.
#include <deque>
#include <functional>
#include <optional>
#include <quasiloc/dataset/frame.h>
#include <quasiloc/estimation/imu_preintegration.h>
#include <quasiloc/reloc/geometric_localizer.h>
#include <quasiloc/tracking/static_initialization.h>
#include <string>
#include <vector>

namespace quasiloc::tracking
{
struct GlobalInitOptions
{
    double velocity_interval_s = 0.5;
    double max_disagreement_deg = 2.0;
    double max_speed_m_s = 4.0;
    double gravity_window_s = 0.2;
    double appearance_margin = 1.25;  ///< an ambiguous fix is settled when the best score is this many times the next
    double min_appearance_score = 0.2;
    /** A relocalization whose caller knows the velocity (the tracker, in its body frame): the first fix is the
     *  start on its own (GlobalInitialState::v_world empty), without waiting velocity_interval_s for a
     *  second fix. The fix still passes the localizer's own tests (inlier share, ambiguity, appearance). */
    bool single_fix = false;
    /** The IMU biases before anything measured them (the calibration's prior); a static start replaces the
     *  gyroscope's. */
    ImuBiasPrior bias_prior;
    bool static_initialization = true;  ///< false: the prior stands even when the platform stands still
    StandstillOptions standstill;
    /** Places of earlier attempts refined against each new frame (0: none; see above). */
    int remembered_places = 3;
    /** The localizer's decision ([GeometricLocalization] min_inlier_ratio, ambiguity_ratio), which the remembered
     *  places pass as the search's answer does. */
    double place_min_inlier_ratio = 0.7, place_ambiguity_ratio = 0.9;
};

/** A place an earlier attempt found (T_world_cam0 as refined against the frame at t) and its inlier share there. */
struct ScoredPlace
{
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    double inlier_ratio = 0;
    double t = 0;
};

/** Whether two poses are different places for the localizer's ambiguity test (farther than 0.3 m or 5 deg). */
bool differentPlaces(const Eigen::Isometry3d& T_a, const Eigen::Isometry3d& T_b);

/** Which remembered place (rescored against the frame the search answered) replaces the search's answer: the one
 *  that explains the most points, when it is a different place from the answer, explains at least min_ratio, the
 *  answer explains less than ambiguity_ratio of it, and no other remembered place different from it comes within
 *  ambiguity_ratio of it; nullopt otherwise (the answer stands). */
std::optional<size_t> preferredRememberedPlace(const Eigen::Isometry3d& answer, double answer_ratio,
                                               const std::vector<ScoredPlace>& remembered, double min_ratio,
                                               double ambiguity_ratio);

/** Where the camera was last known to be (a relocalization after a loss): a frame at time t is searched within
 *  radius_m + speed_m_s * (t - t_known) of position_world only (reloc::SearchSphere), which is faster and leaves
 *  out far places that would make the fix ambiguous. The sphere grows with the time since, so a search that keeps
 *  failing becomes global. */
struct SearchPrior
{
    Eigen::Vector3d position_world = Eigen::Vector3d::Zero();
    double t_known = 0;
    double radius_m = 1.0;
    double speed_m_s = 1.5;
};

/** The body's orientation where a lost track was last verified (a relocalization). The gyroscope carries it to each
 *  attempt (not the tracker, whose orientation may have gone wrong since), and only headings within margin_deg
 *  (the track's own error where it was verified) plus three gyroscope-bias sigmas over the time since are searched
 *  and weighed (reloc::SearchSphere). Position is lost, but orientation is not: a corridor seen from either end, or
 *  a room's turned twin, explains the stereo points as well as the true place, and differs from it by 90 or 180
 *  degrees. The prior holds up to t_until only (the session: for a few seconds after the loss): a verified pose
 *  can be wrong, and a wrong heading must not keep the search away for ever. */
struct HeadingPrior
{
    Eigen::Matrix3d R_world_body = Eigen::Matrix3d::Identity();  ///< at t (the last verified frame)
    double t = 0;
    double margin_deg = 15;
    double t_until = 0;
    std::vector<dataset::ImuSample> imu;  ///< samples after t already received (up to the loss)
};

/** Where the odometry puts the camera at one frame of a relocalization: the lost track, tracked on the IMU and the
 *  stereo landmarks without the map terms (the session, with [TrackMonitor] odometry_while_lost), carried from the
 *  last verified pose. Its error grows with the path since that pose (a drift ratio of the distance travelled, plus
 *  a floor for the verified pose's own error and the doubtful frames before the loss), not with time: a robot
 *  that stands still does not drift away from its prediction. The frame is searched within
 *  kOdometrySphereUncertainties x uncertainty_m of the prediction (reloc::SearchSphere), and an ambiguous fix is
 *  settled by it (settleByOdometry). */
struct OdometryPrediction
{
    Eigen::Vector3d position_world = Eigen::Vector3d::Zero();  ///< cam0's position
    double uncertainty_m = 1;                                  ///< how far the truth may lie from it
};
/** The search sphere around an odometry prediction, in uncertainties: wide enough that a place the odometry rules
 *  out (beyond kOdometryRivalUncertainties) is still searched, and seen as the rival it is. */
constexpr double kOdometrySphereUncertainties = 3;
/** A place this many uncertainties or more from the prediction is not the one the odometry predicts. */
constexpr double kOdometryRivalUncertainties = 2;

/** Which of the places an ambiguous fix could be (refined poses T_world_cam) the odometry settles it on: the one
 *  place within one uncertainty of the prediction when every other place lies at least kOdometryRivalUncertainties
 *  from it; nullopt otherwise (no place near the prediction, or a rival near it too: both are what the odometry
 *  allows, so the fix stays ambiguous). */
std::optional<size_t> settleByOdometry(const std::vector<Eigen::Isometry3d>& places,
                                       const OdometryPrediction& prediction);

/** R_world_body carried from time t through the gyroscope samples after t (rates minus gyro_bias, each held
 *  from the previous sample's time); t becomes the last sample's time. False, and R_world_body no longer known,
 *  when two samples are more than max_gap_s apart (a rate held over a gap is a guess). */
bool carryOrientation(Eigen::Matrix3d& R_world_body, double& t, const std::vector<dataset::ImuSample>& samples,
                      const Eigen::Vector3d& gyro_bias, double max_gap_s = 0.05);

/** The heading prior's bound [deg] at time t, for a gyroscope bias known to gyro_bias_sigma [rad/s]. */
double headingBoundDeg(const HeadingPrior& heading, double gyro_bias_sigma, double t);

/** Scores of candidate poses T_world_cam0 for a frame by its image (higher is better, 0 = no fit). */
using AppearanceScore =
    std::function<std::vector<double>(const dataset::StereoFrame&, const std::vector<Eigen::Isometry3d>&)>;

/** The state the tracker starts from, and the frames after it still to be tracked. */
struct GlobalInitialState
{
    dataset::StereoFrame anchor;
    Eigen::Isometry3d T_world_cam0 = Eigen::Isometry3d::Identity();
    /** The body's velocity at the anchor (map frame); empty for a single fix (GlobalInitOptions::single_fix): the
     *  caller supplies it. */
    std::optional<Eigen::Vector3d> v_world;
    std::vector<dataset::StereoFrame> pending;  ///< frames after the anchor, in order (the closing frame included)
    /** The biases to start from: a static initialization's gyroscope bias when the platform stood still up to the
     *  closing frame, else the calibration's prior. */
    ImuBiasPrior biases;
};

/** One localization attempt, for the diagnostics a person reads when initialisation takes long. */
struct InitAttempt
{
    double t = 0;
    reloc::GeometricLocalization result;
    std::string note;                            ///< anchor / pair closed / why the pair failed
    double search_radius_m = 0;                  ///< the SearchPrior's or the odometry's sphere (0: the whole map)
    std::optional<OdometryPrediction> odometry;  ///< the frame's odometry prediction, if it had one
};

/** The velocity at a (map frame) that carries the IMU samples from fix a to fix b (preintegrated at the biases of
 *  `biases`), and the angle [deg] between the fixes' relative rotation and the bias-corrected gyroscope's. Fixes
 *  are T_world_cam0; samples as estimation::ImuPreintegration::integrateInterval takes them. */
Eigen::Vector3d velocityBetweenFixes(const Eigen::Isometry3d& T_world_cam_a, double t_a,
                                     const Eigen::Isometry3d& T_world_cam_b, double t_b,
                                     const std::vector<estimation::ImuMeasurement>& samples,
                                     const Eigen::Isometry3d& T_body_cam, const estimation::ImuNoise& noise,
                                     const ImuBiasPrior& biases, double* rotation_disagreement_deg = nullptr);

/** The bound [deg] on the disagreement between two fixes dt_s apart and the gyroscope: max_disagreement_deg
 *  (the fixes) plus three sigmas of the remaining gyroscope bias over dt_s. */
double rotationDisagreementBoundDeg(const GlobalInitOptions& options, double gyro_bias_sigma, double dt_s);

/** The velocity at a when fixes a and b close a pair (rotation agrees with the bias-corrected gyroscope within
 *  rotationDisagreementBoundDeg, implied speed below max_speed_m_s); otherwise nullopt and, if `why`, the
 *  reason. */
std::optional<Eigen::Vector3d> pairVelocity(const Eigen::Isometry3d& T_world_cam_a, double t_a,
                                            const Eigen::Isometry3d& T_world_cam_b, double t_b,
                                            const std::vector<estimation::ImuMeasurement>& samples,
                                            const Eigen::Isometry3d& T_body_cam, const estimation::ImuNoise& noise,
                                            const ImuBiasPrior& biases, const GlobalInitOptions& options,
                                            std::string* why);

/** The velocity (map frame) of a relocalized track that restarts at a single fix T_world_cam_fix: the velocity the
 *  track had there, in its own body frame (speed and heading relative to the body survive a wrong pose; the map
 *  frame of the wrong pose does not), turned into the map frame by the fix. */
Eigen::Vector3d velocityAtFix(const Eigen::Isometry3d& T_world_cam_fix, const Eigen::Isometry3d& T_body_cam,
                              const Eigen::Isometry3d& T_world_body_track, const Eigen::Vector3d& v_world_track);

/** The indices of the places b could be (an ambiguous fix) that close a pair with fix a. */
std::vector<size_t> placesClosingThePair(const Eigen::Isometry3d& T_world_cam_a, double t_a,
                                         const std::vector<Eigen::Isometry3d>& places_b, double t_b,
                                         const std::vector<estimation::ImuMeasurement>& samples,
                                         const Eigen::Isometry3d& T_body_cam, const estimation::ImuNoise& noise,
                                         const ImuBiasPrior& biases, const GlobalInitOptions& options);

class GlobalInitializer
{
   public:
    GlobalInitializer(const reloc::GeometricLocalizer& localizer, const Eigen::Isometry3d& T_body_cam,
                      const estimation::ImuNoise& imu_noise, const GlobalInitOptions& options);

    /** Optional: searches near a known position only (see SearchPrior). */
    void setSearchPrior(const SearchPrior& prior) { prior_ = prior; }

    /** Optional: searches near the orientation the track had only (see HeadingPrior). */
    void setHeadingPrior(const HeadingPrior& heading);

    /** Optional: settles ambiguous fixes by the image (see above). */
    void setAppearanceScore(AppearanceScore score) { appearance_ = std::move(score); }

    /** Feeds the next frame; returns the initial state once a pair closes. With localize_it = false the frame only
     *  carries its IMU samples (and is kept among the pending frames): a caller that cannot localize every frame
     *  (a search behind the tracker) still gives the pair the whole IMU record between its fixes. After an
     *  ambiguous attempt on a platform standing still, no frame is localized until the IMU sees it move: the view
     *  does not change, nor does the answer. */
    std::optional<GlobalInitialState> feed(const dataset::StereoFrame& frame, bool localize_it = true,
                                           const std::optional<OdometryPrediction>& odometry = std::nullopt);

    const std::vector<InitAttempt>& attempts() const { return attempts_; }
    /** The biases the pair check uses now: the static estimate's gyroscope bias while the platform has stood
     *  still since the first sample, else the calibration's prior. */
    ImuBiasPrior biases() const;

   private:
    /** The places an ambiguous fix could be (the best first), and which the image prefers (if it was scored). */
    struct AmbiguousFix
    {
        std::vector<Eigen::Isometry3d> poses;
        std::optional<size_t> best_by_appearance;
    };
    /** Where a frame at time t is searched (the odometry's sphere when the frame has a prediction, else the prior's
     *  sphere; the heading prior's bound), or nowhere in particular (no prior). */
    std::optional<reloc::SearchSphere> searchSphere(double t, const std::optional<OdometryPrediction>& odometry) const;
    /** An ambiguous fix settled by the odometry (settleByOdometry), unless the image preferred another place. */
    bool settleByPrediction(reloc::GeometricLocalization& r, const AmbiguousFix& ambiguous,
                            const OdometryPrediction& odometry, std::string& note) const;
    /** The frame localized within `near` (searchSphere at its time); its stereo points (left camera frame) into
     *  `points_cam`. */
    reloc::GeometricLocalization localize(const dataset::StereoFrame& frame,
                                          const std::optional<reloc::SearchSphere>& near, std::string& note,
                                          AmbiguousFix& ambiguous, std::vector<Eigen::Vector3f>& points_cam);
    /** With an anchor: an ambiguous fix is taken when exactly one of its places closes the pair with the anchor and
     *  the image (if scored) prefers that place too. */
    bool settleByAnchor(reloc::GeometricLocalization& r, const AmbiguousFix& ambiguous, double t,
                        std::string& note) const;
    /** Refines the remembered places against the frame's stereo points and replaces the search's answer by one that
     *  explains clearly more (preferredRememberedPlace); places the frame no longer supports are forgotten. */
    void preferRemembered(const std::vector<Eigen::Vector3f>& points_cam, double t,
                          const std::optional<reloc::SearchSphere>& near, reloc::GeometricLocalization& r,
                          AmbiguousFix& ambiguous, std::string& note);
    /** Adds the attempt's answer to the remembered places (replacing the same place; the best remembered_places
     *  kept). */
    void remember(const reloc::GeometricLocalization& r, double t);
    /** The IMU samples of the frames after the anchor. */
    std::vector<estimation::ImuMeasurement> pendingSamples() const;
    /** The last attempt was ambiguous while the platform stood still, and it has not moved since. */
    bool waitsForMotion() const { return ambiguous_standing_ && !static_.moved(); }

    const reloc::GeometricLocalizer& localizer_;
    Eigen::Isometry3d T_body_cam_;
    estimation::ImuNoise imu_noise_;
    GlobalInitOptions options_;
    std::deque<dataset::ImuSample> recent_imu_;  ///< the last gravity_window_s of samples
    StaticInitializer static_;
    std::optional<dataset::StereoFrame> anchor_;
    Eigen::Isometry3d T_world_anchor_ = Eigen::Isometry3d::Identity();
    std::vector<dataset::StereoFrame> pending_;
    std::vector<InitAttempt> attempts_;
    AppearanceScore appearance_;
    std::optional<SearchPrior> prior_;
    std::optional<HeadingPrior> heading_;
    /** Carries the heading prior through `samples`; an IMU gap ends it (with a note for the next attempt). */
    void carryHeading(const std::vector<dataset::ImuSample>& samples);
    std::string heading_note_;
    Eigen::Matrix3d R_world_body_predicted_ = Eigen::Matrix3d::Identity();  ///< the heading prior at t_predicted_
    double t_predicted_ = 0;
    bool ambiguous_standing_ = false;
    /** The remembered places, their orientation carried by the gyroscope up to t_carried. */
    struct RememberedPlace
    {
        ScoredPlace place;
        double t_carried = 0;
    };
    std::vector<RememberedPlace> remembered_;
    /** Carries the remembered places' orientation through `samples`; an IMU gap forgets them. */
    void carryRemembered(const std::vector<dataset::ImuSample>& samples);
};

}  // namespace quasiloc::tracking
