#pragma once
// Global localization of one camera image against the LiDAR map's virtual views by structure, not appearance
// (quasiloc-localize mode `structure`). Camera grey levels and LiDAR reflectivity are unrelated point by point;
// what they share is the layout of gradient orientations with the sign ignored (docs/crossmodal_statistics.md), and
// that only weakly per keypoint (docs/crossmodal_matching.md). So:
//  1. retrieval sums that weak evidence over the whole image: a coarse grid of sign-free orientation histograms of
//     the camera image against the same of every view's rank-equalised reflectivity and depth-edge channels
//     (structure_retrieval.h), searched over shifts of the grid (the query's heading and pitch between the views');
//  2. for each of the best candidates (a view turned by its best shift) the map is rendered at the guess, map
//     keypoints of both channels are matched densely in the camera's orientation field within the window the
//     guess's uncertainty predicts (structure_matching.h), lifted to map points through the provenance, and
//     PnP-RANSAC gives the next guess; the window shrinks from iteration to iteration (iteration_sigma_m/_deg);
//  3. the candidate with the most PnP inliers at the last iteration wins; it must reach min_inliers and
//     min_inlier_ratio, else the answer is "not localized" with the reason.
// The views are any set of T_world_cam (the database's, or view_sampling.h's); their quasi-images are rendered once,
// at construction, at 1/downscale of the query camera's resolution.
//
// Options: [StructureLocalization] (StructureLocalizerOptions::declare, structure_options.cpp).
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/quasi/quasi_options.h>
#include <quasiloc/reloc/localizer.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
/** How retrieval ranks the views: by their best shift's correlation, or by how far it stands out of the view's
 *  correlations at all shifts (peak). */
enum class StructureRetrievalScore
{
    Correlation,
    Peak
};

struct StructureLocalizerOptions : public core::DeclaredOptions
{
    int downscale = 2;          ///< retrieval renders and describes at 1/downscale of the camera's resolution
    double cell_px = 32;        ///< retrieval grid cell, in full-resolution pixels
    int max_shift_x_cells = 6;  ///< heading search: the grid shifted by up to this many cells left and right
    int max_shift_y_cells = 3;  ///< pitch search, up and down
    double min_overlap = 0.5;   ///< of the camera grid's cells, those a shifted view must cover with valid cells
    StructureRetrievalScore retrieval_score = StructureRetrievalScore::Peak;
    int candidates = 12;                  ///< retrieved guesses refined
    double candidate_separation_m = 0.3;  ///< a retrieved guess this close to a better one (and ...
    double candidate_separation_deg = 6;  ///< ... this close in rotation) is skipped
    int keypoints = 200;                  ///< map keypoints per guess, half from each channel
    double min_keypoint_distance_px = 8;  ///< between map keypoints of one channel
    double min_valid_share = 0.8;         ///< of a map keypoint's descriptor footprint
    double window_base_px = 8;            ///< search radius r = base + f (sigma_rad + sigma_m / depth) ...
    double window_max_px = 64;            ///< ... at most this
    std::vector<double> iteration_sigma_m{0.4, 0.15, 0.05};  ///< the guess's uncertainty per iteration
    std::vector<double> iteration_sigma_deg{4, 1.5, 0.5};    ///< (the same count as iteration_sigma_m)
    double ratio = 0.95;                                     ///< best / second best descriptor distance (unsquared)
    double consensus_px = 0;   ///< matches kept when their displacement is this close to the common one
    double pnp_reproj_px = 4;  ///< PnP inlier threshold
    int pnp_max_iterations = 1000;
    int min_step_inliers = 8;        ///< an iteration's PnP needs this many inliers to move the guess
    int min_inliers = 15;            ///< the answer's PnP inliers at the last iteration
    double min_inlier_ratio = 0.15;  ///< the answer's inliers / its correspondences
    int depth_bands = 4;             ///< rank equalisation of the reflectivity per log-depth band
    double fill_sigma_px = 3;        ///< quasi-image holes filled before describing
    double depth_edge_sigma_px = 3;  ///< depth-edge channel: local mean window ...
    double depth_edge_scale = 0.1;   ///< ... and tanh scale (log depth)

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of range or iteration lists of different lengths. */
    void check(const std::string& input) const;
};

/** One refined candidate, for the diagnostics. */
struct StructureCandidate
{
    int view = -1;
    float retrieval_score = 0;
    Eigen::Isometry3d T_world_guess = Eigen::Isometry3d::Identity();  ///< the view turned by its best shift
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();    ///< after the iterations
    int iterations = 0;                                               ///< that moved the guess
    int matches = 0, inliers = 0;                                     ///< of the last iteration
    double guess_error_m = NAN, guess_error_deg = NAN;                ///< against the truth, when given
    double error_m = NAN, error_deg = NAN;
};

struct StructureDiagnostics
{
    std::vector<StructureCandidate> candidates;
    /** With the truth: the best retrieval rank (0-based, over all views' best shifts) of a guess within 0.5 m and
     *  10 deg of the truth (-1: none), and the rank of the view nearest the truth with its shifted guess error. */
    int first_good_rank = -1;
    int nearest_view = -1, nearest_view_rank = -1;
    double nearest_guess_error_m = NAN, nearest_guess_error_deg = NAN;
};

class StructureLocalizer
{
   public:
    /** Renders and describes every view in `camera`'s geometry (at 1/downscale). `map` must outlive the localizer.
     *  InputError for bad options or no view. */
    StructureLocalizer(const map::LidarMap& map, const std::vector<mrpt::poses::CPose3D>& T_world_views,
                       const core::CameraModel& camera, const quasi::QuasiOptions& quasi_options,
                       const StructureLocalizerOptions& options);
    ~StructureLocalizer();

    /** Localizes an 8-bit grey (or BGR) image taken with the camera given at construction. With T_world_cam_truth
     *  the diagnostics carry the errors and retrieval ranks (the answer does not use it). */
    LocalizationReport localize(const cv::Mat& image, const Eigen::Isometry3d* T_world_cam_truth = nullptr);
    const StructureDiagnostics& lastDiagnostics() const;
    /** One line per query: decision, retrieval ranks, candidates with their errors. */
    std::string describeLast() const;
    /** Views and set-up time, for the console. */
    std::string summary() const;

   private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace quasiloc::reloc
