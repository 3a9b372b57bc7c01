#pragma once
// Refining a camera pose against the LiDAR map from a predicted pose: the step that tracking runs
// on keyframes and that relocalization runs on its hypotheses. Four methods, so that they can be compared:
//
//  features  render Q at the prediction; match camera keypoints to Q's over the whole image (mutual NN +
//            ratio); lift Q's keypoints through provenance; robust PnP (absolute_pose.h).
//  guided    the same, but each camera keypoint looks for its counterpart only within a window around its
//            own position (Q is rendered at the prediction, so the counterpart lies within the prediction's
//            reprojection uncertainty: radius = window_sigmas * f * (sigma_rot + sigma_t / median depth));
//            it keeps up to `guided_candidates` candidates (its association distribution) and no ratio test:
//            PnP's consensus picks among them.
//  direct    direct_alignment.h: map edges onto camera edges (distance transform), coarse to fine.
//  combined  direct, then Q re-rendered at the direct estimate and guided matching with the (now small)
//            window of the direct result; PnP's pose is kept if it has enough inliers and agrees with the
//            direct one (within agree_m / agree_deg), else the direct pose stands.
//
//
// Options: [MapRefinement] (MapRefinementOptions::declare, map_refinement_options.cpp) and [DirectAlignment].
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/estimation/direct_alignment.h>
#include <quasiloc/frontend/frontend.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <memory>
#include <optional>
#include <string>

namespace quasiloc::estimation
{
enum class RefinementMethod
{
    Features,
    Guided,
    Direct,
    Combined
};
std::string toString(RefinementMethod m);
RefinementMethod refinementMethodFromString(const std::string& name, const std::string& input);

/** The 8-bit image of a quasi-image that its features are extracted on. */
enum class QuasiGray
{
    Encoding,            ///< Q's gray image ([QuasiImage] gray_mode)
    MatchedReflectivity  ///< the reflectivity remapped to the camera image's histogram (quasi/histogram_matching.h)
};

struct MapRefinementOptions : public core::DeclaredOptions
{
    double window_sigmas = 2.0;
    double min_window_px = 8, max_window_px = 160;
    int guided_candidates = 3;
    double combined_sigma_m = 0.05, combined_sigma_deg = 0.3;
    int min_inliers = 15;
    double agree_m = 0.3, agree_deg = 2.0;
    double gate_sigmas = 3.0;
    double direct_prior_weight = 0.2;
    double lift_radius_px = 2;
    double pnp_max_error_px = 3;
    QuasiGray quasi_gray = QuasiGray::Encoding;
    DirectAlignmentOptions direct;  ///< section [DirectAlignment]

    void declare(core::OptionTable& t) override;
    /** [MapRefinement] from `section`, and `direct` from [DirectAlignment]. */
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    /** InputError naming `input` and the key for a value out of its declared range (here or in `direct`) or
     *  min_window_px > max_window_px. */
    void check(const std::string& input) const;
};

struct MapRefinementResult
{
    bool success = false;  ///< the method produced a pose (features: PnP with >= min_inliers inliers)
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    int matches = 0;                        ///< 2D-3D correspondences given to PnP (guided: all candidates)
    std::vector<Eigen::Vector2d> points2d;  ///< those correspondences (camera pixel, lifted map point), for
    std::vector<Eigen::Vector3d> points3d;  ///<   diagnostics (e.g. counting correct ones at a known pose)
    int inliers = 0;
    double window_px = 0;
    DirectAlignmentStats direct;
    /** direct/combined: the map model the alignment used (built at the prediction), e.g. for a DirectEdgeTerm of
     *  the estimator window together with edgeField(). */
    std::shared_ptr<const DirectAlignmentModel> direct_model;
    double ms_render = 0, ms_extract = 0, ms_match = 0, ms_pnp = 0, ms_direct = 0, ms_total = 0;
};

/** Holds the per-image camera side (features, edge field) so that several methods and hypotheses can be tried
 *  on one image. Not thread-safe (the renderer's buffers). */
class MapRefiner
{
   public:
    /** `renderer` and `frontend` must outlive the refiner. InputError for bad options. */
    MapRefiner(const MapRefinementOptions& options, quasi::QuasiRenderer& renderer, frontend::Frontend& frontend);

