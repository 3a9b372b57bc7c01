// The per-keyframe weight of the map edge term (edge_trust.h).
#include <quasiloc/map/distance_field.h>
#include <quasiloc/tracking/edge_trust.h>

#include <algorithm>
#include <cmath>

namespace quasiloc::tracking
{
double edgeTrustWeight(double disagreement_sigmas, double scale_sigmas)
{
    if (scale_sigmas <= 0 || !(disagreement_sigmas > 0)) return 1.0;
    const double r = disagreement_sigmas / scale_sigmas;
    return std::exp(-0.5 * r * r);
}

double meanSquaredStereoMapSigmas(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam,
                                  const std::vector<Eigen::Vector3d>& p_cam, const std::vector<double>& sigma_m,
                                  double truncation_m)
{
    if (p_cam.empty()) return NAN;
    double sum = 0;
    for (size_t i = 0; i < p_cam.size(); ++i)
    {
        const double d =
            std::min<double>(truncation_m, std::abs(field.distance((T_world_cam * p_cam[i]).cast<float>())));
        sum += (d / sigma_m[i]) * (d / sigma_m[i]);
    }
    return sum / double(p_cam.size());
}

double edgeStereoDisagreement(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam_predicted,
                              const Eigen::Isometry3d& T_world_cam_edges, const StereoSurface& stereo)
{
    if (stereo.p_cam.size() < 10) return 0;
    const double at_prediction =
        meanSquaredStereoMapSigmas(field, T_world_cam_predicted, stereo.p_cam, stereo.sigma_m, stereo.truncation_m);
    const double at_edges =
        meanSquaredStereoMapSigmas(field, T_world_cam_edges, stereo.p_cam, stereo.sigma_m, stereo.truncation_m);
    return std::sqrt(std::max(0.0, stereo.effective_points * (at_edges - at_prediction)));
}

double weighEdgeTerm(const map::DistanceField& field, const Eigen::Isometry3d& T_world_cam_predicted,
                     const Eigen::Isometry3d& T_world_cam_edges, const StereoSurface& stereo, double scale_sigmas,
                     std::vector<estimation::DirectEdgeTerm>& terms)
{
    if (terms.empty()) return 1.0;
    const double d = edgeStereoDisagreement(field, T_world_cam_predicted, T_world_cam_edges, stereo);
    const double w = edgeTrustWeight(d, scale_sigmas);
    if (w < kEdgeTrustDropWeight)
        terms.pop_back();
    else
        terms.back().sigma_px /= std::sqrt(w);
    return w;
}
}  // namespace quasiloc::tracking
