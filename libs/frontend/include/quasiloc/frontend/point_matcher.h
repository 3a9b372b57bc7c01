#pragma once
// Point matching, the same code for (I_{t-1}, I_t), (Q_t, I_t) and left-right pairs; what differs is the search
// region (a window around a predicted position, an epipolar band). Two matchers behind one interface, chosen in
// INI:
//  - mutual_nn: mutual nearest neighbour by descriptor distance with Lowe's ratio test, L2 for float descriptors
//    (SIFT, XFeat; L2-normalised) and Hamming for binary ones (ORB, AKAZE).
//  - lighterglue: the LighterGlue network for XFeat descriptors (TorchScript through libtorch, an optional component:
//    builds without libtorch reject this method with an error naming the key). The network sees every keypoint of
//    both images; the search region then gates its matches.
//
// Options: [PointMatching] (PointMatchingOptions::declare, point_matcher.cpp).
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/frontend/features.h>
#include <string>
#include <vector>

namespace quasiloc::frontend
{
enum class MatchingMethod
{
    MutualNn,    ///< mutual nearest neighbour + ratio test
    LighterGlue  ///< the LighterGlue network (libtorch; [Features] type = xfeat)
};

struct PointMatchingOptions : public core::DeclaredOptions
{
    MatchingMethod method = MatchingMethod::MutualNn;
    double ratio = 0.9;
    bool mutual = true;
    double max_distance_l2 = 1.0;
    int max_distance_hamming = 80;
    double window_px = 0;
    std::string lighterglue_model;
    double lighterglue_min_score = 0.1;

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range, or method = lighterglue in a
     *  build without libtorch ([PointMatching] method) or without a readable model file (lighterglue_model). */
    void check(const std::string& input) const;
    bool useLighterGlue() const { return method == MatchingMethod::LighterGlue; }
    /** The distance limit for these descriptors. */
    double maxDistance(const Features& f) const { return f.binary() ? max_distance_hamming : max_distance_l2; }
};

struct PointCandidate
{
    int index = -1;        ///< keypoint index in the other image
    float distance = 0;    ///< L2 or Hamming
    float similarity = 0;  ///< descriptorSimilarity(distance)
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

/** The matches of query keypoints in the train image by the method of options: mutual nearest neighbour + ratio
 *  test, or LighterGlue (its model loaded once per thread and model file, then reused). The region defaults to
 *  window_px around the query positions. */
std::vector<PointMatch> matchPoints(const Features& query, const Features& train, const PointMatchingOptions& options,
                                    const SearchRegion* region = nullptr);

/** Same, from candidate lists already computed with k >= 2. */
std::vector<PointMatch> selectMatches(const std::vector<std::vector<PointCandidate>>& candidates,
                                      const std::vector<PointCandidate>& best_query_per_train,
                                      const PointMatchingOptions& options);

/** True when this build has libtorch, i.e. [PointMatching] method = lighterglue can be used. */
bool lighterGlueAvailable();

/** A point matcher that owns its state (LighterGlue: the loaded network). Not reentrant: one per thread. */
class PointMatcher
{
   public:
    virtual ~PointMatcher() = default;
    /** Same contract as matchPoints: matches within the region (default: window_px around the query positions),
     *  `distance` and `similarity` are the descriptors' (descriptorSimilarity), whatever the method. */
    virtual std::vector<PointMatch> match(const Features& query, const Features& train,
                                          const SearchRegion* region = nullptr) = 0;
};

/** The matcher of options.method (options.check() first; LighterGlue loads its model here). */
std::unique_ptr<PointMatcher> createPointMatcher(const PointMatchingOptions& options);

}  // namespace quasiloc::frontend
