#include "cost_profile.h"

#include <quasiloc/quasi/histogram_matching.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>

namespace quasiloc::bench
{
Eigen::Isometry3d axisStep(int k, double step_m, double step_deg)
{
    const int axis = k / 2;
    const double sign = k % 2 == 0 ? -1.0 : 1.0;
    Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
    if (axis < 3)
        d.translation()[axis] = sign * step_m;
    else
        d.linear() =
            Eigen::AngleAxisd(sign * step_deg * M_PI / 180, Eigen::Vector3d::Unit(axis - 3)).toRotationMatrix();
    return d;
}

CostProfile profileDirectTerms(const CrossModalSequence& seq, quasi::QuasiRenderer& renderer,
                               const estimation::DirectAlignmentOptions& options, double step_m, double step_deg,
                               frontend::Frontend& frontend, bool matched_reflectivity)
{
    CostProfile p;
    quasi::QuasiImage q;
    for (const QueryFrame& fr : seq.frames)
    {
        renderer.render(core::fromIsometry(fr.T_world_cam), seq.camera, q);
        p.mean_valid_fraction += double(cv::countNonZero(q.valid)) / double(q.valid.total());
        const auto field = estimation::buildCameraEdgeField(options, fr.image);
        const auto model = estimation::buildDirectAlignmentModel(options, q.depth, q.reflectivity, q.valid, q.sparse,
                                                                 seq.camera, fr.T_world_cam);
        const auto nmi =
            estimation::buildNmiSamples(options, q.depth, q.reflectivity, q.sparse, seq.camera, fr.T_world_cam);
        p.mean_edge_points += double(model.edge_points_world.size());
        const double e0 = estimation::edgeCost(options, field, 0, seq.camera, model, fr.T_world_cam);
        const double n0 = estimation::normalizedMutualInformation(options, field, seq.camera, nmi, fr.T_world_cam);
        // Feature-metric score (feature_metric_alignment.h), when the features have a dense map.
        frontend::FrameFeatures fc, fq;
        cv::Mat gray;
        if (fr.image.channels() == 3)
            cv::cvtColor(fr.image, gray, cv::COLOR_BGR2GRAY);
        else
            gray = fr.image;
        frontend.extract(gray, cv::Mat(), fc);
        if (matched_reflectivity) q.gray = quasi::reflectivityMatchedToImage(q, gray);  // [MapRefinement] quasi_gray
        frontend.extract(q.gray, q.valid, fq);
        const bool fm = !fc.points.dense.empty() && !fq.points.dense.empty();
        const frontend::DenseMap cam_dense = fm ? centredDenseMap(fc.points.dense) : frontend::DenseMap{};
        const FeatureMetricModel fm_model =
            fm ? buildFeatureMetricModel(fq.points.dense, q.depth, q.valid, seq.camera, fr.T_world_cam)
               : FeatureMetricModel{};
        const double f0 = fm ? featureMetricScore(cam_dense, fm_model, seq.camera, fr.T_world_cam) : 0.0;
        for (int k = 0; k < 12; ++k)
        {
            const Eigen::Isometry3d T = fr.T_world_cam * axisStep(k, step_m, step_deg);
            const double e = estimation::edgeCost(options, field, 0, seq.camera, model, T);
            const double n = estimation::normalizedMutualInformation(options, field, seq.camera, nmi, T);
            ++p.steps;
            p.edge_truth_best += e0 < e;
            p.nmi_truth_best += n0 > n;
            p.mean_edge_rise += (e - e0) / std::max(1e-9, e0);
            p.mean_nmi_drop += n0 - n;
            if (fm)
            {
                const double f = featureMetricScore(cam_dense, fm_model, seq.camera, T);
                p.fm_truth_best += f0 > f;
                p.mean_fm_drop += f0 - f;
            }
            else
                p.fm_truth_best = -1;
        }
    }
    const double nf = double(std::max<size_t>(1, seq.frames.size()));
    p.mean_valid_fraction /= nf;
    p.mean_edge_points /= nf;
    p.mean_edge_rise /= std::max(1, p.steps);
    p.mean_nmi_drop /= std::max(1, p.steps);
    p.mean_fm_drop /= std::max(1, p.steps);
    return p;
}

}  // namespace quasiloc::bench
