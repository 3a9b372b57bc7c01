#pragma once
// Point matching by descriptor distance: mutual nearest neighbour with Lowe's ratio test, L2 for float
// descriptors (SIFT, XFeat; L2-normalised) and Hamming for binary ones (ORB, AKAZE). The same code matches
// (I_{t-1}, I_t), (Q_t, I_t) and left-right pairs; what differs is the search region (a window around a
// predicted position, an epipolar band). LighterGlue is not implemented yet (Debian 12 has libtorch-dev 1.13.1,
// which the TorchScript model in ../shared/models/lighterglue needs; it must stay an optional component).
//
//   [PointMatching]
//   ratio = 0.9                 ; best < ratio * second best (distance); 1 disables the test
//   mutual = true               ; the train keypoint's best query must be the query
//   max_distance_l2 = 1.0       ; float descriptors: larger L2 distances never match (unit vectors: 0..2)
//   max_distance_hamming = 80   ; binary descriptors: larger Hamming distances never match
//   window_px = 0               ; > 0: a query's match must lie within window_px of the query's position
//                               ;   (or of its predicted position); 0: anywhere in the image
#include <mrpt/config/CLoadableOptions.h>

#include <functional>
#include <opencv2/core.hpp>
#include <quasiloc/frontend/features.h>
#include <string>
#include <vector>

namespace quasiloc::frontend
{
struct PointMatchingOptions : public mrpt::config::CLoadableOptions
{
    double ratio = 0.9;
    bool mutual = true;
    double max_distance_l2 = 1.0;
    int max_distance_hamming = 80;
    double window_px = 0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    void check(const std::string& input) const;
    /** The distance limit for these descriptors. */
    double maxDistance(const Features& f) const { return f.binary() ? max_distance_hamming : max_distance_l2; }
};

struct PointCandidate
{
    int index = -1;         ///< keypoint index in the other image
    float distance = 0;     ///< L2 or Hamming
    float similarity = 0;   ///< descriptorSimilarity(distance)
};

struct PointMatch
{
    int query = -1, train = -1;
    float distance = 0, similarity = 0;
};

/** Where the match of each query keypoint may lie in the train image. */
struct SearchRegion
{
    /** Centre per query keypoint (e.g. its position predicted into the train image); empty = the query
     *  keypoints' own positions. */
    std::vector<cv::Point2f> centers;
    double radius_px = 0;  ///< 0 = the whole image
    /** Optional: per query keypoint, the only train keypoints to consider (e.g. those in its epipolar band);
     *  used when radius_px is 0. */
    std::vector<std::vector<int>> train_subsets;
    /** Optional extra gate on (query, train) pairs (epipolar band, disparity range, ...). */
    std::function<bool(int query, int train)> accept;
};

/** Similarity in about [0, 1] from a descriptor distance: unit float vectors: cosine 1 - d^2 / 2; binary:
 *  1 - 2 d / bits (0 for unrelated random strings, 1 for identical ones). */
float descriptorSimilarity(float distance, const Features& f);

/** The k nearest train keypoints of every query keypoint within the region and max_distance, best first.
 *  If best_query_per_train is given it receives, for every train keypoint, its nearest query (index -1 if
 *  none), for the mutual check. InputError when the descriptor types differ. */
std::vector<std::vector<PointCandidate>> findCandidates(const Features& query, const Features& train, int k,
                                                        double max_distance, const SearchRegion& region,
                                                        std::vector<PointCandidate>* best_query_per_train = nullptr);

/** Mutual nearest neighbour + ratio test. The region defaults to window_px around the query positions. */
std::vector<PointMatch> matchPoints(const Features& query, const Features& train, const PointMatchingOptions& options,
                                    const SearchRegion* region = nullptr);

/** Same, from candidate lists already computed with k >= 2. */
std::vector<PointMatch> selectMatches(const std::vector<std::vector<PointCandidate>>& candidates,
                                      const std::vector<PointCandidate>& best_query_per_train,
                                      const PointMatchingOptions& options);

}  // namespace quasiloc::frontend
