#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/sim/trajectory_spline.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "spline_so3.h"

namespace quasiloc::sim
{
using namespace spline;

namespace
{
/** A distinct sample of the body trajectory, time relative to the first one. */
struct BodySample
{
    double s = 0;
    Eigen::Vector3d p;
    Eigen::Matrix3d R;
};

constexpr double kTimeToleranceS = 1e-6;
// Second-difference penalties on the control points (positions; SO(3) increments d[i+1] - d[i]): they keep
// the system regular where samples are sparse, e.g. the last control point when the last sample falls just
// after a knot (its basis weight is then ~u^3/6). With 1e-6 their bias on the fit is far below a micrometre.
constexpr double kPositionSmoothing = 1e-6;
constexpr double kRotationSmoothing = 1e-6;
// Levenberg damping of the SO(3) Gauss-Newton steps.
constexpr double kRotationDamping = 1e-9;
constexpr int kMaxRotationIterations = 30;
}  // namespace

struct TrajectorySpline::Impl
{
    double t0 = 0, span = 0, dt = 0.1;
    int num_segments = 1;
    std::vector<Eigen::Vector3d> P;  ///< position control points
    std::vector<Eigen::Matrix3d> R;  ///< orientation control points
    std::vector<Eigen::Vector3d> d;  ///< d[i] = Log(R[i-1]^T R[i]), d[0] unused
    SplineFitStats stats;

    /** Segment index and local parameter u for relative time s (clamped to the valid segments). */
    void locate(double s, int& k, double& u) const
    {
        const double x = s / dt;
        k = std::clamp(static_cast<int>(std::floor(x)), 0, num_segments - 1);
        u = x - k;
    }
    void updateIncrements()
    {
        d.assign(R.size(), Eigen::Vector3d::Zero());
        for (size_t i = 1; i < R.size(); ++i) d[i] = logSO3(R[i - 1].transpose() * R[i]);
    }
    Eigen::Matrix3d rotation(int k, const CubicBasis& basis) const
    {
        const auto lambda = basis.cumulative();
        Eigen::Matrix3d Rt = R[k];
        for (int j = 1; j <= 3; ++j) Rt = Rt * expSO3(lambda[j] * d[k + j]);
        return Rt;
    }
    Eigen::Vector3d position(int k, const CubicBasis& basis) const
    {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        for (int j = 0; j < 4; ++j) p += basis.b[j] * P[k + j];
        return p;
    }
    /** Residual Log(Rm^T R(t)) and its Jacobian w.r.t. right perturbations R_i Exp(delta_i), i = k..k+3. */
    Eigen::Vector3d rotationResidual(int k, const CubicBasis& basis, const Eigen::Matrix3d& Rm,
                                     Eigen::Matrix<double, 3, 12>& J) const;

