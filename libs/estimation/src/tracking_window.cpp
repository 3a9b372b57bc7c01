#include <ceres/ceres.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <quasiloc/core/error.h>
#include <quasiloc/estimation/map_distance_factor.h>
#include <quasiloc/estimation/direct_factor.h>
#include <quasiloc/estimation/tracking_window.h>

#include "gram_compressed_cost.h"
#include "marginalization.h"

namespace quasiloc::estimation
{
namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

struct StateBlocks
{
    double pose[kPoseSize];
    double sb[kSpeedBiasSize];
    void set(const FrameState& s)
    {
        poseToParams(s.T_map_body, pose);
        Eigen::Map<Eigen::Matrix<double, 9, 1>> m(sb);
        m << s.v_map, s.gyro_bias, s.acc_bias;
    }
    FrameState get(double t) const
    {
        FrameState s;
        s.t = t;
        s.T_map_body = paramsToPose(pose);
        s.v_map = Eigen::Map<const Eigen::Vector3d>(sb);
        s.gyro_bias = Eigen::Map<const Eigen::Vector3d>(sb + 3);
        s.acc_bias = Eigen::Map<const Eigen::Vector3d>(sb + 6);
        return s;
    }
};

/** A structural factor: one cost function per candidate; the nominal one is in the problem. */
struct Structural
{
    std::vector<std::unique_ptr<ceres::CostFunction>> candidates;
    std::vector<double> probability;
    int nominal = 0;
    int residuals = 0;
    std::unique_ptr<ceres::LossFunctionWrapper> loss;
};

ceres::LossFunction* robustLoss(const EstimatorOptions& o, int residuals)
{
    const double a = o.robust_threshold * std::sqrt(static_cast<double>(residuals));
    if (o.robust_loss == RobustLoss::Huber) return new ceres::HuberLoss(a);
    if (o.robust_loss == RobustLoss::Cauchy) return new ceres::CauchyLoss(a);
    return nullptr;
}

/** H = J^T J of a line or plane candidate (whitened, so W_meas is included) at the pose. */
Matrix6d candidateInformation(const ceres::CostFunction* f, const Eigen::Isometry3d& T)
{
    Eigen::VectorXd r;
    Eigen::Matrix<double, -1, 6> J;
    if (auto* l = dynamic_cast<const PointToLineFactor*>(f))
        l->linearize(T, r, &J);
    else
        static_cast<const PointToPlaneFactor*>(f)->linearize(T, r, &J);
    return J.transpose() * J;
}

void checkInput(const WindowInput& in)
{
    core::require(in.stereo != nullptr, "WindowInput.stereo", "no stereo geometry given");
    core::require(in.imu == nullptr || in.has_previous, "WindowInput.imu", "an IMU factor needs a previous frame");
    core::require(in.prior.information.allFinite(), "WindowInput.prior", "information is not finite");
    for (const FrameState* s : {&in.current, &in.previous})
        core::require(s->T_map_body.matrix().allFinite() && s->v_map.allFinite(), "WindowInput state",
                      "pose or velocity is not finite");
    for (const DirectEdgeTerm& d : in.direct_terms)
        core::require(d.field && d.model && d.camera && !d.model->edge_points_world.empty() && d.sigma_px > 0 &&
                          d.effective_points > 0,
                      "WindowInput.direct_terms", "needs a field, a camera, a model with edge points and sigmas > 0");
    for (const MapDistanceTerm& m : in.map_distance_terms)
        core::require(m.field && !m.p_cam.empty() && m.p_cam.size() == m.sigma_m.size() && m.effective_points > 0,
                      "WindowInput.map_distance_terms", "needs a field and one sigma per point (at least one point)");
}

class Window
{
   public:
    Window(const EstimatorOptions& o, const WindowInput& in) : opt_(o), in_(in)
    {
        ceres::Problem::Options po;
        po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
        po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
        po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
        problem_ = std::make_unique<ceres::Problem>(po);
        use_imu_ = o.use_imu && in.imu != nullptr;
        cur_.set(in.current);
        prev_.set(in.previous);
        build();
    }

