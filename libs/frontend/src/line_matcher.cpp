#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/line_matcher.h>

#include "ini_read.h"

namespace quasiloc::frontend
{
using namespace detail;

void LineMatchingOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& s)
{
    epsilon = readDouble(cfg, s, "epsilon", epsilon);
    dustbin_cost = readDouble(cfg, s, "dustbin_cost", dustbin_cost);
    max_iterations = readInt(cfg, s, "max_iterations", max_iterations);
    tolerance = readDouble(cfg, s, "tolerance", tolerance);
    min_probability = readDouble(cfg, s, "min_probability", min_probability);
    gate_max_distance_px = readDouble(cfg, s, "gate_max_distance_px", gate_max_distance_px);
    gate_max_angle_deg = readDouble(cfg, s, "gate_max_angle_deg", gate_max_angle_deg);
}

void LineMatchingOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
    c.write(s, "epsilon", epsilon, 30, 40, "entropy regularisation");
    c.write(s, "dustbin_cost", dustbin_cost, 30, 40, "cost of leaving a line unmatched");
    c.write(s, "max_iterations", max_iterations, 30, 40, "Sinkhorn iterations at most");
    c.write(s, "tolerance", tolerance, 30, 40, "row-marginal error to stop at");
    c.write(s, "min_probability", min_probability, 30, 40, "P_ij needed for a match");
    c.write(s, "gate_max_distance_px", gate_max_distance_px, 30, 40, "geometric gate: midpoint distance");
    c.write(s, "gate_max_angle_deg", gate_max_angle_deg, 30, 40, "geometric gate: direction difference");
}

void LineMatchingOptions::check(const std::string& input) const
{
    const std::string S = "LineMatching";
    requireKey(epsilon >= 0.01 && epsilon <= 10, input, S, "epsilon", "must be in [0.01, 10]");
    requireKey(dustbin_cost >= 0 && dustbin_cost <= 2, input, S, "dustbin_cost", "must be in [0, 2]");
    requireKey(max_iterations >= 1, input, S, "max_iterations", "must be >= 1");
    requireKey(tolerance > 0, input, S, "tolerance", "must be > 0");
    requireKey(min_probability > 0 && min_probability <= 1, input, S, "min_probability", "must be in (0, 1]");
    requireKey(gate_max_distance_px > 0, input, S, "gate_max_distance_px", "must be > 0");
    requireKey(gate_max_angle_deg > 0 && gate_max_angle_deg <= 90, input, S, "gate_max_angle_deg", "must be in (0, 90]");
}

bool lineGate(const LineSegment& a, const LineSegment& b, const LineMatchingOptions& o)
{
    const float cosang = std::abs(a.direction().dot(b.direction()));
    if (cosang < std::cos(o.gate_max_angle_deg * M_PI / 180.0)) return false;
    const float d = std::min(a.distanceToSegment(b.midpoint()), b.distanceToSegment(a.midpoint()));
    return d <= o.gate_max_distance_px;
}

LineMatchResult matchLines(const cv::Mat& query_desc, const std::vector<LineSegment>& query_lines,
                           const cv::Mat& train_desc, const std::vector<LineSegment>& train_lines,
                           const LineMatchingOptions& options, bool use_gate)
{
    const int M = query_desc.rows, N = train_desc.rows;
    core::require(M == int(query_lines.size()) && N == int(train_lines.size()), "line matching",
                  "one descriptor row per segment expected");
    core::require(M == 0 || N == 0 || (query_desc.cols == train_desc.cols && query_desc.type() == CV_32F &&
                                       train_desc.type() == CV_32F),
                  "line matching", "descriptors must be CV_32F rows of the same length");
    LineMatchResult r;
    r.similarity.resize(M, N);
    r.allowed.setConstant(M, N, true);
    if (M > 0 && N > 0)
    {
        cv::Mat S;
        cv::gemm(query_desc, train_desc, 1.0, cv::noArray(), 0.0, S, cv::GEMM_2_T);
        for (int i = 0; i < M; ++i)
            for (int j = 0; j < N; ++j)
            {
                r.similarity(i, j) = S.at<float>(i, j);
                if (use_gate) r.allowed(i, j) = lineGate(query_lines[i], train_lines[j], options);
            }
    }
    const Eigen::MatrixXd cost = (1.0 - r.similarity.cast<double>().array()).matrix();
    r.transport = sinkhorn(cost, options.dustbin_cost, options.epsilon, options.max_iterations, options.tolerance,
                           &r.allowed);
    const auto P = r.transport.plan.topLeftCorner(M, N);
    for (int i = 0; i < M && N > 0; ++i)
    {
        int j = 0;
        const double p = P.row(i).maxCoeff(&j);
        int i_back = 0;
        P.col(j).maxCoeff(&i_back);
        if (i_back == i && p >= options.min_probability && r.allowed(i, j))
            r.matches.push_back(LineMatch{i, j, float(p), r.similarity(i, j)});
    }
    return r;
}
}  // namespace quasiloc::frontend
