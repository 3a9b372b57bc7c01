// LighterGlue (XFeat's lightweight LightGlue) behind PointMatcher. This file is plain C++: the network itself is
// behind lighterglue/network.h, compiled from libtorch only when the build has it. The network sees every
// keypoint of both images (its attention needs the context); the search region gates its matches afterwards.
#include <algorithm>
#include <cmath>
#include <map>
#include <quasiloc/core/error.h>

#include "lighterglue/network.h"
#include "lighterglue_matcher.h"

namespace quasiloc::frontend
{
namespace detail
{
cv::Mat normalisedKeypoints(const Features& f)
{
    float w = float(f.image_size.width), h = float(f.image_size.height);
    if (f.image_size.empty())
        for (const auto& k : f.keypoints) w = std::max(w, k.pt.x + 1), h = std::max(h, k.pt.y + 1);
    const float scale = std::max(1.f, 0.5f * std::max(w, h));
    cv::Mat out(int(f.size()), 2, CV_32F);
    for (int i = 0; i < out.rows; ++i)
    {
        out.at<float>(i, 0) = (f.keypoints[size_t(i)].pt.x - 0.5f * w) / scale;
        out.at<float>(i, 1) = (f.keypoints[size_t(i)].pt.y - 0.5f * h) / scale;
    }
    return out;
}

std::vector<std::pair<int, int>> mutualBestAssignments(const cv::Mat& scores, double min_score)
{
    CV_Assert(scores.type() == CV_32FC1 && scores.rows >= 1 && scores.cols >= 1);
    const int M = scores.rows - 1, N = scores.cols - 1;
    std::vector<int> best_col(size_t(M), -1), best_row(size_t(N), -1);
    std::vector<float> col_max(size_t(N), -INFINITY);
    for (int i = 0; i < M; ++i)
    {
        const float* s = scores.ptr<float>(i);
        float row_max = -INFINITY;
        for (int j = 0; j < N; ++j)
        {
            if (s[j] > row_max) row_max = s[j], best_col[size_t(i)] = j;
            if (s[j] > col_max[size_t(j)]) col_max[size_t(j)] = s[j], best_row[size_t(j)] = i;
        }
    }
    const float min_log = float(std::log(min_score));
    std::vector<std::pair<int, int>> out;
    for (int i = 0; i < M; ++i)
    {
        const int j = best_col[size_t(i)];
        if (j >= 0 && best_row[size_t(j)] == i && scores.at<float>(i, j) > min_log) out.emplace_back(i, j);
    }
    return out;
}

bool regionAllows(const SearchRegion& region, const Features& query, const Features& train, int i, int j)
{
    if (region.radius_px > 0)
    {
        const cv::Point2f c = region.centers.empty() ? query.keypoints[size_t(i)].pt : region.centers[size_t(i)];
        const cv::Point2f d = train.keypoints[size_t(j)].pt - c;
        if (d.x * d.x + d.y * d.y > float(region.radius_px * region.radius_px)) return false;
    }
    else if (!region.train_subsets.empty())
    {
        const auto& subset = region.train_subsets[size_t(i)];
        if (std::find(subset.begin(), subset.end(), j) == subset.end()) return false;
    }
    return !region.accept || region.accept(i, j);
}
}  // namespace detail

namespace
{
using namespace detail;

void requireXFeatDescriptors(const Features& f, const char* which)
{
    if (f.size() == 0) return;  // an image without keypoints has nothing to match, whatever its descriptor type
    core::require(f.descriptors.type() == CV_32FC1 && f.descriptors.cols == 64 && f.descriptors.rows == int(f.size()),
                  std::string("LighterGlue matching (") + which + " features)",
                  "expects XFeat descriptors (64 floats per keypoint, [Features] type = xfeat)");
}

class LighterGlueMatcher : public PointMatcher
{
   public:
    explicit LighterGlueMatcher(const PointMatchingOptions& o) : options_(o), network_(o.lighterglue_model) {}

    std::vector<PointMatch> match(const Features& query, const Features& train, const SearchRegion* region) override
    {
        return matchWith(options_, query, train, region);
    }

    /** match() with another window_px / lighterglue_min_score (same model). */
    std::vector<PointMatch> matchWith(const PointMatchingOptions& options, const Features& query, const Features& train,
                                      const SearchRegion* region)
    {
        requireXFeatDescriptors(query, "query");
        requireXFeatDescriptors(train, "train");
        if (query.size() == 0 || train.size() == 0) return {};
        SearchRegion own;
        own.radius_px = options.window_px;
        const SearchRegion& r = region ? *region : own;
        core::require(r.centers.empty() || r.centers.size() == query.size(), "point matching",
                      "one search centre per query keypoint expected");
        core::require(r.radius_px > 0 || r.train_subsets.empty() || r.train_subsets.size() == query.size(),
                      "point matching", "one train subset per query keypoint expected");
        const cv::Mat scores = network_.logAssignment(normalisedKeypoints(query), normalisedKeypoints(train),
                                                      continuous(query.descriptors), continuous(train.descriptors));
        std::vector<PointMatch> out;
        for (const auto& [i, j] : mutualBestAssignments(scores, options.lighterglue_min_score))
        {
            if (!regionAllows(r, query, train, i, j)) continue;
            const float d = float(cv::norm(query.descriptors.row(i), train.descriptors.row(j), cv::NORM_L2));
            out.push_back(PointMatch{i, j, d, descriptorSimilarity(d, train)});
        }
        return out;
    }

   private:
    static cv::Mat continuous(const cv::Mat& m) { return m.isContinuous() ? m : m.clone(); }

    PointMatchingOptions options_;
    LighterGlueNetwork network_;
};

class MutualNearestMatcher : public PointMatcher
{
   public:
    explicit MutualNearestMatcher(const PointMatchingOptions& o) : options_(o) {}
    std::vector<PointMatch> match(const Features& query, const Features& train, const SearchRegion* region) override
    {
        return matchMutualNearest(query, train, options_, region);
    }

   private:
    PointMatchingOptions options_;
};
}  // namespace

bool lighterGlueAvailable() { return lighterGlueCompiledIn(); }

std::unique_ptr<PointMatcher> createPointMatcher(const PointMatchingOptions& options)
{
    options.check("point matching options");
    if (options.useLighterGlue()) return std::make_unique<LighterGlueMatcher>(options);
    return std::make_unique<MutualNearestMatcher>(options);
}

namespace detail
{
std::vector<PointMatch> matchWithLighterGlue(const Features& query, const Features& train,
                                             const PointMatchingOptions& options, const SearchRegion* region)
{
    // matchPoints is a free function called with options only (tracker, map refinement): the network is loaded
    // once per thread and model file and kept, instead of once per call (a load takes far longer than a match).
    // Per thread because a TorchScript module is not documented as safe to run from several threads at once.
    thread_local std::map<std::string, std::unique_ptr<LighterGlueMatcher>> loaded;
    auto& matcher = loaded[options.lighterglue_model];
    if (!matcher)
    {
        options.check("point matching options");
        matcher = std::make_unique<LighterGlueMatcher>(options);
    }
    return matcher->matchWith(options, query, train, region);
}
}  // namespace detail
}  // namespace quasiloc::frontend
