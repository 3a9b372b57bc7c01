#pragma once
// TUM trajectory files: one pose per line, "t tx ty tz qx qy qz qw", '#' comments. A file holds
// T_world_frame; the frame is named in the header comment (e.g. "# T_world_cam0").
#include <mrpt/poses/CPose3D.h>

#include <string>
#include <vector>

namespace quasiloc::core
{
struct TimedPose
{
    double t = 0;  ///< seconds
    mrpt::poses::CPose3D pose;
};

struct Trajectory
{
    std::string header;  ///< comment lines without the leading '#', joined by '\n'
    std::vector<TimedPose> poses;
};

/** Reads a TUM file. InputError naming the file and line for a missing file, a line with other than
 *  8 numbers, a non-finite value or a non-unit quaternion (|q| off by > 1e-2); quaternions are normalised.
 *  Timestamps need not be sorted (the reader sorts them, stable). */
Trajectory readTum(const std::string& path);
/** Writes atomically with full precision (timestamps to 1 ns, translations to 0.1 um). */
void writeTum(const std::string& path, const Trajectory& traj);

/** Linear/slerp interpolation of a time-sorted trajectory at t; false when t is outside it by more
 *  than `max_extrapolation_s`. */
bool interpolatePose(const Trajectory& traj, double t, mrpt::poses::CPose3D& out, double max_extrapolation_s = 0);

}  // namespace quasiloc::core