    /** Adds the SO(3) second-difference penalty to the normal equations of the rotation fit. */
    void addRotationSmoothing(std::vector<Eigen::Triplet<double>>& triplets, Eigen::VectorXd& g) const;
    void initRotations(const std::vector<BodySample>& samples);
    void fitPositions(const std::vector<BodySample>& samples);
    void fitRotations(const std::vector<BodySample>& samples);
    void computeStats(const std::vector<BodySample>& samples);
};

Eigen::Vector3d TrajectorySpline::Impl::rotationResidual(int k, const CubicBasis& basis, const Eigen::Matrix3d& Rm,
                                                         Eigen::Matrix<double, 3, 12>& J) const
{
    const auto lambda = basis.cumulative();
    std::array<Eigen::Matrix3d, 4> A;  // A[j] = Exp(lambda_j d_j), j = 1..3
    for (int j = 1; j <= 3; ++j) A[j] = expSO3(lambda[j] * d[k + j]);
    std::array<Eigen::Matrix3d, 4> post;  // post[j] = A[j+1] ... A[3]
    post[3].setIdentity();
    for (int j = 2; j >= 0; --j) post[j] = A[j + 1] * post[j + 1];
    const Eigen::Matrix3d Rt = R[k] * post[0];
    const Eigen::Vector3d r = logSO3(Rm.transpose() * Rt);

    // Perturbing R_i moves d_j = Log(R_{k+j-1}^T R_{k+j}) by Jr^-1(d_j) (delta_{k+j} - Exp(d_j)^T delta_{k+j-1})
    // and A_j by Jr(lambda_j d_j) lambda_j times that; each factor's change reaches R(t) through post[j].
    std::array<Eigen::Matrix3d, 4> M;
    std::array<Eigen::Matrix3d, 4> Dt;  // Exp(d_j)^T
    for (int j = 1; j <= 3; ++j)
    {
        M[j] = post[j].transpose() * rightJacobian(lambda[j] * d[k + j]) * lambda[j] * rightJacobianInverse(d[k + j]);
        Dt[j] = (R[k + j - 1].transpose() * R[k + j]).transpose();
    }
    const Eigen::Matrix3d Jr_inv_r = rightJacobianInverse(r);
    J.block<3, 3>(0, 0) = Jr_inv_r * (post[0].transpose() - M[1] * Dt[1]);
    J.block<3, 3>(0, 3) = Jr_inv_r * (M[1] - M[2] * Dt[2]);
    J.block<3, 3>(0, 6) = Jr_inv_r * (M[2] - M[3] * Dt[3]);
    J.block<3, 3>(0, 9) = Jr_inv_r * M[3];
    return r;
}

void TrajectorySpline::Impl::fitPositions(const std::vector<BodySample>& samples)
{
    const int n = static_cast<int>(P.size());
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(samples.size() * 16 + static_cast<size_t>(n) * 9);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
    for (const auto& smp : samples)
    {
        int k;
        double u;
        locate(smp.s, k, u);
        const CubicBasis basis(u);
        for (int a = 0; a < 4; ++a)
        {
            rhs.row(k + a) += basis.b[a] * smp.p.transpose();
            for (int b = 0; b < 4; ++b) triplets.emplace_back(k + a, k + b, basis.b[a] * basis.b[b]);
        }
    }
    const double coeffs[3] = {1, -2, 1};
    for (int i = 1; i + 1 < n; ++i)
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                triplets.emplace_back(i - 1 + a, i - 1 + b, kPositionSmoothing * coeffs[a] * coeffs[b]);
    Eigen::SparseMatrix<double> H(n, n);
    H.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
    if (solver.info() != Eigen::Success)
        throw core::InputError("trajectory samples", "position spline fit is singular");
    const Eigen::MatrixXd X = solver.solve(rhs);
    for (int i = 0; i < n; ++i) P[i] = X.row(i).transpose();
}

void TrajectorySpline::Impl::addRotationSmoothing(std::vector<Eigen::Triplet<double>>& triplets,
                                                  Eigen::VectorXd& g) const
{
    // d_i = Log(R_{i-1}^T R_i) moves by dd_prev(i) delta_{i-1} + dd_next(i) delta_i.
    const int n = static_cast<int>(R.size());
    std::vector<Eigen::Matrix3d> dd_prev(n), dd_next(n);
    for (int i = 1; i < n; ++i)
    {
        dd_next[i] = rightJacobianInverse(d[i]);
        dd_prev[i] = -dd_next[i] * (R[i - 1].transpose() * R[i]).transpose();
    }
    Eigen::Matrix<double, 3, 9> J;
    for (int i = 1; i + 1 < n; ++i)
    {
        const Eigen::Vector3d r = d[i + 1] - d[i];
        J << -dd_prev[i], dd_prev[i + 1] - dd_next[i], dd_next[i + 1];
        g.segment<9>(3 * (i - 1)) += kRotationSmoothing * J.transpose() * r;
        const Eigen::Matrix<double, 9, 9> JtJ = kRotationSmoothing * J.transpose() * J;
        for (int a = 0; a < 9; ++a)
            for (int b = 0; b < 9; ++b) triplets.emplace_back(3 * (i - 1) + a, 3 * (i - 1) + b, JtJ(a, b));
    }
}

void TrajectorySpline::Impl::fitRotations(const std::vector<BodySample>& samples)
{
    const int n = static_cast<int>(R.size());
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::Matrix<double, 3, 12> J;
    for (int iter = 1; iter <= kMaxRotationIterations; ++iter)
    {
        stats.rotation_iterations = iter;
        updateIncrements();
        triplets.clear();
        triplets.reserve(samples.size() * 144 + static_cast<size_t>(n) * 84);
        Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * n);
        for (const auto& smp : samples)
        {
            int k;
            double u;
            locate(smp.s, k, u);
            const Eigen::Vector3d r = rotationResidual(k, CubicBasis(u), smp.R, J);
            g.segment<12>(3 * k) += J.transpose() * r;
            const Eigen::Matrix<double, 12, 12> JtJ = J.transpose() * J;
            for (int a = 0; a < 12; ++a)
                for (int b = 0; b < 12; ++b) triplets.emplace_back(3 * k + a, 3 * k + b, JtJ(a, b));
        }
        addRotationSmoothing(triplets, g);
        for (int i = 0; i < 3 * n; ++i) triplets.emplace_back(i, i, kRotationDamping);
        Eigen::SparseMatrix<double> H(3 * n, 3 * n);
        H.setFromTriplets(triplets.begin(), triplets.end());
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
        if (solver.info() != Eigen::Success)
            throw core::InputError("trajectory samples", "orientation spline fit is singular");
        const Eigen::VectorXd delta = -solver.solve(g);
        for (int i = 0; i < n; ++i) R[i] = orthonormalize(R[i] * expSO3(delta.segment<3>(3 * i)));
        if (delta.lpNorm<Eigen::Infinity>() < 1e-10) break;
    }
    updateIncrements();
}

