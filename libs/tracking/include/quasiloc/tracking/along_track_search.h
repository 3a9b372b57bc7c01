#pragma once
// A search of the frame's stereo points against the map along the camera's horizontal viewing direction, for the
// error the window's map terms cannot reach: along a street.
//
// The stereo surface term (map_distance_factor.h) is truncated: a point farther off its surface than a few of its
// sigmas stops pulling. Along a straight street the road and the facades are parallel to the motion, so a track that
// drifts along the street stays on them and the term holds its height and side only; what lies across the street
// (a wall ahead, the curbs and facades of a crossing street, poles, trees) is metres off its surface by the time the
// drift shows, beyond the truncation. The search shifts the camera along the horizontal projection of its optical
// axis over [-range, range] and scores each shift by the truncated chi-square of the points' distances to the map;
// a minimum away from the prediction that is clearly lower than the prediction's score and than every shift a metre
// or more from it (a unique one: a street with nothing across it has a flat score) becomes a measurement of the
// position along that direction. The track's prior then widens along it: its confidence along the street came from
// the IMU and the landmarks, whose drift the search has just seen.
#include <Eigen/Geometry>
#include <quasiloc/estimation/prior_factor.h>
#include <quasiloc/estimation/tracking_window.h>
#include <quasiloc/map/distance_field.h>
#include <quasiloc/tracking/tracking_options.h>
#include <vector>

namespace quasiloc::tracking
{
struct AlongTrackSearchOptions
{
    double range_m = 4;             ///< shifts searched on each side of the prediction
    double step_m = 0.1;            ///< between shifts
    double cap_sigmas = 3;          ///< a point's distance counts up to this many of its sigmas
    double effective_points = 200;  ///< all points together count as this many independent observations
    double min_gain =
        9;  ///< chi-square the best shift must gain over the prediction and over any shift >= unique_m from it
    double unique_m = 1.0;
    double smooth_m = 0;  ///< each shift's score is the mean of the scores within this of it
};

struct AlongTrackFix
{
    bool found = false;
    double shift_m = 0;                                             ///< along `direction_world`
    Eigen::Vector3d direction_world = Eigen::Vector3d::Zero();      ///< unit, horizontal
    double chi2_prediction = 0, chi2_best = 0, chi2_runner_up = 0;  ///< runner-up: the best shift >= unique_m away
};

/** The camera's optical axis projected onto the horizontal plane of the map frame (z up), unit; zero when the camera
 *  looks straight up or down. */
Eigen::Vector3d horizontalViewingDirection(const Eigen::Isometry3d& T_world_cam);

/** Scores the shifts of the points (camera frame, with their sigmas) at T_world_cam + s * direction against the
 *  field. found when the best shift is not the prediction (|s| >= step) and gains min_gain over both the prediction
 *  and the runner-up. InputError for mismatched inputs or options out of range. */
AlongTrackFix searchAlongTrack(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam,
                               const std::vector<Eigen::Vector3d>& p_cam, const std::vector<double>& sigma_m,
                               const AlongTrackSearchOptions& options);

/** The fix as a pose measurement of the current body pose (information along the direction only, sigma_m) at the
 *  predicted body pose shifted by it. */
estimation::PoseMeasurement alongTrackMeasurement(const AlongTrackFix& fix, const Eigen::Isometry3d& T_map_body_pred,
                                                  double sigma_m);

/** The prior's position (body-frame tangent) grows by shift^2 along the fix's direction and its velocity by
 *  (velocity_sigma)^2 along it; the other directions keep their marginals. */
void widenAlongTrack(estimation::StatePrior& prior, const AlongTrackFix& fix, double velocity_sigma);

/** The tracker's use of it ([MapFactors] along_track_* keys) before the window: the points searched at the start
 *  guess (the prediction); with a fix, the previous state's prior widens (widenAlongTrack), the previous state, its
 *  prior's mean and the start guess move by the shift (the window starts where the map puts the track) and the
 * measurement joins `measurements`. */
AlongTrackFix correctAlongTrack(const map::DistanceField& field, const MapFactorOptions& options,
                                const Eigen::Isometry3d& T_body_cam, const std::vector<Eigen::Vector3d>& p_cam,
                                const std::vector<double>& sigma_m, estimation::FrameState& previous,
                                estimation::StatePrior& prior, estimation::FrameState& start,
                                std::vector<estimation::PoseMeasurement>& measurements);

}  // namespace quasiloc::tracking
