// Candidate search: descriptor distances only for the (query, train) pairs the search region allows
// (a grid of train keypoints for windowed searches); a full distance matrix (cv::batchDistance, SIMD) when
// the region is the whole image.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/frontend/point_matcher.h>
#include <sys/stat.h>

#include "lighterglue_matcher.h"

namespace quasiloc::frontend
{
void PointMatchingOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.addEnum("method", method, {{"mutual_nn", MatchingMethod::MutualNn}, {"lighterglue", MatchingMethod::LighterGlue}},
              "mutual_nn | lighterglue (needs libtorch and [Features] type = xfeat)");
    t.add("ratio", ratio, "", Range{0, 1, true, false}, "mutual_nn: best < ratio * second best (distance); 1 disables");
    t.add("mutual", mutual, "mutual_nn: the train keypoint's best query must be the query");
    t.add("max_distance_l2", max_distance_l2, "", Range{0, 2, true, false},
          "float descriptors: larger L2 distances never match (unit vectors: 0..2)");
    t.add("max_distance_hamming", max_distance_hamming, "", Range::above(0),
          "binary descriptors: larger Hamming distances never match");
    t.add("window_px", window_px, "px", Range::atLeast(0),
          "> 0: a match must lie within this of the query's (predicted) position; 0: anywhere");
    t.add("lighterglue_model", lighterglue_model,
          "TorchScript file (e.g. ../shared/models/lighterglue/lighterglue_L3_ts.pt); required by lighterglue");
    t.add("lighterglue_min_score", lighterglue_min_score, "", Range::strictlyBetween(0, 1),
          "lighterglue: a mutual best pair matches when its assignment probability is above this");
}

void PointMatchingOptions::check(const std::string& input) const
{
    checkRanges(input, "PointMatching");
    if (!useLighterGlue()) return;
    const auto key = [&](const char* k) { return input + ": " + core::iniKeyName("PointMatching", k); };
    core::require(lighterGlueAvailable(), key("method"),
                  "'lighterglue' needs libtorch, and this build has none (install libtorch-dev, then configure with "
                  "-DQUASILOC_WITH_TORCH=ON); use mutual_nn");
    struct stat st;
    core::require(!lighterglue_model.empty(), key("lighterglue_model"), "required when method = lighterglue");
    core::require(::stat(lighterglue_model.c_str(), &st) == 0 && S_ISREG(st.st_mode), key("lighterglue_model"),
                  "'" + lighterglue_model + "' is not a readable file");
}

float descriptorSimilarity(float distance, const Features& f)
{
    if (f.binary()) return 1.f - 2.f * distance / float(8 * std::max(1, f.descriptors.cols));
    return 1.f - 0.5f * distance * distance;
}

namespace
{
/** Hamming distances of one query string to every train string. Compiled twice (ifunc): with the POPCNT
 *  instruction where the CPU has it (x86-64's baseline lacks it and GCC then calls a slow software popcount). */
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target_clones("popcnt", "default")))
#endif
void hammingRow(const uchar* q, const cv::Mat& train, float* out)
{
    const int bytes = train.cols;
    for (int j = 0; j < train.rows; ++j)
    {
        const uchar* t = train.ptr<uchar>(j);
        int bits = 0, c = 0;
        for (; c + 8 <= bytes; c += 8)
        {
            uint64_t x, y;
            std::memcpy(&x, q + c, 8);
            std::memcpy(&y, t + c, 8);
            bits += __builtin_popcountll(x ^ y);
        }
        for (; c < bytes; ++c) bits += __builtin_popcount(unsigned(q[c] ^ t[c]));
        out[j] = float(bits);
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target_clones("popcnt", "default")))
#endif
float pairDistance(const cv::Mat& a, int i, const cv::Mat& b, int j)
{
    if (a.depth() == CV_8U)
    {
        const uchar* p = a.ptr<uchar>(i);
        const uchar* q = b.ptr<uchar>(j);
        int bits = 0, c = 0;
        for (; c + 8 <= a.cols; c += 8)
        {
            uint64_t x, y;
            std::memcpy(&x, p + c, 8);
            std::memcpy(&y, q + c, 8);
            bits += __builtin_popcountll(x ^ y);
        }
        for (; c < a.cols; ++c) bits += __builtin_popcount(unsigned(p[c] ^ q[c]));
        return float(bits);
    }
    const float* p = a.ptr<float>(i);
    const float* q = b.ptr<float>(j);
    float s = 0;
    for (int c = 0; c < a.cols; ++c)
    {
        const float d = p[c] - q[c];
        s += d * d;
    }
    return std::sqrt(s);
}

/** Keeps the k smallest distances of a query, sorted (k is small: insertion). */
void insertCandidate(std::vector<PointCandidate>& list, int k, const PointCandidate& c)
{
    if (int(list.size()) == k && c.distance >= list.back().distance) return;
    auto it = std::upper_bound(list.begin(), list.end(), c, [](const PointCandidate& a, const PointCandidate& b) {
        return a.distance < b.distance;
    });
    list.insert(it, c);
    if (int(list.size()) > k) list.pop_back();
}

