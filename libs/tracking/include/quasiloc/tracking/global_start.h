#pragma once
// Starts without ground truth: at the beginning ([Initialization] init = global) and after a loss
// ([Relocalization] relocalize = true). Reads frames until two of them localize by geometry and agree with the IMU
// (tracking/global_initialization.h), and keeps a readable record of every attempt (initialization.txt).
#include <functional>
#include <map>
#include <memory>
#include <quasiloc/dataset/frame_source.h>
#include <ostream>
#include <quasiloc/tracking/global_initialization.h>
#include <quasiloc/tracking/map_context.h>
#include <quasiloc/tracking/tracker.h>
#include <string>

namespace quasiloc::tracking
{
class GlobalStarter
{
   public:
    /** Builds the localizer (candidate positions, on the context's distance field) and a map refiner (on the
     *  context's search renderer) whose direct edge alignment settles fixes that geometry finds ambiguous
     *  (AppearanceScore: the share of map edges on camera edges after aligning from each candidate). `context`,
     *  `frontend` and `console` must outlive the starter. InputError naming the map on failure. */
    GlobalStarter(MapContext& context, const core::StereoRig& rig, const InitializationOptions& options,
                  const reloc::GeometricLocalizationOptions& localization,
                  const estimation::MapRefinementOptions& refinement, frontend::Frontend& frontend,
                  const estimation::ImuNoise& imu_noise, std::ostream& console);
    ~GlobalStarter();

    /** Feeds frames from `next` (false: no more) to a fresh GlobalInitializer until a start is found; nullopt when
     *  the frames end first. `label` names the occasion in the record ("initialisation", "relocalization 2"). */
    std::optional<GlobalInitialState> find(const std::function<bool(dataset::StereoFrame&)>& next,
                                           const std::string& label,
                                           const std::optional<SearchPrior>& prior = std::nullopt);
    /** The same one frame at a time, for a caller that goes on tracking meanwhile: begin() starts a search,
     *  feed() returns the start once found (and ends the search); attempt = false: the frame's IMU samples only
     *  (GlobalInitializer::feed). single_fix: the first fix is the start, without velocity
     *  (GlobalInitOptions::single_fix; for a relocalization, whose tracker knows its velocity). heading: the
     *  orientation the track had (a relocalization), which settles fixes ambiguous between turned places. odometry:
     *  where the lost track puts the frame (searched near it, and settling ambiguity; OdometryPrediction). */
    void begin(const std::string& label, const std::optional<SearchPrior>& prior = std::nullopt,
               bool single_fix = false, const std::optional<HeadingPrior>& heading = std::nullopt);
    /** The IMU biases the next search starts from (its pair check and the start it returns, unless the platform
     *  stands still meanwhile): the calibration's prior for the start, the track's for a relocalization. Not while
     *  a search is under way. */
    void setBiasPrior(const ImuBiasPrior& biases) { init_options_.bias_prior = biases; }
    std::optional<GlobalInitialState> feed(const dataset::StereoFrame& frame, bool attempt = true,
                                           const std::optional<OdometryPrediction>& odometry = std::nullopt);

    const map::DistanceField& field() const { return localizer_->field(); }
    /** Wall time of the localizer's set-up (its distance field, if this built it, and the candidate positions). */
    double setupSeconds() const { return setup_s_; }

    /** What the frame's stereo geometry says of a tracked pose. */
    struct TrackCheck
    {
        double explained = 0;               ///< share of the stereo points the map explains at the tracked pose
        bool refined = false;               ///< the points were aligned to the map from the tracked pose (below)
        double refined_explained = 0;       ///< that share at the aligned pose
        double moved_m = 0, moved_deg = 0;  ///< from the tracked pose to the aligned one
    };
    /** explained = GeometricLocalizer::inlierRatio at T_world_cam0; when it is below `refine_below`, the points are
     *  also aligned to the map from T_world_cam0 (Gauss-Newton on the distance field, then ICP), which tells a
     *  view the map merely explains poorly (the alignment stays) from a wrong pose (it moves away). `points`: the
     *  frame's stereo cloud when the tracker computed it already (the same SGBM with the same options: one stereo
     *  pipeline per frame); empty: computed here. */
    TrackCheck checkTrack(const dataset::StereoFrame& frame, const Eigen::Isometry3d& T_world_cam0, double refine_below,
                          const std::vector<Eigen::Vector3f>& points = {}) const;

    /** The console lines of the attempts are kept (takeConsole) instead of printed: for a search on another thread,
     *  whose lines the tracking thread prints between its own. */
    void deferConsole(bool defer) { defer_console_ = defer; }
    std::string takeConsole();
    /** Where the starter's lines go. */
    std::ostream& console() { return out_; }

    /** One line per attempt (t, result, error against ground truth when the frames have it), and every start. */
    const std::string& record() const { return record_; }

   private:
    void say(const std::string& text);

    std::unique_ptr<reloc::GeometricLocalizer> localizer_;
    std::unique_ptr<estimation::MapRefiner> refiner_;
    core::CameraModel camera_;
    Eigen::Isometry3d T_body_cam_;
    estimation::ImuNoise imu_noise_;
    GlobalInitOptions init_options_;
    std::string record_;
    bool defer_console_ = false;
    std::string console_;
    std::ostream& out_;
    double setup_s_ = 0;
    // The search under way (begin() .. a start).
    std::unique_ptr<GlobalInitializer> init_;
    std::string label_;
    size_t reported_ = 0;
    std::map<double, mrpt::poses::CPose3D> truth_;  // ground truth of the frames fed, for the record
};
}  // namespace quasiloc::tracking
