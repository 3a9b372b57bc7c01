#pragma once
// FrameSource: the one interface through which the estimator sees data, so an MRPT rawlog, an EuRoC ASL
// folder and the simulator's output look the same.
#include <memory>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/frame.h>
#include <string>
#include <vector>

namespace quasiloc::dataset
{
class FrameSource
{
   public:
    virtual ~FrameSource() = default;
    /** Calibration of the stereo pair and its pose in the IMU (body) frame. */
    virtual const core::StereoRig& rig() const = 0;
    /** Fills `frame` with the next stereo frame; false at the end of the data. Throws on corrupt input. */
    virtual bool next(StereoFrame& frame) = 0;
    /** A short description for logs ("rawlog /path/x.rawlog"). */
    virtual std::string description() const = 0;
    /** Things about the input that were tolerated but that a person should know (skipped rows, dropped
     *  samples, frames without ground truth...), one line each. Complete once next() has returned false;
     *  sources that decide everything up front (EuRoC) fill it at open. */
    virtual std::vector<std::string> warnings() const { return {}; }
};

struct FrameSourceOptions
{
    /** Optional TUM file with T_world_cam0; frames get the pose at their timestamp (within max_gt_dt_s).
     *  An EuRoC state_groundtruth_estimate0/data.csv (T_world_body) is accepted too and multiplied by the rig's
     *  T_body_left (see ground_truth.h). */
    std::string groundtruth_tum;
    double max_gt_dt_s = 0.005;
    /** Optional calibration INI (StereoRig keys, prefix "camera_"); overrides what the data carries. */
    std::string calibration_ini;
    /** Rawlogs: how long MRPT may go without progress (asking for bytes, or finishing) while it reads one object of
     *  a class the reader does not parse, in its child process; after that the child is killed and the object is an
     *  InputError. Reading a valid object takes milliseconds. */
    double mrpt_object_timeout_s = 10;
};

/** Streams a rawlog (never loads it whole). Stereo frames come from CObservationStereoImages (external
 *  images resolved in `<name>_Images/` beside the rawlog); IMU from CObservationIMU. The rig comes from the
 *  first stereo observation (leftCamera, rightCamera, rightCameraPose, cameraPose) unless a calibration INI
 *  is given. Objects of other classes (observations, which warnings() counts, and actions) are read by MRPT in a
 *  child process that the first of them forks (rawlogs of quasiloc's tools hold none): a corrupt one is an
 *  InputError, not a crash or an exit of the calling program. */
std::unique_ptr<FrameSource> openRawlog(const std::string& rawlog_path, const FrameSourceOptions& options = {});

/** Reads an EuRoC ASL folder (the one holding mav0/, or mav0/ itself). cam1 rows without an image
 *  (or cam0 rows without a matching cam1 image) are skipped and counted, not fatal: warnings() lists them
 *  (one line per reason, with the count and the first timestamps) right after opening. See euroc.h for the
 *  structured counts. */
std::unique_ptr<FrameSource> openEuroc(const std::string& asl_folder, const FrameSourceOptions& options = {});

}  // namespace quasiloc::dataset
