#pragma once
// Line matching by optimal transport (sinkhorn.h) on C_ij = 1 - <f_i, f_j> of the hybrid descriptors.
// A match is a mutual argmax of the plan's inner block with P_ij >= min_probability. With a predicted pose,
// the caller passes segments already in the same pixel frame (a quasi-image rendered at the predicted pose
// is), and the geometric gate removes pairs that are too far apart or too differently oriented.
//
// Options: [LineMatching] (LineMatchingOptions::declare, line_matcher.cpp).
#include <opencv2/core.hpp>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/frontend/lines.h>
#include <quasiloc/frontend/sinkhorn.h>
#include <string>
#include <vector>

namespace quasiloc::frontend
{
struct LineMatchingOptions : public core::DeclaredOptions
{
    double epsilon = 0.05;
    double dustbin_cost = 0.35;
    int max_iterations = 100;
    double tolerance = 1e-4;
    double min_probability = 0.2;
    double gate_max_distance_px = 40;
    double gate_max_angle_deg = 10;

    void declare(core::OptionTable& t) override;
};

struct LineMatch
{
    int query = -1, train = -1;
    float probability = 0;  ///< P_ij of the transport plan
    float similarity = 0;   ///< <f_i, f_j>
};

struct LineMatchResult
{
    std::vector<LineMatch> matches;
    Eigen::MatrixXf similarity;  ///< <f_i, f_j>, M x N
    BoolMatrix allowed;          ///< the gate (all true without it)
    SinkhornResult transport;
};

/** True when the two segments pass the geometric gate of `options`. */
bool lineGate(const LineSegment& a, const LineSegment& b, const LineMatchingOptions& options);

/** Matches query lines (descriptors one row each) to train lines. use_gate: apply the geometric gate. */
LineMatchResult matchLines(const cv::Mat& query_desc, const std::vector<LineSegment>& query_lines,
                           const cv::Mat& train_desc, const std::vector<LineSegment>& train_lines,
                           const LineMatchingOptions& options, bool use_gate);

}  // namespace quasiloc::frontend