    void build();
    double medianDepth() const;
    std::vector<double*> landmarkBlocks();
    Matrix6d currentPoseMarginal(bool structural_too);
    Eigen::MatrixXd currentStateMarginal();
    void setWeights(const std::vector<double>& w);
    ceres::Solver::Summary solve();

    const EstimatorOptions& opt_;
    const WindowInput& in_;
    PoseManifold manifold_;
    bool use_imu_ = false;
    StateBlocks prev_, cur_;
    std::vector<Eigen::Vector3d> landmarks_;
    std::vector<std::unique_ptr<ceres::CostFunction>> owned_;
    std::vector<std::unique_ptr<ceres::LossFunction>> owned_losses_;
    std::vector<ceres::ResidualBlockId> base_blocks_, structural_blocks_;
    std::vector<Structural> structural_;
    // Last member: destroyed first, before the cost functions, losses and manifold it points to.
    std::unique_ptr<ceres::Problem> problem_;

   private:
    void add(ceres::CostFunction* f, ceres::LossFunction* loss, std::vector<double*> blocks)
    {
        owned_.emplace_back(f);
        if (loss) owned_losses_.emplace_back(loss);
        base_blocks_.push_back(problem_->AddResidualBlock(f, loss, blocks));
    }
    void addStructural(Structural&& s)
    {
        s.loss = std::make_unique<ceres::LossFunctionWrapper>(robustLoss(opt_, s.residuals), ceres::TAKE_OWNERSHIP);
        structural_blocks_.push_back(
            problem_->AddResidualBlock(s.candidates[s.nominal].get(), s.loss.get(), cur_.pose));
        structural_.push_back(std::move(s));
    }
};

void Window::build()
{
    const CameraGeometry& cam = in_.stereo->left;
    problem_->AddParameterBlock(cur_.pose, kPoseSize, &manifold_);
    if (in_.has_previous) problem_->AddParameterBlock(prev_.pose, kPoseSize, &manifold_);
    double* prior_pose = in_.has_previous ? prev_.pose : cur_.pose;
    if (use_imu_)
    {
        add(new StatePriorFactor(in_.prior), nullptr, {prior_pose, prev_.sb});
        add(new ImuFactor(*in_.imu), nullptr, {prev_.pose, prev_.sb, cur_.pose, cur_.sb});
        add(new BiasRandomWalkFactor(in_.imu->noise(), in_.imu->dt()), nullptr, {prev_.sb, cur_.sb});
    }
    else
    {
        add(new PosePriorFactor(in_.prior.mean.T_map_body, in_.prior.information.topLeftCorner<6, 6>()), nullptr,
            {prior_pose});
    }
    if (in_.has_previous && opt_.use_temporal_landmarks)
    {
        landmarks_.reserve(in_.landmarks.size());
        for (const auto& lm : in_.landmarks)
        {
            landmarks_.push_back(lm.p_map_guess);
            double* X = landmarks_.back().data();
            add(new StereoLandmarkFactor(*in_.stereo, lm.previous.left_px, lm.previous.right_px, lm.sigma_px),
                robustLoss(opt_, 4), {prev_.pose, X});
            add(new StereoLandmarkFactor(*in_.stereo, lm.current.left_px, lm.current.right_px, lm.sigma_px),
                robustLoss(opt_, 4), {cur_.pose, X});
        }
    }
    for (const auto& m : in_.pose_measurements)
        add(new PosePriorFactor(m.T_map_body, m.information), robustLoss(opt_, 6), {cur_.pose});
    for (const auto& d : in_.direct_terms)
    {
        const double n = double(d.model->edge_points_world.size());
        const double sigma = d.sigma_px * std::sqrt(std::max(1.0, n / d.effective_points));
        // The Huber is inside the residual (direct_factor.h), in units of this sigma.
        add(new detail::GramCompressedCost(std::make_unique<DirectEdgeCostFunction>(
                *d.field, 0, *d.camera, *d.model, cam.T_body_cam, sigma, d.truncation_px, d.huber_px)),
            nullptr, {cur_.pose});
    }
    for (const auto& m : in_.map_distance_terms)
    {
        const double scale = std::sqrt(std::max(1.0, double(m.p_cam.size()) / m.effective_points));
        std::vector<double> sigma = m.sigma_m;
        for (double& s : sigma) s *= scale;
        add(new detail::GramCompressedCost(std::make_unique<MapDistanceCostFunction>(
                *m.field, m.p_cam, sigma, cam.T_body_cam, m.truncation_m, m.huber_sigmas)),
            nullptr, {cur_.pose});
    }
    if (opt_.usePoints())
        for (const auto& p : in_.points)
            add(new PointReprojectionFactor(cam, p.px, p.p_map, p.sigma_px), robustLoss(opt_, 2), {cur_.pose});
    if (opt_.useLines())
        for (const auto& l : in_.lines)
        {
            if (l.candidates.empty()) continue;
            Structural s;
            for (const auto& c : l.candidates)
            {
                s.candidates.emplace_back(new PointToLineFactor(cam, l.line_px, c.support_map, l.sigma_px));
                s.probability.push_back(c.probability);
            }
            s.nominal = nominalCandidate(l.candidates);
            s.residuals = static_cast<int>(l.candidates[s.nominal].support_map.size());
            addStructural(std::move(s));
        }
    if (opt_.usePlanes())
        for (const auto& p : in_.planes)
        {
            if (p.candidates.empty()) continue;
            Structural s;
            for (const auto& c : p.candidates)
            {
                s.candidates.emplace_back(new PointToPlaneFactor(cam, p.points_cam, c.n_map, c.d, p.sigma_m));
                s.probability.push_back(c.probability);
            }
            s.nominal = nominalCandidate(p.candidates);
            s.residuals = static_cast<int>(p.points_cam.size());
            addStructural(std::move(s));
        }
}

double Window::medianDepth() const
{
    const Eigen::Isometry3d T_cam_map = camFromMap(paramsToPose(cur_.pose), in_.stereo->left.T_body_cam);
    std::vector<double> depths;
    auto keep = [&](const Eigen::Vector3d& p_map) {
        const double z = (T_cam_map * p_map).z();
        if (z > opt_.min_depth_m) depths.push_back(z);
    };
    if (opt_.usePoints())
        for (const auto& p : in_.points) keep(p.p_map);
    if (depths.empty())  // no map-point match: the structures' depths stand in
    {
        for (const auto& l : in_.lines)
            for (const auto& c : l.candidates)
                for (const auto& p : c.support_map) keep(p);
        for (const auto& pl : in_.planes)
            for (const auto& p : pl.points_cam)
                if (p.z() > opt_.min_depth_m) depths.push_back(p.z());
    }
    return estimation::medianDepth(depths, 1.0);
}

std::vector<double*> Window::landmarkBlocks()
{
    std::vector<double*> out;
    out.reserve(landmarks_.size());
    for (auto& X : landmarks_) out.push_back(X.data());
    return out;
}

Matrix6d Window::currentPoseMarginal(bool structural_too)
{
    std::vector<double*> marg;
    if (in_.has_previous) marg.push_back(prev_.pose);
    if (use_imu_) marg.insert(marg.end(), {prev_.sb, cur_.sb});
    std::vector<ceres::ResidualBlockId> blocks = base_blocks_;
    if (structural_too) blocks.insert(blocks.end(), structural_blocks_.begin(), structural_blocks_.end());
    return detail::marginalInformation(*problem_, marg, landmarkBlocks(), {cur_.pose}, blocks, opt_.marginal_damping);
}

Eigen::MatrixXd Window::currentStateMarginal()
{
    std::vector<double*> marg, keep = {cur_.pose};
    if (in_.has_previous) marg.push_back(prev_.pose);
    if (use_imu_)
    {
        marg.push_back(prev_.sb);
        keep.push_back(cur_.sb);
    }
    std::vector<ceres::ResidualBlockId> blocks = base_blocks_;
    blocks.insert(blocks.end(), structural_blocks_.begin(), structural_blocks_.end());
    return detail::marginalInformation(*problem_, marg, landmarkBlocks(), keep, blocks, opt_.marginal_damping);
}

void Window::setWeights(const std::vector<double>& w)
{
    for (size_t i = 0; i < structural_.size(); ++i)
        structural_[i].loss->Reset(
            new ceres::ScaledLoss(robustLoss(opt_, structural_[i].residuals), w[i], ceres::TAKE_OWNERSHIP),
            ceres::TAKE_OWNERSHIP);
}

ceres::Solver::Summary Window::solve()
{
    ceres::Solver::Options so;
    so.max_num_iterations = opt_.inner_iterations;
    so.linear_solver_type = landmarks_.empty() ? ceres::DENSE_QR : ceres::DENSE_SCHUR;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, problem_.get(), &summary);
    return summary;
}
}  // namespace