    /** The camera image (8-bit gray or BGR) and its camera model: extracts features (unless with_features is
     *  false: then only the direct method can be used) and the edge field once. */
    void setImage(const cv::Mat& image, const core::CameraModel& camera, bool with_features = true);
    /** Refines T_world_cam_pred with `method`; sigma_*: the prediction's uncertainty (guided window).
     *  direct_prior_weight: this call's weight of the prediction prior in the direct term (default: the option's;
     *  0: none, e.g. to see where the term's own optimum lies when the prediction is the answer). */
    MapRefinementResult refine(RefinementMethod method, const Eigen::Isometry3d& T_world_cam_pred, double sigma_m,
                               double sigma_rad, std::optional<double> direct_prior_weight = std::nullopt);

    /** The direct method in two halves, so that the first can overlap setImage() on another thread:
     *  prepareDirect renders the map at the prediction with `camera` and builds its edge model (it reads no member
     *  that setImage writes); alignPrepared aligns that model to the edge field of the last setImage(), with the
     *  prediction prior of refine(). refine(Direct) is the two in turn. `encode` false: quasiImage() gets the planes
     *  only (QuasiRenderer::render), no bgr or gray, so no quasiFeatureImage(). `downscale` > 1: the map is rendered
     *  at 1/downscale of the camera's resolution (CameraModel::downscaled) and its edges found on blocks of
     *  model_block_px / downscale rendered pixels, the same blocks of the image (it must divide model_block_px);
     *  quasiImage() is then at that resolution. */
    std::shared_ptr<const DirectAlignmentModel> prepareDirect(const core::CameraModel& camera,
                                                              const Eigen::Isometry3d& T_world_cam_pred,
                                                              bool encode = true, int downscale = 1);
    MapRefinementResult alignPrepared(std::shared_ptr<const DirectAlignmentModel> model,
                                      const Eigen::Isometry3d& T_world_cam_pred, double sigma_m, double sigma_rad,
                                      std::optional<double> direct_prior_weight = std::nullopt);
    double lastImageMs() const { return image_ms_; }
    const MapRefinementOptions& options() const { return options_; }
    /** The camera side of the direct term for the current image (valid until the next setImage). */
    const CameraEdgeField& edgeField() const { return edge_field_; }
    const frontend::FrameFeatures& cameraFeatures() const { return camera_features_; }
    /** The quasi-image the last refine() rendered (at its T_world_cam_pred). */
    const quasi::QuasiImage& quasiImage() const { return q_; }
    /** The 8-bit image of that quasi-image that its features are extracted on (quasi_gray): its gray image, or its
     *  reflectivity matched to the current camera image's histogram. */
    cv::Mat quasiFeatureImage() const;

   private:
    /** Render at the prediction, extract on Q, match (guided: within the window of sigma_m / sigma_rad), lift,
     *  PnP. */
    MapRefinementResult featurePose(const Eigen::Isometry3d& T_world_cam_pred, bool guided, double sigma_m,
                                    double sigma_rad);
    double windowFor(double sigma_m, double sigma_rad, double median_depth_m) const;

    MapRefinementOptions options_;
    quasi::QuasiRenderer& renderer_;
    frontend::Frontend& frontend_;
    core::CameraModel camera_;
    cv::Mat gray_;
    bool has_features_ = false;
    frontend::FrameFeatures camera_features_;
    CameraEdgeField edge_field_;
    quasi::QuasiImage q_;
    double image_ms_ = 0;
    double prepare_ms_ = 0;  ///< the last prepareDirect's render and model
};

}  // namespace quasiloc::estimation
