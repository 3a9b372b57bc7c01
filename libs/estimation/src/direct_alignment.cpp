// Direct alignment: Levenberg-Marquardt on the distance-transform residuals of map edges, coarse to fine,
// and NMI between camera intensity and map reflectivity (a measure).
#include <mrpt/system/CTicTac.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <quasiloc/estimation/direct_alignment.h>
#include <quasiloc/estimation/pose_parametrization.h>

#include "direct_alignment_detail.h"
#include "parallel_points.h"

namespace quasiloc::estimation
{
namespace
{
using detail::bilinear;
using detail::projectToLevel;
inline double huberCost(double r, double k) { return std::abs(r) <= k ? 0.5 * r * r : k * (std::abs(r) - 0.5 * k); }
inline double huberWeight(double r, double k) { return std::abs(r) <= k ? 1.0 : k / std::abs(r); }

struct CostPart
{
    double cost = 0;
    size_t inliers = 0;
    CostPart& operator+=(const CostPart& o)
    {
        cost += o.cost, inliers += o.inliers;
        return *this;
    }
};

struct NormalPart
{
    Matrix6d H = Matrix6d::Zero();
    Vector6d b = Vector6d::Zero();
    NormalPart& operator+=(const NormalPart& o)
    {
        H += o.H, b += o.b;
        return *this;
    }
};

double levelCost(const DirectAlignmentOptions& o, const CameraEdgeLevel& L, const core::CameraModel& camera,
                 const DirectAlignmentModel& model, const Eigen::Isometry3d& T_world_cam, double* inlier_ratio)
{
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    const double trunc_cost = huberCost(o.truncation_px, o.huber_px);
    const CostPart sum = detail::sumInStripes(model.edge_points_world.size(), CostPart{}, [&](size_t begin, size_t end, CostPart& part) {
        for (size_t i = begin; i < end; ++i)
        {
            Eigen::Vector3d p_cam;
            Eigen::Vector2d u;
            if (!projectToLevel(camera, L, T_cam_world, model.edge_points_world[i], p_cam, u, nullptr))
            {
                part.cost += trunc_cost;
                continue;
            }
            const double r = std::min<double>(bilinear(L.distance[model.edge_bin[i]], float(u.x()), float(u.y())),
                                              o.truncation_px);
            part.cost += huberCost(r, o.huber_px);
            part.inliers += r < o.huber_px;
        }
    });
    const size_t n = std::max<size_t>(1, model.edge_points_world.size());
    if (inlier_ratio) *inlier_ratio = double(sum.inliers) / double(n);
    return sum.cost / double(n);
}

/** Gauss-Newton normal equations of the Huber-weighted edge residuals at one level. Points at the
 *  truncation (flat field) or outside the image carry no gradient and are left out. */
void normalEquations(const DirectAlignmentOptions& o, const CameraEdgeLevel& L, const core::CameraModel& camera,
                     const DirectAlignmentModel& model, const Eigen::Isometry3d& T_world_cam, Matrix6d& H, Vector6d& b)
{
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    const double flat = o.truncation_px - 1e-3;
    const NormalPart sum = detail::sumInStripes(model.edge_points_world.size(), NormalPart{}, [&](size_t begin, size_t end, NormalPart& part) {
        for (size_t i = begin; i < end; ++i)
        {
            Eigen::Vector3d p_cam;
            Eigen::Vector2d u;
            Eigen::Matrix<double, 2, 3> J_u_p;
            if (!projectToLevel(camera, L, T_cam_world, model.edge_points_world[i], p_cam, u, &J_u_p)) continue;
            const float x = float(u.x()), y = float(u.y());
            const size_t bin = model.edge_bin[i];
            const double r = bilinear(L.distance[bin], x, y);
            if (r >= flat) continue;
            const cv::Mat& D = L.distance[bin];
            const Eigen::RowVector2d g(0.5 * (bilinear(D, x + 1, y) - bilinear(D, x - 1, y)),
                                       0.5 * (bilinear(D, x, y + 1) - bilinear(D, x, y - 1)));
            // p_cam = R^T (P - t) with the right perturbation: d p_cam / d delta = [hat(p_cam), -I].
            const Eigen::Matrix<double, 1, 6> J = g * J_u_p * pointInBodyJacobian(p_cam);
            const double w = huberWeight(r, o.huber_px);
            part.H.noalias() += w * J.transpose() * J;
            part.b.noalias() += w * r * J.transpose();
        }
    });
    const double n = double(std::max<size_t>(1, model.edge_points_world.size()));
    H = sum.H / n, b = sum.b / n;  // levelCost is a mean
}

/** The prior's cost weight * 0.5 |delta / sigma|^2 with delta = T (-) T_prior, and its Gauss-Newton terms
 *  (d delta / d perturbation ~ I near the prior). */
double priorCost(const DirectPrior* prior, const Eigen::Isometry3d& T, Matrix6d* H, Vector6d* b)
{
    if (!prior) return 0;
    const Vector6d d = boxMinus(T, prior->T_world_cam);
    const Vector6d info = prior->weight * poseInformationDiagonal(prior->sigma_rad, prior->sigma_m);
    if (H) H->diagonal() += info;
    if (b) *b += info.cwiseProduct(d);
    return 0.5 * d.dot(info.cwiseProduct(d));
}

/** Levenberg-Marquardt at one level. Returns the iterations taken. */
int alignLevel(const DirectAlignmentOptions& o, const CameraEdgeLevel& L, const core::CameraModel& camera,
               const DirectAlignmentModel& model, const DirectPrior* prior, Eigen::Isometry3d& T_world_cam, bool& any_step)
{
    double cost = levelCost(o, L, camera, model, T_world_cam, nullptr) + priorCost(prior, T_world_cam, nullptr, nullptr);
    double lambda = 1e-3;
    int it = 0;
    for (; it < o.iterations_per_level; ++it)
    {
        Matrix6d H;
        Vector6d b;
        normalEquations(o, L, camera, model, T_world_cam, H, b);
        priorCost(prior, T_world_cam, &H, &b);
        if (H.trace() <= 0) break;
        bool improved = false;
        for (int tries = 0; tries < 6 && !improved; ++tries)
        {
            Matrix6d A = H;
            A.diagonal() += lambda * H.diagonal() + Vector6d::Constant(1e-9 * H.trace());
            const Eigen::LDLT<Matrix6d> ldlt(A);
            if (ldlt.info() != Eigen::Success) break;
            const Vector6d delta = -ldlt.solve(b);
            const Eigen::Isometry3d T_new = boxPlus(T_world_cam, delta);
            const double c = levelCost(o, L, camera, model, T_new, nullptr) + priorCost(prior, T_new, nullptr, nullptr);
            if (c < cost)
            {
                T_world_cam = T_new;
                const bool converged = cost - c < 1e-6 * cost || delta.norm() < 1e-7;
                cost = c;
                lambda = std::max(1e-7, lambda / 3);
                improved = any_step = true;
                if (converged) return it + 1;
            }
            else
                lambda *= 4;
        }
        if (!improved) break;
    }
    return it;
}
}  // namespace

double edgeCost(const DirectAlignmentOptions& options, const CameraEdgeField& field, int level,
                const core::CameraModel& camera, const DirectAlignmentModel& model,
                const Eigen::Isometry3d& T_world_cam, double* inlier_ratio)
{
    return levelCost(options, field.levels.at(size_t(level)), camera, model, T_world_cam,
                     inlier_ratio);
}

double normalizedMutualInformation(const DirectAlignmentOptions& o, const CameraEdgeField& field,
                                   const core::CameraModel& camera, const NmiSamples& samples,
                                   const Eigen::Isometry3d& T_world_cam)
{
    const int B = o.nmi_bins;
    std::vector<double> joint(size_t(B) * size_t(B), 0.0);
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    size_t n = 0;
    for (size_t i = 0; i < samples.points_world.size(); ++i)
    {
        const Eigen::Vector3d p_cam = T_cam_world * samples.points_world[i];
        Eigen::Vector2d u;
        if (!camera.project(p_cam, u, nullptr, 1e-3)) continue;
        if (u.x() < 0 || u.y() < 0 || u.x() > field.gray.cols - 1 || u.y() > field.gray.rows - 1) continue;
        const int a = std::min(B - 1, int(field.gray.at<uint8_t>(int(u.y() + 0.5), int(u.x() + 0.5)) * B / 256));
        const int c = std::min(B - 1, int(samples.reflectivity[i] * float(B)));
        joint[size_t(a) * size_t(B) + size_t(c)] += 1;
        ++n;
    }
    if (n < 50) return 1.0;
    std::vector<double> pa(size_t(B), 0.0), pb(size_t(B), 0.0);
    double h_joint = 0;
    for (int a = 0; a < B; ++a)
        for (int c = 0; c < B; ++c)
        {
            const double p = joint[size_t(a) * size_t(B) + size_t(c)] / double(n);
            pa[size_t(a)] += p, pb[size_t(c)] += p;
            if (p > 0) h_joint -= p * std::log(p);
        }
    double h_a = 0, h_b = 0;
    for (int k = 0; k < B; ++k)
    {
        if (pa[size_t(k)] > 0) h_a -= pa[size_t(k)] * std::log(pa[size_t(k)]);
        if (pb[size_t(k)] > 0) h_b -= pb[size_t(k)] * std::log(pb[size_t(k)]);
    }
    return h_joint > 0 ? (h_a + h_b) / h_joint : 1.0;
}

bool alignDirect(const DirectAlignmentOptions& o, const CameraEdgeField& field, const core::CameraModel& camera,
                 const DirectAlignmentModel& model, Eigen::Isometry3d& T_world_cam, DirectAlignmentStats* stats,
                 const DirectPrior* prior)
{
    mrpt::system::CTicTac tic;
    DirectAlignmentStats st;
    st.edge_points = int(model.edge_points_world.size());
    if (field.levels.empty() || model.edge_points_world.size() < 20)
    {
        if (stats) *stats = st;
        return false;
    }
    st.initial_edge_cost = edgeCost(o, field, 0, camera, model, T_world_cam);
    bool any_step = false;
    const int coarsest = int(field.levels.size()) - 1;
    for (int l = coarsest; l >= 0; --l)
        st.iterations += alignLevel(o, field.levels[size_t(l)], camera, model, prior, T_world_cam, any_step);
    st.final_edge_cost = edgeCost(o, field, 0, camera, model, T_world_cam, &st.final_inlier_ratio);
    Vector6d gradient;
    normalEquations(o, field.levels[0], camera, model, T_world_cam, st.hessian, gradient);
    st.ms = tic.Tac() * 1e3;
    if (stats) *stats = st;
    return any_step;
}

}  // namespace quasiloc::estimation
