#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/frontend/line_matcher.h>

namespace quasiloc::frontend
{
void LineMatchingOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("epsilon", epsilon, "", Range::between(0.01, 10),
          "entropy regularisation (cost units; smaller = sharper plan, more iterations)");
    t.add("dustbin_cost", dustbin_cost, "", Range::between(0, 2),
          "cost of leaving a line unmatched (pairs with 1 - <f_i,f_j> above it lose)");
    t.add("max_iterations", max_iterations, "", Range::atLeast(1), "Sinkhorn iterations at most");
    t.add("tolerance", tolerance, "", Range::above(0), "row-marginal error at which iterations stop");
    t.add("min_probability", min_probability, "", Range{0, 1, true, false}, "P_ij needed for a match");
    t.add("gate_max_distance_px", gate_max_distance_px, "px", Range::above(0),
          "geometric gate: a segment's midpoint within this of the other segment");
    t.add("gate_max_angle_deg", gate_max_angle_deg, "deg", Range{0, 90, true, false},
          "geometric gate: directions within this angle (undirected)");
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
    core::require(
        M == 0 || N == 0 ||
            (query_desc.cols == train_desc.cols && query_desc.type() == CV_32F && train_desc.type() == CV_32F),
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
    r.transport =
        sinkhorn(cost, options.dustbin_cost, options.epsilon, options.max_iterations, options.tolerance, &r.allowed);
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
