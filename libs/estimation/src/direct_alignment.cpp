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

/** One pass over the edge points at one level and pose: the mean Huber cost (points outside the image or beyond
 *  the truncation count as truncation_px), the share within huber_px, and, when asked for, the Gauss-Newton
 *  normal equations of the Huber-weighted residuals (points at the truncation or outside carry no gradient). Both
 *  in one pass where both are needed at one pose (a level's start, the final Hessian): the projections are
 *  shared. The LM's trial steps take the cost alone: more than half of them are rejected. */
struct LevelEval
{
    bool has_normal_equations = false;
    double cost = 0;
    size_t inliers = 0;
    double inlier_ratio = 0;  ///< inliers over all the edge points (set once the stripes are summed)
    Matrix6d H = Matrix6d::Zero();
    Vector6d b = Vector6d::Zero();
    LevelEval& operator+=(const LevelEval& o)
    {
        cost += o.cost, inliers += o.inliers;
        H += o.H, b += o.b;
        return *this;
    }
};

LevelEval evaluateLevel(const DirectAlignmentOptions& o, const CameraEdgeLevel& L, const core::CameraModel& camera,
                        const DirectAlignmentModel& model, const Eigen::Isometry3d& T_world_cam, bool normal_equations)
{
    const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
    const double trunc_cost = huberCost(o.truncation_px, o.huber_px);
    const double flat = o.truncation_px - 1e-3;
    LevelEval sum = detail::sumInStripes(
        model.edge_points_world.size(), LevelEval{}, [&](size_t begin, size_t end, LevelEval& part) {
            for (size_t i = begin; i < end; ++i)
            {
                Eigen::Vector3d p_cam;
                Eigen::Vector2d u;
                Eigen::Matrix<double, 2, 3> J_u_p;
                if (!projectToLevel(camera, L, T_cam_world, model.edge_points_world[i], p_cam, u,
                                    normal_equations ? &J_u_p : nullptr))
                {
                    part.cost += trunc_cost;
                    continue;
                }
                const float x = float(u.x()), y = float(u.y());
                const cv::Mat& D = L.distance[model.edge_bin[i]];
                const double r_field = bilinear(D, x, y);
                const double r = std::min<double>(r_field, o.truncation_px);
                part.cost += huberCost(r, o.huber_px);
                part.inliers += r < o.huber_px;
                if (!normal_equations || r_field >= flat) continue;
                const Eigen::RowVector2d g(0.5 * (bilinear(D, x + 1, y) - bilinear(D, x - 1, y)),
                                           0.5 * (bilinear(D, x, y + 1) - bilinear(D, x, y - 1)));
                // p_cam = R^T (P - t) with the right perturbation: d p_cam / d delta = [hat(p_cam), -I].
                const Eigen::Matrix<double, 1, 6> J = g * J_u_p * pointInBodyJacobian(p_cam);
                const double w = huberWeight(r_field, o.huber_px);
                part.H.noalias() += w * J.transpose() * J;
                part.b.noalias() += w * r_field * J.transpose();
            }
        });
    const double n = double(std::max<size_t>(1, model.edge_points_world.size()));
    sum.cost /= n, sum.H /= n, sum.b /= n;  // means
    sum.inlier_ratio = double(sum.inliers) / n;
    sum.has_normal_equations = normal_equations;
    return sum;
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

/** Levenberg-Marquardt at one level. Returns the iterations taken; `last` is the evaluation at the final pose. */
int alignLevel(const DirectAlignmentOptions& o, const CameraEdgeLevel& L, const core::CameraModel& camera,
               const DirectAlignmentModel& model, const DirectPrior* prior, Eigen::Isometry3d& T_world_cam,
               bool& any_step, LevelEval& last)
{
    last = evaluateLevel(o, L, camera, model, T_world_cam, true);
    double cost = last.cost + priorCost(prior, T_world_cam, nullptr, nullptr);
    double lambda = 1e-3;
    int it = 0;
    for (; it < o.iterations_per_level; ++it)
    {
        if (!last.has_normal_equations) last = evaluateLevel(o, L, camera, model, T_world_cam, true);
        Matrix6d H = last.H;
        Vector6d b = last.b;
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
            LevelEval e = evaluateLevel(o, L, camera, model, T_new, false);
            const double c = e.cost + priorCost(prior, T_new, nullptr, nullptr);
            if (c < cost)
            {
                T_world_cam = T_new;
                last = e;
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
    const LevelEval e = evaluateLevel(options, field.levels.at(size_t(level)), camera, model, T_world_cam, false);
    if (inlier_ratio) *inlier_ratio = e.inlier_ratio;
    return e.cost;
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
    LevelEval last;
    for (int l = coarsest; l >= 0; --l)
        st.iterations += alignLevel(o, field.levels[size_t(l)], camera, model, prior, T_world_cam, any_step, last);
    // The finest level's last evaluation is at the final pose.
    st.final_edge_cost = last.cost;
    st.final_inlier_ratio = last.inlier_ratio;
    st.hessian =
        last.has_normal_equations ? last.H : evaluateLevel(o, field.levels[0], camera, model, T_world_cam, true).H;
    st.ms = tic.Tac() * 1e3;
    if (stats) *stats = st;
    return any_step;
}

}  // namespace quasiloc::estimation