bool estimateWindow(const EstimatorOptions& options, const ReweightingOptions& rw, const WindowInput& input,
                    WindowResult& result, mrpt::system::CTimeLogger* timer)
{
    checkInput(input);
    auto t_build = Clock::now();
    Window w(options, input);
    result = WindowResult{};
    result.stats.structural_factors = static_cast<int>(w.structural_.size());
    result.stats.linearize_ms += msSince(t_build);
    bool usable = true;
    for (int round = 0; round < options.outer_iterations; ++round)
    {
        const auto t0 = Clock::now();
        const Eigen::Isometry3d T_before = paramsToPose(w.cur_.pose);
        // The reweighting weighs structural factors only: without any, its inputs (a marginal of the whole
        // window, the median depth) would be computed for nothing.
        if (!w.structural_.empty())
        {
            const Matrix6d H0 = w.currentPoseMarginal(false);
            const double L = w.medianDepth();
            std::vector<StructuralCandidates> cands(w.structural_.size());
            for (size_t i = 0; i < w.structural_.size(); ++i)
            {
                const Structural& s = w.structural_[i];
                for (const auto& f : s.candidates) cands[i].H.push_back(candidateInformation(f.get(), T_before));
                cands[i].probability = s.probability;
                cands[i].nominal = s.nominal;
            }
            result.stats.linearize_ms += msSince(t0);
            const auto t1 = Clock::now();
            computeWeights(rw, H0, L, cands, result.reweighting);
            w.setWeights(result.reweighting.weight);
            result.stats.L = L;
            result.stats.reweight_ms += msSince(t1);
        }
        const auto t2 = Clock::now();
        const ceres::Solver::Summary summary = w.solve();
        result.stats.solve_ms += msSince(t2);
        result.stats.rounds = round + 1;
        result.stats.lm_iterations += static_cast<int>(summary.iterations.size()) - 1;
        result.stats.final_cost = summary.final_cost;
        if (!summary.IsSolutionUsable())
        {
            usable = false;
            break;
        }
        if (boxMinus(paramsToPose(w.cur_.pose), T_before).norm() < 1e-6) break;
    }
    if (timer)
    {
        timer->registerUserMeasure("estimation.linearize", result.stats.linearize_ms * 1e-3);
        timer->registerUserMeasure("estimation.reweight", result.stats.reweight_ms * 1e-3);
        timer->registerUserMeasure("estimation.solve", result.stats.solve_ms * 1e-3);
    }
    if (!usable)
    {
        result.current = input.current;
        result.previous = input.previous;
        return false;
    }
    const auto t3 = Clock::now();
    result.current = w.cur_.get(input.current.t);
    if (!w.use_imu_)  // velocity and biases are not estimated: carry the guess through
    {
        result.current.v_map = input.current.v_map;
        result.current.gyro_bias = input.current.gyro_bias;
        result.current.acc_bias = input.current.acc_bias;
    }
    result.previous = input.has_previous ? w.prev_.get(input.previous.t) : input.previous;
    const Eigen::MatrixXd Hm = w.currentStateMarginal();
    result.marginal.mean = result.current;
    result.marginal.information.setZero();
    result.marginal.information.topLeftCorner(Hm.rows(), Hm.cols()) = Hm;
    result.stats.marginalize_ms = msSince(t3);
    if (timer) timer->registerUserMeasure("estimation.marginalize", result.stats.marginalize_ms * 1e-3);
    return true;
}

}  // namespace quasiloc::estimation
