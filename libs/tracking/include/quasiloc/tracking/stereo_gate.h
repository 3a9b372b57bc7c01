#pragma once
// The stereo gate of one frame: whether the frame's stereo factors enter the window, given how well the stereo
// agrees with the map at the edge-aligned pose. The track monitor (track_monitor.h) sets its bound from the track's
// health before each frame; the tracker applies it to what it measured. The edge-aligned pose rests on the left
// image alone, so it can judge the stereo, but only while its edges fit as well as they usually do: aligned from a
// wrong pose (a restart, a kidnap, the end of a gap) the edges settle in a poorer optimum, and then the stereo, not
// the pose, is the one to believe.
#include <cmath>

namespace quasiloc::tracking
{
struct StereoGate
{
    /** The stereo is left out above this median distance to the map, in point sigmas; 0: never left out. */
    double max_sigmas = 0;
    /** The edge pose judges the stereo only with an edge inlier ratio of at least this share of the usual one. */
    double min_edge_ratio = 0;
    /** The usual edge inlier ratio (NaN: none yet, the edges count as usual). */
    double usual_edge_ratio = NAN;
    /** False while the track is lost: the frame is tracked by odometry alone (IMU and stereo landmarks), since the
     *  map terms at a doubtful pose pull it into a wrong place's optimum and the search's prior with it. */
    bool map_terms = true;
    /** While the track is lost: the velocity's variance grows by this squared per second [m/s/sqrt(s)] before the
     *  frame (zero_velocity_update.h), since a lost track's velocity may have diverged; 0: as the marginal says. */
    double velocity_random_walk = 0;

    bool edgesAsUsual(double edge_inlier_ratio) const
    {
        return std::isnan(usual_edge_ratio) || edge_inlier_ratio >= min_edge_ratio * usual_edge_ratio;
    }
    /** The stereo, measured at `stereo_map_sigmas` against an alignment with `edge_inlier_ratio`, is left out. */
    bool rejects(double stereo_map_sigmas, double edge_inlier_ratio) const
    {
        return edgesAsUsual(edge_inlier_ratio) && max_sigmas > 0 && stereo_map_sigmas > max_sigmas;
    }
};
}  // namespace quasiloc::tracking
