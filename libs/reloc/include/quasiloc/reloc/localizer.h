#pragma once
// Global localization of one camera image against the database (no initial guess), PAPER_NOTES "Global
// localization":
//  1. extract the query's point features with the database's [Features] options;
//  2. retrieval: bag-of-words scores through the inverted index, the best retrieval_per_group * groups views;
//  3. grouping: retrieved views whose positions lie within group_radius_m and headings within
//     group_heading_deg of a group's best view join it (views that see the same part of the map); groups are
//     ordered by their summed retrieval score;
//  4. re-ranking: the query is matched (mutual nearest neighbour + ratio, [PointMatching] of the localizer) to
//     the best views_per_group views of each group; groups are re-ranked by the number of query keypoints
//     matched to a lifted map point;
//  5. multi-view voting: within a group, a query keypoint may be matched in several views; its 3D candidates
//     vote, candidates closer than voting_radius_m agree, and the point with the most votes (then the best
//     descriptor similarity) is kept: one 2D-3D correspondence per query keypoint, consistent across views;
//  6. multi-hypothesis PnP (estimation::estimateAbsolutePose, MAGSAC++ + refinement) on the top pnp_groups
//     groups; the hypothesis with the most inliers wins;
//  7. decision: the winner must have min_inliers inliers and min_inlier_ratio of its correspondences, lie
//     within max_distance_to_views_m of its group's views, and no other hypothesis farther than
//     ambiguity_distance_m may reach ambiguity_ratio of its inliers; otherwise the answer is "not localized"
//     (with the reason), never a weak guess.
// Budgets: Fast tries fast_groups groups, and fast_groups_retry when that fails; Full tries full_groups, then
// full_groups_retry.
//
// Options: [Localization] (LocalizerOptions::declare, localizer_options.cpp) and [PointMatching].
#include <Eigen/Geometry>
#include <memory>
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/estimation/absolute_pose.h>
#include <quasiloc/frontend/point_matcher.h>
#include <quasiloc/reloc/database.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
enum class LocalizationMode
{
    Fast,
    Full
};
std::string toString(LocalizationMode m);
/** "fast" | "full"; InputError naming `input` otherwise. */
LocalizationMode localizationModeFromString(const std::string& s, const std::string& input);

struct LocalizerOptions : public core::DeclaredOptions
{
    int retrieval_per_group = 4;
    double group_radius_m = 1.0;
    double group_heading_deg = 50;
    int views_per_group = 3;
    int fast_groups = 16, fast_groups_retry = 32;
    int full_groups = 40, full_groups_retry = 200;
    int pnp_groups = 4;
    int min_group_matches = 12;
    /** A query descriptor is compared only with the view's descriptors under the same vocabulary node at this level
     *  (1 = the root's children; 0 = all): the direct index of DBoW2, about branching^level times fewer
     *  comparisons. */
    int match_level = 1;
    double voting_radius_m = 0.1;
    /** Only correspondences confirmed by this many of a group's views are kept, when at least min_group_matches of
     *  them are (else all). Why 1: docs/experiments.md. */
    int min_votes = 1;
    double pnp_reproj_px = 3.0;
    /** Why usac_default: docs/experiments.md. */
    estimation::PnpMethod pnp_method = estimation::PnpMethod::UsacDefault;
    int pnp_max_iterations = 1000;
    int min_inliers = 15;
    double min_inlier_ratio = 0.1;
    double max_distance_to_views_m = 3.0;
    double ambiguity_distance_m = 0.5;
    double ambiguity_ratio = 0.8;
    /** [PointMatching] (window_px must be 0: there is no prior here). The ratio test defaults to 0.8 here,
     *  stricter than the front-end's 0.9: without a search window most second-best candidates are unrelated. */
    frontend::PointMatchingOptions matching = [] {
        frontend::PointMatchingOptions m;
        m.ratio = 0.8;
        return m;
    }();

    void declare(core::OptionTable& t) override;
    /** InputError naming `input` and the key for a value out of its declared range, retry budgets below their
     *  first tries, and for [PointMatching] (window_px must be 0). */
    void check(const std::string& input) const;
    estimation::AbsolutePoseOptions pnpOptions() const;
};

struct RetrievedView
{
    int view = -1;
    float score = 0;   ///< bag-of-words score
    int group = -1;    ///< index into LocalizationReport::groups
    int matches = -1;  ///< query keypoints matched to a lifted point of this view (-1: not matched)
};

struct GroupReport
{
    std::vector<int> views;  ///< database view ids, best retrieval score first
    float score = 0;         ///< summed retrieval score
    int matched = 0;         ///< query keypoints with a 3D correspondence after voting (-1: not re-ranked)
    int inliers = -1;        ///< PnP inliers (-1: no PnP)
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  ///< its PnP pose (if inliers >= 0)
};

struct LocalizationTimes
{
    double extract = 0, retrieval = 0, rerank = 0, pnp = 0, total = 0;  ///< milliseconds (wall)
};

struct LocalizationReport
{
    bool localized = false;
    std::string reason;  ///< why not localized ("" when localized)
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    int inliers = 0, correspondences = 0;
    int best_group = -1;
    int query_keypoints = 0;
    bool retried = false;  ///< the second (larger) group budget was needed
    std::vector<RetrievedView> retrieved;
    std::vector<GroupReport> groups;
    LocalizationTimes ms;
};

class Localizer
{
   public:
    /** Keeps a reference to `db` (must outlive the localizer). InputError for bad options. */
    Localizer(const Database& db, const LocalizerOptions& options);
    ~Localizer();
    /** Localizes an 8-bit grayscale image taken with `camera` (it may differ from the database's). */
    LocalizationReport localize(const cv::Mat& gray, const core::CameraModel& camera, LocalizationMode mode);

   private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/** A human-readable account of one query (retrieved views with scores and groups, matches, hypotheses). */
std::string describe(const LocalizationReport& r, const Database& db);

}  // namespace quasiloc::reloc