void TrajectorySpline::Impl::computeStats(const std::vector<BodySample>& samples)
{
    double sum_p2 = 0, sum_r2 = 0;
    for (const auto& smp : samples)
    {
        int k;
        double u;
        locate(smp.s, k, u);
        const CubicBasis basis(u);
        const double ep = (position(k, basis) - smp.p).norm();
        const double er = logSO3(smp.R.transpose() * rotation(k, basis)).norm();
        sum_p2 += ep * ep;
        sum_r2 += er * er;
        stats.max_position_m = std::max(stats.max_position_m, ep);
        stats.max_rotation_rad = std::max(stats.max_rotation_rad, er);
    }
    stats.rms_position_m = std::sqrt(sum_p2 / samples.size());
    stats.rms_rotation_rad = std::sqrt(sum_r2 / samples.size());
}

TrajectorySpline TrajectorySpline::fitCameraTrajectory(const core::Trajectory& T_world_cam0,
                                                       const mrpt::poses::CPose3D& T_body_cam0,
                                                       const TrajectorySplineOptions& options)
{
    const Eigen::Isometry3d T_cam0_body = core::toIsometry(T_body_cam0).inverse();
    core::Trajectory body = T_world_cam0;
    for (auto& tp : body.poses) tp.pose = core::fromIsometry(core::toIsometry(tp.pose) * T_cam0_body);
    return fitBodyTrajectory(body, options);
}

namespace
{
/** Distinct, sorted samples with times relative to the first (absolute time in t0). Runs of equal
 *  timestamps (EuRoC rows before and after ground truth) keep their LAST row: in V1_02_medium the first row
 *  of the leading run is an outlier 3 cm away from the rest of the run. */
std::vector<BodySample> distinctSamples(const core::Trajectory& traj, double& t0, size_t& num_dropped)
{
    const std::string input = "trajectory to fit (" + std::to_string(traj.poses.size()) + " poses)";
    std::vector<BodySample> samples;
    const auto& poses = traj.poses;
    num_dropped = 0;
    for (size_t i = 0; i < poses.size(); ++i)
    {
        core::require(std::isfinite(poses[i].t), input, "timestamp of pose " + std::to_string(i) + " is not finite");
        core::checkFinite(poses[i].pose, input + ", pose " + std::to_string(i));
        if (i + 1 < poses.size())
        {
            core::require(poses[i + 1].t >= poses[i].t, input,
                          "timestamps are not sorted (pose " + std::to_string(i + 1) + ")");
            if (poses[i + 1].t == poses[i].t)
            {
                ++num_dropped;
                continue;
            }
        }
        if (samples.empty()) t0 = poses[i].t;
        const Eigen::Isometry3d T = core::toIsometry(poses[i].pose);
        samples.push_back({poses[i].t - t0, T.translation(), orthonormalize(T.linear())});
    }
    core::require(samples.size() >= 4, input,
                  "fewer than 4 distinct timestamps (" + std::to_string(samples.size()) + ")");
    return samples;
}
}  // namespace

