// GlobalInitializer: two geometric localizations and the IMU between them (global_initialization.h).
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/estimation/pose_parametrization.h>
#include <quasiloc/tracking/global_initialization.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace quasiloc::tracking
{
namespace
{
std::string bracketed(const std::string& note) { return note.empty() ? "" : " [" + note + "]"; }

double angleBetweenDeg(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b)
{
    return Eigen::AngleAxisd(R_a.transpose() * R_b).angle() * 180.0 / M_PI;
}
}  // namespace

GlobalInitializer::GlobalInitializer(const reloc::GeometricLocalizer& localizer, const Eigen::Isometry3d& T_body_cam,
                                     const estimation::ImuNoise& imu_noise, const GlobalInitOptions& options)
    : localizer_(localizer),
      T_body_cam_(T_body_cam),
      imu_noise_(imu_noise),
      options_(options),
      static_(imu_noise.gyro_noise_density, options.standstill)
{}

ImuBiasPrior GlobalInitializer::biases() const
{
    return options_.static_initialization ? withStaticEstimate(options_.bias_prior, static_.estimate())
                                          : options_.bias_prior;
}

std::optional<reloc::SearchSphere> GlobalInitializer::searchSphere(
    double t, const std::optional<OdometryPrediction>& odometry) const
{
    const bool heading = heading_ && t <= heading_->t_until;
    if (!prior_ && !heading && !odometry) return std::nullopt;
    reloc::SearchSphere sphere{Eigen::Vector3d::Zero(), std::numeric_limits<double>::infinity()};
    if (odometry)
        sphere = {odometry->position_world, kOdometrySphereUncertainties * odometry->uncertainty_m};
    else if (prior_)
        sphere = {prior_->position_world, prior_->radius_m + prior_->speed_m_s * std::max(0.0, t - prior_->t_known)};
    if (heading)
    {
        sphere.R_world_cam = R_world_body_predicted_ * T_body_cam_.linear();
        sphere.heading_bound_deg = headingBoundDeg(*heading_, biases().gyro_sigma, t);
    }
    return sphere;
}

reloc::GeometricLocalization GlobalInitializer::localize(const dataset::StereoFrame& frame,
                                                         const std::optional<reloc::SearchSphere>& near,
                                                         std::string& note, AmbiguousFix& ambiguous,
                                                         std::vector<Eigen::Vector3f>& points_cam)
{
    std::vector<Eigen::Vector3d> acc;
    if (const auto still = options_.static_initialization ? static_.estimate() : std::nullopt)
        acc.push_back(still->mean_specific_force);  // the whole standing span: less vibration than the last 0.2 s
    else
        for (const auto& s : recent_imu_) acc.push_back(s.acc);
    const Eigen::Vector3d up_cam = reloc::upInCamera(acc, T_body_cam_.linear().transpose());
    // One stereo matching per attempt: the search and the remembered places' rescoring use the same points.
    reloc::GeometricLocalization r =
        localizer_.localize(frame.left, frame.right, up_cam, near ? &*near : nullptr, &points_cam);
    ambiguous = {};
    if (!r.ambiguous) return r;
    ambiguous.poses = {r.T_world_cam};
    ambiguous.poses.insert(ambiguous.poses.end(), r.alternatives.begin(), r.alternatives.end());
    if (!appearance_) return r;
    const std::vector<double> score = appearance_(frame, ambiguous.poses);
    size_t best = 0;
    for (size_t i = 1; i < score.size(); ++i)
        if (score[i] > score[best]) best = i;
    ambiguous.best_by_appearance = best;
    double next = 0;
    for (size_t i = 0; i < score.size(); ++i)
        if (i != best) next = std::max(next, score[i]);
    std::ostringstream s;
    s.precision(3);
    s << "appearance scores";
    for (double v : score) s << " " << v;
    if (score[best] >= options_.min_appearance_score && score[best] >= options_.appearance_margin * next)
    {
        r.T_world_cam = ambiguous.poses[best];
        r.localized = true;
        r.reason.clear();
        s << ": ambiguity settled (pose " << best << ")";
    }
    else
        s << ": still ambiguous";
    note = s.str();
    return r;
}

bool GlobalInitializer::settleByAnchor(reloc::GeometricLocalization& r, const AmbiguousFix& ambiguous, double t,
                                       std::string& note) const
{
    const std::vector<size_t> closing =
        placesClosingThePair(T_world_anchor_, anchor_->timestamp, ambiguous.poses, t, pendingSamples(), T_body_cam_,
                             imu_noise_, biases(), options_);
    if (closing.size() != 1) return false;
    const size_t pick = closing.front();
    if (ambiguous.best_by_appearance && *ambiguous.best_by_appearance != pick) return false;
    r.T_world_cam = ambiguous.poses[pick];
    r.localized = true;
    r.reason.clear();
    note +=
        (note.empty() ? "" : "; ") + std::string("ambiguity settled by the anchor (pose ") + std::to_string(pick) + ")";
    return true;
}

bool differentPlaces(const Eigen::Isometry3d& T_a, const Eigen::Isometry3d& T_b)
{
    return core::translationDistance(T_a, T_b) > 0.3 || angleBetweenDeg(T_a.linear(), T_b.linear()) > 5;
}

std::optional<size_t> preferredRememberedPlace(const Eigen::Isometry3d& answer, double answer_ratio,
                                               const std::vector<ScoredPlace>& remembered, double min_ratio,
                                               double ambiguity_ratio)
{
    std::optional<size_t> best;
    for (size_t i = 0; i < remembered.size(); ++i)
        if (!best || remembered[i].inlier_ratio > remembered[*best].inlier_ratio) best = i;
    if (!best) return std::nullopt;
    const ScoredPlace& b = remembered[*best];
    if (!differentPlaces(b.T_world_cam, answer) || b.inlier_ratio < min_ratio ||
        answer_ratio >= ambiguity_ratio * b.inlier_ratio)
        return std::nullopt;
    for (size_t i = 0; i < remembered.size(); ++i)
        if (i != *best && differentPlaces(remembered[i].T_world_cam, b.T_world_cam) &&
            remembered[i].inlier_ratio >= ambiguity_ratio * b.inlier_ratio)
            return std::nullopt;  // two remembered places explain the frame nearly as well
    return best;
}

void GlobalInitializer::carryRemembered(const std::vector<dataset::ImuSample>& samples)
{
    const Eigen::Vector3d gyro_bias = biases().gyro_bias;
    std::vector<RememberedPlace> kept;
    for (RememberedPlace& p : remembered_)
    {
        Eigen::Isometry3d T_world_body = p.place.T_world_cam * T_body_cam_.inverse();
        Eigen::Matrix3d R_world_body = T_world_body.linear();
        if (!carryOrientation(R_world_body, p.t_carried, samples, gyro_bias)) continue;  // a rate over a gap: a guess
        T_world_body.linear() = R_world_body;
        p.place.T_world_cam = T_world_body * T_body_cam_;
        kept.push_back(p);
    }
    remembered_ = std::move(kept);
}

void GlobalInitializer::preferRemembered(const std::vector<Eigen::Vector3f>& points, double t,
                                         const std::optional<reloc::SearchSphere>& near,
                                         reloc::GeometricLocalization& r, AmbiguousFix& ambiguous, std::string& note)
{
    if (remembered_.empty()) return;
    std::vector<RememberedPlace> kept;
    for (RememberedPlace& p : remembered_)
    {
        Eigen::Isometry3d T = p.place.T_world_cam;
        localizer_.refine(points, T);
        localizer_.polish(points, T);
        const double ratio = localizer_.inlierRatio(points, T);
        if (ratio < options_.place_min_inlier_ratio) continue;  // the frame does not support it (any more)
        if (near && ((T.translation() - near->centre).norm() > near->radius_m || !near->headingAdmits(T.linear())))
            continue;  // refined out of where this frame is searched
        const bool same = std::any_of(kept.begin(), kept.end(), [&](const RememberedPlace& k) {
            return !differentPlaces(k.place.T_world_cam, T) && k.place.inlier_ratio >= ratio;
        });
        if (same) continue;
        kept.erase(std::remove_if(kept.begin(), kept.end(),
                                  [&](const RememberedPlace& k) { return !differentPlaces(k.place.T_world_cam, T); }),
                   kept.end());
        kept.push_back({{T, ratio, p.place.t}, t});
    }
    remembered_ = std::move(kept);
    std::vector<ScoredPlace> scored;
    for (const RememberedPlace& p : remembered_) scored.push_back(p.place);
    const std::optional<size_t> pick = preferredRememberedPlace(
        r.T_world_cam, r.inlier_ratio, scored, options_.place_min_inlier_ratio, options_.place_ambiguity_ratio);
    if (!pick) return;
    std::ostringstream s;
    s.precision(3);
    s << std::fixed << "a place found at t " << scored[*pick].t << " explains " << 100 * scored[*pick].inlier_ratio
      << " % against the search's " << 100 * r.inlier_ratio << " %: taken";
    r.T_world_cam = scored[*pick].T_world_cam;
    r.inlier_ratio = scored[*pick].inlier_ratio;
    r.localized = true;
    r.ambiguous = false;
    r.reason.clear();
    ambiguous = {};
    note += (note.empty() ? "" : "; ") + s.str();
}

void GlobalInitializer::remember(const reloc::GeometricLocalization& r, double t)
{
    if (options_.remembered_places <= 0 || r.inlier_ratio < options_.place_min_inlier_ratio) return;
    remembered_.erase(
        std::remove_if(remembered_.begin(), remembered_.end(),
                       [&](const RememberedPlace& p) { return !differentPlaces(p.place.T_world_cam, r.T_world_cam); }),
        remembered_.end());
    remembered_.push_back({{r.T_world_cam, r.inlier_ratio, t}, t});
    std::stable_sort(remembered_.begin(), remembered_.end(), [](const RememberedPlace& a, const RememberedPlace& b) {
        return a.place.inlier_ratio > b.place.inlier_ratio;
    });
    if (remembered_.size() > size_t(options_.remembered_places)) remembered_.resize(size_t(options_.remembered_places));
}

std::optional<size_t> settleByOdometry(const std::vector<Eigen::Isometry3d>& places,
                                       const OdometryPrediction& prediction)
{
    std::optional<size_t> near;
    for (size_t i = 0; i < places.size(); ++i)
    {
        const double d = (places[i].translation() - prediction.position_world).norm();
        if (d <= prediction.uncertainty_m)
        {
            if (near) return std::nullopt;  // two places the odometry allows
            near = i;
        }
        else if (d < kOdometryRivalUncertainties * prediction.uncertainty_m)
            return std::nullopt;  // a rival the odometry does not rule out
    }
    return near;
}

bool GlobalInitializer::settleByPrediction(reloc::GeometricLocalization& r, const AmbiguousFix& ambiguous,
                                           const OdometryPrediction& odometry, std::string& note) const
{
    if (ambiguous.poses.empty()) return false;  // not ambiguous
    const std::optional<size_t> pick = settleByOdometry(ambiguous.poses, odometry);
    if (!pick) return false;
    std::ostringstream s;
    s.precision(3);
    if (r.localized && ambiguous.best_by_appearance != pick)
    {  // the image settled it on a place the odometry rules out: neither cue is taken
        r.localized = false;
        r.reason = "ambiguous: the image prefers another place than the odometry";
        s << "the odometry prefers pose " << *pick << ", the image pose " << *ambiguous.best_by_appearance;
    }
    else
    {
        r.T_world_cam = ambiguous.poses[*pick];
        r.localized = true;
        r.reason.clear();
        s << "ambiguity settled by the odometry (pose " << *pick << ", "
          << (r.T_world_cam.translation() - odometry.position_world).norm() << " m from its prediction)";
    }
    note += (note.empty() ? "" : "; ") + s.str();
    return r.localized;
}

void GlobalInitializer::setHeadingPrior(const HeadingPrior& heading)
{
    heading_ = heading;
    R_world_body_predicted_ = heading.R_world_body;
    t_predicted_ = heading.t;
    carryHeading(heading.imu);
}

bool carryOrientation(Eigen::Matrix3d& R_world_body, double& t, const std::vector<dataset::ImuSample>& samples,
                      const Eigen::Vector3d& gyro_bias, double max_gap_s)
{
    for (const dataset::ImuSample& s : samples)
    {
        if (s.t <= t) continue;
        if (s.t - t > max_gap_s) return false;
        R_world_body = R_world_body * estimation::expSO3((s.gyro - gyro_bias) * (s.t - t));
        t = s.t;
    }
    return true;
}

void GlobalInitializer::carryHeading(const std::vector<dataset::ImuSample>& samples)
{
    if (!heading_) return;
    const double t_before = t_predicted_;
    if (carryOrientation(R_world_body_predicted_, t_predicted_, samples, biases().gyro_bias)) return;
    heading_.reset();
    std::ostringstream s;
    s.precision(3);
    s << std::fixed << "heading prior dropped: no gyroscope sample after t " << t_before;
    heading_note_ = s.str();
}

double headingBoundDeg(const HeadingPrior& heading, double gyro_bias_sigma, double t)
{
    const double dt = std::max(0.0, t - heading.t);
    return heading.margin_deg + 3.0 * gyro_bias_sigma * 180.0 / M_PI * dt;
}

Eigen::Vector3d velocityBetweenFixes(const Eigen::Isometry3d& T_world_cam_a, double t_a,
                                     const Eigen::Isometry3d& T_world_cam_b, double t_b,
                                     const std::vector<estimation::ImuMeasurement>& samples,
                                     const Eigen::Isometry3d& T_body_cam, const estimation::ImuNoise& noise,
                                     const ImuBiasPrior& biases, double* rotation_disagreement_deg)
{
    estimation::ImuPreintegration imu(noise, biases.gyro_bias, biases.acc_bias);
    imu.integrateInterval(samples, t_a, t_b);
    const Eigen::Isometry3d T_a = T_world_cam_a * T_body_cam.inverse(), T_b = T_world_cam_b * T_body_cam.inverse();
    const double dt = imu.dt();
    if (rotation_disagreement_deg)
        *rotation_disagreement_deg =
            Eigen::AngleAxisd((T_a.linear() * imu.deltaR()).transpose() * T_b.linear()).angle() * 180.0 / M_PI;
    return (T_b.translation() - T_a.translation() - 0.5 * noise.gravity() * dt * dt - T_a.linear() * imu.deltaP()) / dt;
}

double rotationDisagreementBoundDeg(const GlobalInitOptions& options, double gyro_bias_sigma, double dt_s)
{
    return options.max_disagreement_deg + 3.0 * gyro_bias_sigma * std::abs(dt_s) * 180.0 / M_PI;
}

std::optional<Eigen::Vector3d> pairVelocity(const Eigen::Isometry3d& T_world_cam_a, double t_a,
                                            const Eigen::Isometry3d& T_world_cam_b, double t_b,
                                            const std::vector<estimation::ImuMeasurement>& samples,
                                            const Eigen::Isometry3d& T_body_cam, const estimation::ImuNoise& noise,
                                            const ImuBiasPrior& biases, const GlobalInitOptions& options,
                                            std::string* why)
{
    double disagreement_deg = 0;
    const Eigen::Vector3d v = velocityBetweenFixes(T_world_cam_a, t_a, T_world_cam_b, t_b, samples, T_body_cam, noise,
                                                   biases, &disagreement_deg);
    const double bound_deg = rotationDisagreementBoundDeg(options, biases.gyro_sigma, t_b - t_a);
    std::ostringstream s;
    s.precision(3);
    if (disagreement_deg > bound_deg)
        s << "the two fixes' rotation differs from the bias-corrected gyroscope's by " << disagreement_deg << " deg (> "
          << bound_deg << ": " << options.max_disagreement_deg << " + 3 x " << biases.gyro_sigma
          << " rad/s gyroscope bias sigma [" << biases.source << "])";
    else if (v.norm() > options.max_speed_m_s)
        s << "implied speed " << v.norm() << " m/s (> " << options.max_speed_m_s << ")";
    if (why) *why = s.str();
    if (!s.str().empty()) return std::nullopt;
    return v;
}

std::vector<size_t> placesClosingThePair(const Eigen::Isometry3d& T_world_cam_a, double t_a,
                                         const std::vector<Eigen::Isometry3d>& places_b, double t_b,
                                         const std::vector<estimation::ImuMeasurement>& samples,
                                         const Eigen::Isometry3d& T_body_cam, const estimation::ImuNoise& noise,
                                         const ImuBiasPrior& biases, const GlobalInitOptions& options)
{
    std::vector<size_t> out;
    for (size_t i = 0; i < places_b.size(); ++i)
        if (pairVelocity(T_world_cam_a, t_a, places_b[i], t_b, samples, T_body_cam, noise, biases, options, nullptr))
            out.push_back(i);
    return out;
}

std::vector<estimation::ImuMeasurement> GlobalInitializer::pendingSamples() const
{
    std::vector<estimation::ImuMeasurement> samples;
    for (const auto& f : pending_)
        for (const auto& s : f.imu) samples.push_back({s.t, s.acc, s.gyro});
    return samples;
}

Eigen::Vector3d velocityAtFix(const Eigen::Isometry3d& T_world_cam_fix, const Eigen::Isometry3d& T_body_cam,
                              const Eigen::Isometry3d& T_world_body_track, const Eigen::Vector3d& v_world_track)
{
    const Eigen::Vector3d v_body = T_world_body_track.linear().transpose() * v_world_track;
    return (T_world_cam_fix * T_body_cam.inverse()).linear() * v_body;
}

std::optional<GlobalInitialState> GlobalInitializer::feed(const dataset::StereoFrame& frame, bool localize_it,
                                                          const std::optional<OdometryPrediction>& odometry)
{
    for (const auto& s : frame.imu) recent_imu_.push_back(s);
    static_.add(frame.imu);
    carryHeading(frame.imu);
    carryRemembered(frame.imu);
    while (!recent_imu_.empty() && recent_imu_.front().t < frame.timestamp - options_.gravity_window_s)
        recent_imu_.pop_front();
    if (recent_imu_.empty()) return std::nullopt;  // no gravity direction yet
    if (anchor_)
    {
        pending_.push_back(frame);
        if (frame.timestamp - anchor_->timestamp < options_.velocity_interval_s) return std::nullopt;
    }
    if (!localize_it || waitsForMotion()) return std::nullopt;
    InitAttempt attempt;
    attempt.t = frame.timestamp;
    std::string appearance_note;
    AmbiguousFix ambiguous;
    const std::optional<reloc::SearchSphere> near = searchSphere(frame.timestamp, odometry);
    std::vector<Eigen::Vector3f> points_cam;
    attempt.result = localize(frame, near, appearance_note, ambiguous, points_cam);
    if (near && (prior_ || odometry)) attempt.search_radius_m = near->radius_m;
    attempt.odometry = odometry;
    if (odometry) settleByPrediction(attempt.result, ambiguous, *odometry, appearance_note);
    if (!heading_note_.empty())
    {
        appearance_note += (appearance_note.empty() ? "" : "; ") + heading_note_;
        heading_note_.clear();
    }
    if (near && near->R_world_cam)
    {
        std::ostringstream s;
        s.precision(3);
        s << "headings within " << near->heading_bound_deg << " deg of the gyroscope's";
        if (attempt.result.inlier_ratio > 0)
            s << " (answer " << angleBetweenDeg(attempt.result.T_world_cam.linear(), *near->R_world_cam)
              << " deg from it)";
        appearance_note += (appearance_note.empty() ? "" : "; ") + s.str();
    }
    if (!odometry && options_.remembered_places > 0)
    {  // the odometry's relocalization settles by its prediction instead
        preferRemembered(points_cam, frame.timestamp, near, attempt.result, ambiguous, appearance_note);
        remember(attempt.result, frame.timestamp);
    }
    if (anchor_ && !attempt.result.localized && attempt.result.ambiguous)
        settleByAnchor(attempt.result, ambiguous, frame.timestamp, appearance_note);
    if (anchor_ && attempt.result.localized)
    {
        std::string why;
        if (const auto v =
                pairVelocity(T_world_anchor_, anchor_->timestamp, attempt.result.T_world_cam, frame.timestamp,
                             pendingSamples(), T_body_cam_, imu_noise_, biases(), options_, &why))
        {
            attempt.note = "pair closed" + bracketed(appearance_note);
            attempts_.push_back(attempt);
            GlobalInitialState s;
            s.anchor = *anchor_;
            s.T_world_cam0 = T_world_anchor_;
            s.v_world = v;
            s.biases = biases();
            s.pending = std::move(pending_);
            anchor_.reset();
            pending_.clear();
            return s;
        }
        attempt.note = "pair rejected: " + why;
    }
    else if (anchor_ && frame.timestamp - anchor_->timestamp < 2 * options_.velocity_interval_s)
    {  // the closing fix may come a little later: keep the anchor for another interval
        attempt.note = "not localized (anchor kept): " + attempt.result.reason + bracketed(appearance_note);
        attempts_.push_back(attempt);
        return std::nullopt;
    }
    // Without a closed pair the newest fix (if any) becomes the anchor.
    pending_.clear();
    anchor_.reset();
    if (attempt.result.localized && options_.single_fix)
    {
        attempt.note = "single fix" + bracketed(appearance_note);
        attempts_.push_back(attempt);
        GlobalInitialState s;
        s.anchor = frame;
        s.T_world_cam0 = attempt.result.T_world_cam;
        s.biases = biases();
        return s;
    }
    if (attempt.result.localized)
    {
        anchor_ = frame;
        T_world_anchor_ = attempt.result.T_world_cam;
        attempt.note += attempt.note.empty() ? "anchor" : "; new anchor";
    }
    else if (attempt.note.empty())
        attempt.note = "not localized: " + attempt.result.reason;
    attempt.note += bracketed(appearance_note);
    ambiguous_standing_ = attempt.result.ambiguous && static_.estimate() && !static_.moved();
    if (ambiguous_standing_) attempt.note += "; standing still: the next attempt waits for the platform to move";
    attempts_.push_back(attempt);
    return std::nullopt;
}

}  // namespace quasiloc::tracking
