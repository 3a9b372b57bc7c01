#include <mrpt/system/CTicTac.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/estimation/absolute_pose.h>
#include <quasiloc/estimation/map_refinement.h>
#include <quasiloc/quasi/histogram_matching.h>
#include <quasiloc/frontend/lifting.h>
#include <unordered_map>

namespace quasiloc::estimation
{
std::string toString(RefinementMethod m)
{
    switch (m)
    {
        case RefinementMethod::Features: return "features";
        case RefinementMethod::Guided: return "guided";
        case RefinementMethod::Direct: return "direct";
        case RefinementMethod::Combined: return "combined";
    }
    return "?";
}

RefinementMethod refinementMethodFromString(const std::string& name, const std::string& input)
{
    for (RefinementMethod m :
         {RefinementMethod::Features, RefinementMethod::Guided, RefinementMethod::Direct, RefinementMethod::Combined})
        if (toString(m) == name) return m;
    throw core::InputError(input, "'" + name + "' is not one of features, guided, direct, combined");
}

MapRefiner::MapRefiner(const MapRefinementOptions& options, quasi::QuasiRenderer& renderer,
                       frontend::Frontend& frontend)
    : options_(options), renderer_(renderer), frontend_(frontend)
{
    options_.check("MapRefiner");
}

void MapRefiner::setImage(const cv::Mat& image, const core::CameraModel& camera, bool with_features)
{
    core::require(!image.empty() && image.depth() == CV_8U && (image.channels() == 1 || image.channels() == 3),
                  "camera image", "must be a non-empty 8-bit gray or BGR image");
    core::require(
        image.cols == camera.width && image.rows == camera.height, "camera image",
        "size " + std::to_string(image.cols) + "x" + std::to_string(image.rows) + " differs from the camera model's");
    mrpt::system::CTicTac tic;
    camera_ = camera;
    if (image.channels() == 3)
        cv::cvtColor(image, gray_, cv::COLOR_BGR2GRAY);
    else
        gray_ = image;
    has_features_ = with_features;
    if (with_features) frontend_.extract(gray_, cv::Mat(), camera_features_);
    edge_field_ = buildCameraEdgeField(options_.direct, gray_);
    image_ms_ = tic.Tac() * 1e3;
}

cv::Mat MapRefiner::quasiFeatureImage() const
{
    if (options_.quasi_gray == QuasiGray::MatchedReflectivity) return quasi::reflectivityMatchedToImage(q_, gray_);
    return q_.gray;
}

double MapRefiner::windowFor(double sigma_m, double sigma_rad, double median_depth_m) const
{
    const double f = 0.5 * (camera_.fx + camera_.fy);
    const double r = options_.window_sigmas * f * (sigma_rad + sigma_m / std::max(0.5, median_depth_m));
    return std::clamp(r, options_.min_window_px, options_.max_window_px);
}

namespace
{
bool withinGate(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B, double max_m, double max_rad)
{
    return (A.translation() - B.translation()).norm() <= max_m &&
           Eigen::AngleAxisd(A.linear().transpose() * B.linear()).angle() <= max_rad;
}

double medianValidDepth(const quasi::QuasiImage& q)
{
    std::vector<float> d;
    for (int y = 0; y < q.depth.rows; y += 4)
        for (int x = 0; x < q.depth.cols; x += 4)
            if (q.valid.at<uint8_t>(y, x)) d.push_back(q.depth.at<float>(y, x));
    if (d.empty()) return 10.0;
    std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
    return d[d.size() / 2];
}
}  // namespace

MapRefinementResult MapRefiner::featurePose(const Eigen::Isometry3d& T_world_cam_pred, bool guided, double sigma_m,
                                            double sigma_rad)
{
    MapRefinementResult res;
    res.T_world_cam = T_world_cam_pred;
    mrpt::system::CTicTac tic;
    renderer_.render(core::fromIsometry(T_world_cam_pred), camera_, q_);
    res.ms_render = tic.Tac() * 1e3;
    const double window_px = guided ? windowFor(sigma_m, sigma_rad, medianValidDepth(q_)) : 0.0;
    res.window_px = window_px;
    tic.Tic();
    frontend::FrameFeatures fq;
    frontend_.extract(quasiFeatureImage(), q_.valid, fq);
    res.ms_extract = tic.Tac() * 1e3;

    tic.Tic();
    const frontend::Features& cam = camera_features_.points;
    std::vector<std::pair<int, int>> pairs;  // (camera keypoint, Q keypoint)
    if (window_px <= 0)
    {
        frontend::PointMatchingOptions pm = frontend_.options().point_matching;
        pm.window_px = 0;
        for (const frontend::PointMatch& m : frontend::matchPoints(cam, fq.points, pm))
            pairs.emplace_back(m.query, m.train);
    }
    else
    {
        frontend::SearchRegion region;
        region.radius_px = window_px;
        const auto candidates = frontend::findCandidates(cam, fq.points, options_.guided_candidates,
                                                         frontend_.options().point_matching.maxDistance(cam), region);
        for (size_t i = 0; i < candidates.size(); ++i)
            for (const frontend::PointCandidate& c : candidates[i]) pairs.emplace_back(int(i), c.index);
    }
    std::unordered_map<int, std::optional<frontend::LiftedPoint>> lifted;
    std::vector<Eigen::Vector2d> pts2d;
    std::vector<Eigen::Vector3d> pts3d;
    for (const auto& [i, j] : pairs)
    {
        auto it = lifted.find(j);
        if (it == lifted.end())
            it = lifted
                     .emplace(j, frontend::liftPixel(q_, renderer_.map(), fq.points.keypoints[size_t(j)].pt,
                                                     options_.lift_radius_px))
                     .first;
        if (!it->second) continue;
        const cv::Point2f& u = cam.keypoints[size_t(i)].pt;
        pts2d.emplace_back(u.x, u.y);
        pts3d.push_back(it->second->p_world.cast<double>());
    }
    res.matches = int(pts2d.size());
    res.ms_match = tic.Tac() * 1e3;
    res.points2d = pts2d;
    res.points3d = pts3d;

    tic.Tic();
    if (res.matches >= options_.min_inliers)
    {
        AbsolutePoseOptions po;
        po.max_reproj_error_px = options_.pnp_max_error_px;
        po.min_inliers = options_.min_inliers;
        Eigen::Isometry3d T_cam_world;
        AbsolutePoseStats st;
        if (estimateAbsolutePose(po, pts2d, pts3d, camera_, &T_cam_world, &st))
        {
            res.success = true;
            res.inliers = st.num_inliers;
            res.T_world_cam = T_cam_world.inverse();
        }
    }
    res.ms_pnp = tic.Tac() * 1e3;
    return res;
}

std::shared_ptr<const DirectAlignmentModel> MapRefiner::prepareDirect(const core::CameraModel& camera,
                                                                      const Eigen::Isometry3d& T_world_cam_pred,
                                                                      bool encode, int downscale)
{
    mrpt::system::CTicTac tic;
    // The model reads the planes on blocks only: rendered at a lower resolution, the same blocks cost a fraction of
    // the render's per-pixel work (completion, see-through filter). buildDirectAlignmentModel checks that the
    // downscale divides the blocks; CameraModel::downscaled keeps the whole coarse pixels of any image size.
    const core::CameraModel render_camera = camera.downscaled(downscale);
    renderer_.render(core::fromIsometry(T_world_cam_pred), render_camera, q_, encode,
                     renderer_.options().completionRadiusAt(downscale));
    auto model = std::make_shared<const DirectAlignmentModel>(buildDirectAlignmentModel(
        options_.direct, q_.depth, q_.reflectivity, q_.valid, q_.sparse, render_camera, T_world_cam_pred, downscale));
    prepare_ms_ = tic.Tac() * 1e3;
    return model;
}

MapRefinementResult MapRefiner::alignPrepared(std::shared_ptr<const DirectAlignmentModel> model,
                                              const Eigen::Isometry3d& T_world_cam_pred, double sigma_m,
                                              double sigma_rad, std::optional<double> direct_prior_weight)
{
    const double prior_weight = direct_prior_weight.value_or(options_.direct_prior_weight);
    core::require(prior_weight >= 0, "MapRefiner::alignPrepared direct_prior_weight", "must be >= 0");
    core::require(!gray_.empty(), "MapRefiner::alignPrepared", "setImage() must be called first");
    core::require(model != nullptr, "MapRefiner::alignPrepared", "no model (prepareDirect)");
    mrpt::system::CTicTac tic;
    MapRefinementResult res;
    Eigen::Isometry3d T = T_world_cam_pred;
    DirectPrior prior{T_world_cam_pred, sigma_m, sigma_rad, prior_weight};
    res.success =
        alignDirect(options_.direct, edge_field_, camera_, *model, T, &res.direct, prior_weight > 0 ? &prior : nullptr);
    res.T_world_cam = T;
    res.direct_model = std::move(model);
    res.ms_render = prepare_ms_;
    res.ms_direct = tic.Tac() * 1e3;
    res.ms_total = res.ms_render + res.ms_direct;
    return res;
}

MapRefinementResult MapRefiner::refine(RefinementMethod method, const Eigen::Isometry3d& T_world_cam_pred,
                                       double sigma_m, double sigma_rad, std::optional<double> direct_prior_weight)
{
    core::require(!gray_.empty(), "MapRefiner::refine", "setImage() must be called first");
    core::require(has_features_ || method == RefinementMethod::Direct, "MapRefiner::refine",
                  "method " + toString(method) + " needs the camera features (setImage with_features)");
    mrpt::system::CTicTac total;
    MapRefinementResult res;
    if (method == RefinementMethod::Features || method == RefinementMethod::Guided)
    {
        res = featurePose(T_world_cam_pred, method == RefinementMethod::Guided, sigma_m, sigma_rad);
        // A PnP consensus far outside the prediction's uncertainty is a consensus of wrong matches (cross-modal
        // matches are mostly wrong): keep the prediction rather than jump.
        if (res.success && !withinGate(res.T_world_cam, T_world_cam_pred, options_.gate_sigmas * sigma_m,
                                       options_.gate_sigmas * sigma_rad))
        {
            res.success = false;
            res.T_world_cam = T_world_cam_pred;
        }
    }
    else
    {
        const MapRefinementResult direct = alignPrepared(prepareDirect(camera_, T_world_cam_pred), T_world_cam_pred,
                                                         sigma_m, sigma_rad, direct_prior_weight);
        if (method == RefinementMethod::Direct)
            res = direct;
        else
        {
            res = featurePose(direct.T_world_cam, true, options_.combined_sigma_m,
                              options_.combined_sigma_deg * M_PI / 180.0);
            const bool agree =
                res.success && res.inliers >= options_.min_inliers &&
                withinGate(res.T_world_cam, direct.T_world_cam, options_.agree_m, options_.agree_deg * M_PI / 180.0);
            if (!agree)
            {
                res.T_world_cam = direct.T_world_cam;
                res.success = direct.success;
            }
            res.direct = direct.direct;
            res.direct_model = direct.direct_model;
            res.ms_render += direct.ms_render;
            res.ms_direct = direct.ms_direct;
        }
    }
    res.ms_total = total.Tac() * 1e3;
    return res;
}

}  // namespace quasiloc::estimation