void TrajectorySpline::Impl::initRotations(const std::vector<BodySample>& samples)
{
    // Control point i acts around t0 + (i - 1) dt: start the SO(3) fit from the sampled orientation there.
    size_t j = 0;
    for (size_t i = 0; i < R.size(); ++i)
    {
        const double s = std::clamp((static_cast<double>(i) - 1) * dt, 0.0, span);
        while (j + 2 < samples.size() && samples[j + 1].s <= s) ++j;
        const double f = std::clamp((s - samples[j].s) / (samples[j + 1].s - samples[j].s), 0.0, 1.0);
        const Eigen::Quaterniond qa(samples[j].R), qb(samples[j + 1].R);
        R[i] = qa.slerp(f, qb).toRotationMatrix();
    }
}

TrajectorySpline TrajectorySpline::fitBodyTrajectory(const core::Trajectory& T_world_body,
                                                     const TrajectorySplineOptions& options)
{
    core::require(std::isfinite(options.knot_spacing_s) && options.knot_spacing_s > 0,
                  "TrajectorySplineOptions.knot_spacing_s", "must be > 0");
    auto impl = std::make_shared<Impl>();
    impl->dt = options.knot_spacing_s;
    const auto samples = distinctSamples(T_world_body, impl->t0, impl->stats.num_duplicates_dropped);
    impl->span = samples.back().s;
    impl->num_segments = std::max(1, static_cast<int>(std::ceil(impl->span / impl->dt - 1e-9)));
    const size_t n = static_cast<size_t>(impl->num_segments) + 3;
    impl->P.assign(n, Eigen::Vector3d::Zero());
    impl->R.resize(n);
    impl->initRotations(samples);
    impl->fitPositions(samples);
    impl->fitRotations(samples);
    impl->stats.num_samples = samples.size();
    impl->stats.num_control_points = n;
    impl->computeStats(samples);

    TrajectorySpline spline;
    spline.impl_ = impl;
    return spline;
}

double TrajectorySpline::tStart() const { return impl_->t0; }
double TrajectorySpline::tEnd() const { return impl_->t0 + impl_->span; }
double TrajectorySpline::knotSpacing() const { return impl_->dt; }
const SplineFitStats& TrajectorySpline::fitStats() const { return impl_->stats; }

BodyState TrajectorySpline::evaluate(double t) const
{
    const Impl& m = *impl_;
    const double s = t - m.t0;
    if (!(s >= -kTimeToleranceS && s <= m.span + kTimeToleranceS))
        throw std::out_of_range("TrajectorySpline::evaluate: t = " + std::to_string(t) + " outside [" +
                                std::to_string(tStart()) + ", " + std::to_string(tEnd()) + "]");
    int k;
    double u;
    m.locate(s, k, u);
    const CubicBasis basis(u);
    BodyState st;
    st.p_world = m.position(k, basis);
    for (int j = 0; j < 4; ++j)
    {
        st.v_world += basis.db[j] * m.P[k + j];
        st.a_world += basis.ddb[j] * m.P[k + j];
    }
    st.v_world /= m.dt;
    st.a_world /= m.dt * m.dt;

    // Body rate and its derivative by the recursion of Sommer et al.: w_{j+1} = A_j^T w_j + dlambda_j d_j.
    const auto lambda = basis.cumulative(), dlambda = basis.cumulativeD(), ddlambda = basis.cumulativeDD();
    Eigen::Matrix3d Rt = m.R[k];
    Eigen::Vector3d w = Eigen::Vector3d::Zero(), dw = Eigen::Vector3d::Zero();
    for (int j = 1; j <= 3; ++j)
    {
        const Eigen::Vector3d& dj = m.d[k + j];
        const Eigen::Matrix3d A = expSO3(lambda[j] * dj);
        Rt = Rt * A;
        w = A.transpose() * w + dlambda[j] * dj;
        dw = A.transpose() * dw + ddlambda[j] * dj + dlambda[j] * w.cross(dj);
    }
    st.R_world_body = Rt;
    st.omega_body = w / m.dt;
    st.alpha_body = dw / (m.dt * m.dt);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = orthonormalize(Rt);
    T.translation() = st.p_world;
    st.T_world_body = core::fromIsometry(T);
    return st;
}

}  // namespace quasiloc::sim
