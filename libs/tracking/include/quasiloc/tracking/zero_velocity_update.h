#pragma once
// What the tracker changes in the previous state's prior before a frame, when the IMU or the track's health says
// something of the velocity that the window's marginal does not know:
//   - a zero-velocity update: the platform stands (the IMU's standstill detector, static_initialization.h), so the
//     velocity is zero to within the sway of a standing platform, as OpenVINS's zero-velocity update does;
//   - a widened velocity: while the track is lost its velocity may have diverged (the marginal grows only by the
//     IMU's noise densities, not by the tilt and bias errors a lost track accumulates), and a velocity that is surer
//     than it is turns the stereo landmarks that disagree with it into outliers of the window's robust loss.
// Tangent order of the prior: prior_factor.h ([dtheta; dp; v; b_g; b_a]).
#include <opencv2/core/types.hpp>
#include <quasiloc/estimation/prior_factor.h>
#include <quasiloc/frontend/point_matcher.h>
#include <vector>

namespace quasiloc::tracking
{
/** The block of 3 tangent coordinates from `first` becomes independent of the rest, with `sigma` per axis (its
 *  correlations with the other blocks are dropped: its new value does not come from them). */
void resetBlock(estimation::StatePrior& prior, int first, double sigma);

/** The state (and the prior's mean) stand: velocity zero, with sigma_v [m/s] per axis. */
void applyZeroVelocity(estimation::FrameState& state, estimation::StatePrior& prior, double sigma_v);

/** The velocity's covariance grows by `variance` [m^2/s^2] per axis; the other blocks' marginals and the
 *  correlations stay as they were. */
void widenVelocity(estimation::StatePrior& prior, double variance);

/** The median image motion [px] of the matched keypoints (query: `previous`, train: `current`); NaN with fewer
 *  than min_matches. An IMU that reads standing cannot tell standing from a steady straight run (both read gravity
 *  and vibration alone); the image can. */
double medianImageMotionPx(const std::vector<cv::KeyPoint>& previous, const std::vector<cv::KeyPoint>& current,
                           const std::vector<frontend::PointMatch>& matches, size_t min_matches);

/** Keypoints followed through consecutive frames' matches: where each keypoint of the newest frame was first seen,
 *  and how many frames ago. From one frame to the next a slow run forward moves most points by less than a pixel
 *  (ORB keypoints lie on their pyramid level's pixel grid); over a third of a second it moves them by several. */
class KeypointTracks
{
   public:
    /** The frame `current` with its matches to `previous` (query: previous, train: current). When `previous` is not
     *  the frame added last, the tracks start again at `previous`. Returns the median motion [px] since their first
     *  sighting of the tracks followed over at least min_frames frames; NaN with fewer than min_tracks of them. */
    double add(const void* previous_id, const std::vector<cv::KeyPoint>& previous, const void* current_id,
               const std::vector<cv::KeyPoint>& current, const std::vector<frontend::PointMatch>& matches,
               int min_frames, size_t min_tracks);

   private:
    struct Origin
    {
        cv::Point2f pt;
        int frames = 0;  ///< frames followed
    };
    const void* last_id_ = nullptr;
    std::vector<Origin> origins_;  ///< per keypoint of the frame added last
};

}  // namespace quasiloc::tracking
