#pragma once
// Internals of the LighterGlue matcher shared with point_matcher.cpp and the unit tests (not installed).
#include <quasiloc/frontend/point_matcher.h>
#include <utility>
#include <vector>

namespace quasiloc::frontend::detail
{
/** Keypoints as the network wants them: (k - size / 2) / (max(size) / 2), Mx2 CV_32F. The size is
 *  f.image_size, or (features made by hand) the extent of the keypoints. */
cv::Mat normalisedKeypoints(const Features& f);

/** The (row, column) pairs of the inner MxN block of a log-assignment matrix ((M+1)x(N+1), CV_32F) that are each
 *  other's best and whose probability exp(score) is above min_score, by row. */
std::vector<std::pair<int, int>> mutualBestAssignments(const cv::Mat& log_assignment, double min_score);

/** Whether the region allows train keypoint j for query keypoint i: the window when radius_px > 0, else the
 *  train subset when given; then the extra gate (the same precedence as findCandidates). */
bool regionAllows(const SearchRegion& region, const Features& query, const Features& train, int i, int j);

/** matchPoints for method = lighterglue: a matcher per thread and model file, loaded on first use. */
std::vector<PointMatch> matchWithLighterGlue(const Features& query, const Features& train,
                                             const PointMatchingOptions& options, const SearchRegion* region);

/** matchPoints for method = mutual_nn. */
std::vector<PointMatch> matchMutualNearest(const Features& query, const Features& train,
                                           const PointMatchingOptions& options, const SearchRegion* region);
}  // namespace quasiloc::frontend::detail
