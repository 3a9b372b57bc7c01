#include <quasiloc/tracking/global_start.h>

#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

namespace quasiloc::tracking
{
GlobalStarter::GlobalStarter(MapContext& context, const core::StereoRig& rig, const InitializationOptions& o,
                             const reloc::GeometricLocalizationOptions& localization,
                             const estimation::MapRefinementOptions& refinement, frontend::Frontend& frontend,
                             const estimation::ImuNoise& imu_noise, std::ostream& console)
    : refiner_(std::make_unique<estimation::MapRefiner>(refinement, context.searchRenderer(), frontend)),
      camera_(rig.left),
      T_body_cam_(core::toIsometry(rig.T_body_left)),
      imu_noise_(imu_noise),
      out_(console)
{
    const auto t0 = std::chrono::steady_clock::now();
    localizer_ = std::make_unique<reloc::GeometricLocalizer>(
        context.map(), rig, localization, context.distanceField(localization),
        context.renderer().sharedVisibilityIndex(), context.name());
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    setup_s_ = ms / 1000;
    init_options_.velocity_interval_s = o.init_velocity_interval_s;
    init_options_.max_disagreement_deg = o.init_max_disagreement_deg;
    init_options_.max_speed_m_s = o.init_max_speed_m_s;
    init_options_.static_initialization = o.static_initialization;
    init_options_.remembered_places = o.init_remembered_places;
    init_options_.place_min_inlier_ratio = localization.min_inlier_ratio;
    init_options_.place_ambiguity_ratio = localization.ambiguity_ratio;
    std::ostringstream r;
    r << std::fixed << std::setprecision(1) << "# global localization by geometry: distance field and "
      << localizer_->positions() << " candidate positions built in " << ms << " ms\n"
      << "# occasion, t, localized, inlier_ratio, runner_up_inlier_ratio, runner_up_offset_m, runner_up_offset_deg, "
         "query_points, candidates, ms_cloud, ms_search, ms_refine, error_m, error_deg, search_radius_m, note\n";
    record_ = r.str();
    out_ << "global localization by geometry ready (" << localizer_->positions() << " candidate positions, "
         << std::fixed << std::setprecision(0) << ms << " ms)" << std::endl;
}

GlobalStarter::~GlobalStarter() = default;

std::optional<GlobalInitialState> GlobalStarter::find(const std::function<bool(dataset::StereoFrame&)>& next,
                                                      const std::string& label, const std::optional<SearchPrior>& prior)
{
    begin(label, prior);
    dataset::StereoFrame f;
    while (next(f))
        if (auto start = feed(f)) return start;
    record_ += "# " + label + ": the frames ended before a start was found\n";
    init_.reset();
    return std::nullopt;
}

void GlobalStarter::begin(const std::string& label, const std::optional<SearchPrior>& prior, bool single_fix,
                          const std::optional<HeadingPrior>& heading)
{
    GlobalInitOptions options = init_options_;
    options.single_fix = single_fix;
    init_ = std::make_unique<GlobalInitializer>(*localizer_, T_body_cam_, imu_noise_, options);
    if (prior) init_->setSearchPrior(*prior);
    if (heading) init_->setHeadingPrior(*heading);
    init_->setAppearanceScore([this](const dataset::StereoFrame& frame, const std::vector<Eigen::Isometry3d>& poses) {
        refiner_->setImage(frame.left, camera_, false);
        std::vector<double> score;
        for (const Eigen::Isometry3d& T : poses)
        {
            const auto r = refiner_->refine(estimation::RefinementMethod::Direct, T, 0.05, M_PI / 180);
            score.push_back(r.success ? r.direct.final_inlier_ratio : 0.0);
        }
        return score;
    });
    label_ = label;
    reported_ = 0;
    truth_.clear();
}

std::optional<GlobalInitialState> GlobalStarter::feed(const dataset::StereoFrame& f, bool attempt,
                                                      const std::optional<OdometryPrediction>& odometry)
{
    core::require(bool(init_), "GlobalStarter", "feed() without begin()");
    std::ostringstream r;
    r << std::fixed << std::setprecision(3);
    if (f.T_world_cam0) truth_[f.timestamp] = *f.T_world_cam0;
    std::optional<GlobalInitialState> start = init_->feed(f, attempt, odometry);
    for (; reported_ < init_->attempts().size(); ++reported_)
    {
        const InitAttempt& a = init_->attempts()[reported_];
        double e_m = NAN, e_deg = NAN, e_odometry_m = NAN;
        if (auto it = truth_.find(a.t); it != truth_.end())
        {
            const Eigen::Isometry3d G = core::toIsometry(it->second);
            e_m = core::translationDistance(a.result.T_world_cam, G);
            e_deg = core::rotationDistanceRad(a.result.T_world_cam, G) * 180 / M_PI;
            if (a.odometry) e_odometry_m = (a.odometry->position_world - G.translation()).norm();
        }
        const auto& g = a.result;
        r << label_ << ", " << a.t << ", " << g.localized << ", " << g.inlier_ratio << ", " << g.runner_up_inlier_ratio
          << ", " << g.runner_up_offset_m << ", " << g.runner_up_offset_deg << ", " << g.query_points << ", "
          << g.candidates << ", " << g.ms_cloud << ", " << g.ms_search << ", " << g.ms_refine << ", " << e_m << ", "
          << e_deg << ", " << a.search_radius_m << ", " << a.note << "\n";
        std::ostringstream line;
        line << label_ << " t " << std::fixed << std::setprecision(3) << a.t << ": " << a.note << " (inliers "
             << 100 * g.inlier_ratio << " %, ";
        if (!std::isnan(e_m)) line << "error " << 100 * e_m << " cm " << e_deg << " deg, ";  // with ground truth
        line << g.ms_cloud + g.ms_search + g.ms_refine << " ms";
        if (a.odometry)
        {
            line << ", searched within " << a.search_radius_m << " m of the odometry's prediction (uncertainty "
                 << a.odometry->uncertainty_m << " m";
            if (!std::isnan(e_odometry_m)) line << ", its error " << e_odometry_m << " m";
            line << ")";
        }
        else if (a.search_radius_m > 0)
            line << ", searched within " << a.search_radius_m << " m of the last confirmed pose";
        line << ")\n";
        say(line.str());
    }
    if (start)
    {
        r << "# " << label_ << ": start at t " << start->anchor.timestamp << "\n";
        // A pair's start (a single fix has no velocity of its own to report).
        if (start->v_world && start->anchor.T_world_cam0 && !start->pending.empty() &&
            start->pending.front().T_world_cam0)
        {
            const Eigen::Isometry3d G = core::toIsometry(*start->anchor.T_world_cam0);
            const auto& n = start->pending.front();
            const Eigen::Vector3d dp_gt = (core::toIsometry(*n.T_world_cam0) * T_body_cam_.inverse()).translation() -
                                          (G * T_body_cam_.inverse()).translation();
            const double dt = n.timestamp - start->anchor.timestamp;
            std::ostringstream s;
            s << std::fixed << std::setprecision(3) << label_ << " start error "
              << 100 * core::translationDistance(start->T_world_cam0, G) << " cm, "
              << core::rotationDistanceRad(start->T_world_cam0, G) * 180 / M_PI << " deg; velocity "
              << start->v_world->norm() << " m/s, error " << (*start->v_world - dp_gt / dt).norm()
              << " m/s (ground truth by differences over " << dt << " s)";
            r << "# " << s.str() << "\n";
            say(s.str() + "\n");
        }
        init_.reset();
    }
    record_ += r.str();
    return start;
}

void GlobalStarter::say(const std::string& text)
{
    if (defer_console_)
        console_ += text;
    else
        out_ << text << std::flush;
}

std::string GlobalStarter::takeConsole()
{
    std::string out;
    out.swap(console_);
    return out;
}

GlobalStarter::TrackCheck GlobalStarter::checkTrack(const dataset::StereoFrame& frame,
                                                    const Eigen::Isometry3d& T_world_cam0, double refine_below,
                                                    const std::vector<Eigen::Vector3f>& given_points) const
{
    TrackCheck c;
    const std::vector<Eigen::Vector3f> points =
        given_points.empty() ? localizer_->stereoPoints(frame.left, frame.right) : given_points;
    c.explained = localizer_->inlierRatio(points, T_world_cam0);
    if (c.explained >= refine_below) return c;
    Eigen::Isometry3d T = T_world_cam0;
    localizer_->refine(points, T);
    localizer_->polish(points, T);
    c.refined = true;
    c.refined_explained = localizer_->inlierRatio(points, T);
    c.moved_m = core::translationDistance(T, T_world_cam0);
    c.moved_deg = core::rotationDistanceRad(T, T_world_cam0) * 180 / M_PI;
    return c;
}
}  // namespace quasiloc::tracking
