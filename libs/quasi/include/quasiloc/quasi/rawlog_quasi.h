#pragma once
// rawlog-quasi: a rawlog with a quasi-image beside every camera frame, so that camera images and quasi-images
// can be compared in RawLogViewer. Sections [RawlogQuasi] (RawlogQuasiOptions::declare, rawlog_quasi.cpp) and
// [QuasiImage] (renderer options, quasi_options.h).
//
// Output: every observation of the input is copied in order (external image files copied into the output's
// _Images folder); after each CObservationStereoImages comes a CObservationImage (label sensor_label,
// same timestamp, cameraParams = the left camera, cameraPose = T_body_left, the BGR quasi-image as an external
// PNG). Geometry: the quasi-image is rendered with the RAW (distorted) left camera model at T_world_cam0, i.e.
// in exactly the pixel geometry of the stored left image, so both overlay pixel for pixel.
// Nothing is written at the final paths unless the whole run succeeds (staged outputs).
#include <quasiloc/quasi/quasi_options.h>
#include <string>
#include <vector>

namespace quasiloc::quasi
{
struct RawlogQuasiOptions : public core::DeclaredOptions
{
    std::string input_rawlog, map_file, groundtruth, output_rawlog;
    double max_gt_dt_s = 0.005;
    std::string sensor_label = "quasi";
    std::string png_dir;
    int png_every = 1;
    int max_frames = 0;

    void declare(core::OptionTable& t) override;
    /** The declared ranges, then InputError naming the key for a missing or unusable value (files must exist). */
    void check(const std::string& input) const;
};

struct RawlogQuasiResult
{
    size_t observations_copied = 0, stereo_frames = 0, quasi_images = 0, frames_without_pose = 0;
    size_t pngs_written = 0;
    /** Provenance check over all quasi-images: worst reprojection error (px) of sparse / completed pixels. */
    double max_sparse_error_px = 0, max_completed_error_px = 0;
    double mean_render_ms = 0, max_render_ms = 0;
    std::vector<std::string> warnings;
    std::string timing_table;  ///< CTimeLogger stage table (quasi.culling, .projection, .completion, .encoding)
};

/** Runs the conversion; `effective_config` (the INI text of all options) is written beside the output rawlog
 *  as <output name>_rawlog-quasi.ini. */
RawlogQuasiResult runRawlogQuasi(const RawlogQuasiOptions& options, const QuasiOptions& quasi_options,
                                 const std::string& effective_config);

}  // namespace quasiloc::quasi