/** Calls visit(i, j) for every train keypoint j within radius of centre i (grid of train keypoints). */
template <class Visit>
void forWindowPairs(const Features& train, const std::vector<cv::Point2f>& centers, double radius, Visit visit)
{
    const float cell = float(std::max(radius, 1.0));
    float max_x = 0, max_y = 0;
    for (const auto& k : train.keypoints) max_x = std::max(max_x, k.pt.x), max_y = std::max(max_y, k.pt.y);
    const int gw = int(max_x / cell) + 1, gh = int(max_y / cell) + 1;
    std::vector<std::vector<int>> grid(size_t(gw) * gh);
    for (size_t j = 0; j < train.keypoints.size(); ++j)
    {
        const auto& p = train.keypoints[j].pt;
        grid[size_t(std::max(0, int(p.y / cell))) * gw + std::max(0, int(p.x / cell))].push_back(int(j));
    }
    const float r2 = float(radius * radius);
    for (size_t i = 0; i < centers.size(); ++i)
    {
        const cv::Point2f c = centers[i];
        const int x0 = std::max(0, int(std::floor((c.x - cell) / cell))),
                  x1 = std::min(gw - 1, int((c.x + cell) / cell));
        const int y0 = std::max(0, int(std::floor((c.y - cell) / cell))),
                  y1 = std::min(gh - 1, int((c.y + cell) / cell));
        for (int gy = y0; gy <= y1; ++gy)
            for (int gx = x0; gx <= x1; ++gx)
                for (int j : grid[size_t(gy) * gw + gx])
                {
                    const cv::Point2f d = train.keypoints[j].pt - c;
                    if (d.x * d.x + d.y * d.y <= r2) visit(int(i), j);
                }
    }
}
}  // namespace

std::vector<std::vector<PointCandidate>> findCandidates(const Features& query, const Features& train, int k,
                                                        double max_distance, const SearchRegion& region,
                                                        std::vector<PointCandidate>* best_query_per_train)
{
    std::vector<std::vector<PointCandidate>> out(query.size());
    if (best_query_per_train) best_query_per_train->assign(train.size(), PointCandidate{-1, 1e30f, 0});
    if (query.size() == 0 || train.size() == 0) return out;
    core::require(
        query.descriptors.type() == train.descriptors.type() && query.descriptors.cols == train.descriptors.cols,
        "point matching", "the two images have different descriptor types");
    auto consider = [&](int i, int j, float d) {
        if (d > max_distance || (region.accept && !region.accept(i, j))) return;
        const PointCandidate c{j, d, descriptorSimilarity(d, train)};
        insertCandidate(out[i], k, c);
        if (best_query_per_train && d < (*best_query_per_train)[j].distance)
            (*best_query_per_train)[j] = PointCandidate{i, d, c.similarity};
    };
    if (region.radius_px > 0)
    {
        std::vector<cv::Point2f> own;
        if (region.centers.empty())
            for (const auto& kp : query.keypoints) own.push_back(kp.pt);
        const auto& centers = region.centers.empty() ? own : region.centers;
        core::require(centers.size() == query.size(), "point matching",
                      "one search centre per query keypoint expected");
        forWindowPairs(train, centers, region.radius_px,
                       [&](int i, int j) { consider(i, j, pairDistance(query.descriptors, i, train.descriptors, j)); });
    }
    else if (!region.train_subsets.empty())
    {
        core::require(region.train_subsets.size() == query.size(), "point matching",
                      "one train subset per query keypoint expected");
        for (size_t i = 0; i < query.size(); ++i)
            for (int j : region.train_subsets[i])
                consider(int(i), j, pairDistance(query.descriptors, int(i), train.descriptors, j));
    }
    else if (query.binary())
    {
        // A row of popcounts at a time beats cv::batchDistance's per-pair calls for 32-61 byte strings.
        std::vector<float> row(train.size());
        for (int i = 0; i < int(query.size()); ++i)
        {
            hammingRow(query.descriptors.ptr<uchar>(i), train.descriptors, row.data());
            for (int j = 0; j < int(train.size()); ++j) consider(i, j, row[j]);
        }
    }
    else
    {
        cv::Mat dist;
        cv::batchDistance(query.descriptors, train.descriptors, dist, CV_32F, cv::noArray(), cv::NORM_L2, 0);
        for (int i = 0; i < dist.rows; ++i)
        {
            const float* d = dist.ptr<float>(i);
            for (int j = 0; j < dist.cols; ++j) consider(i, j, d[j]);
        }
    }
    if (best_query_per_train)
        for (auto& b : *best_query_per_train)
            if (b.index < 0) b.distance = 0;
    return out;
}

std::vector<PointMatch> selectMatches(const std::vector<std::vector<PointCandidate>>& candidates,
                                      const std::vector<PointCandidate>& best_query_per_train,
                                      const PointMatchingOptions& options)
{
    std::vector<PointMatch> matches;
    for (size_t i = 0; i < candidates.size(); ++i)
    {
        const auto& c = candidates[i];
        if (c.empty()) continue;
        if (c.size() > 1 && options.ratio < 1 && !(c[0].distance < options.ratio * c[1].distance)) continue;
        if (options.mutual && best_query_per_train[c[0].index].index != int(i)) continue;
        matches.push_back(PointMatch{int(i), c[0].index, c[0].distance, c[0].similarity});
    }
    return matches;
}

std::vector<PointMatch> matchPoints(const Features& query, const Features& train, const PointMatchingOptions& options,
                                    const SearchRegion* region)
{
    if (options.useLighterGlue()) return detail::matchWithLighterGlue(query, train, options, region);
    return detail::matchMutualNearest(query, train, options, region);
}

std::vector<PointMatch> detail::matchMutualNearest(const Features& query, const Features& train,
                                                   const PointMatchingOptions& options, const SearchRegion* region)
{
    SearchRegion own;
    own.radius_px = options.window_px;
    std::vector<PointCandidate> best_query;
    const auto cands = findCandidates(query, train, 2, options.maxDistance(query), region ? *region : own, &best_query);
    return selectMatches(cands, best_query, options);
}
}  // namespace quasiloc::frontend
