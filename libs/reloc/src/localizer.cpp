#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/estimation/absolute_pose.h>
#include <quasiloc/reloc/localizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <unordered_map>
#include <numeric>
#include <sstream>
#include <opencv2/core/utility.hpp>

namespace quasiloc::reloc
{
namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

Eigen::Vector3d viewPosition(const DatabaseView& v)
{
    return {v.T_world_cam.x(), v.T_world_cam.y(), v.T_world_cam.z()};
}
Eigen::Vector3d viewForward(const DatabaseView& v)
{
    const auto R = v.T_world_cam.getRotationMatrix();
    return {R(0, 2), R(1, 2), R(2, 2)};
}

/** One group's 2D-3D correspondences after voting. */
struct GroupCorrespondences
{
    std::vector<Eigen::Vector2d> points2D;
    std::vector<Eigen::Vector3d> points3D;
    std::vector<std::pair<int, int>> view_matches;  ///< (view, matched lifted keypoints)
};
}  // namespace

std::string toString(LocalizationMode m) { return m == LocalizationMode::Fast ? "fast" : "full"; }

LocalizationMode localizationModeFromString(const std::string& s, const std::string& input)
{
    if (s == "fast") return LocalizationMode::Fast;
    if (s == "full") return LocalizationMode::Full;
    throw core::InputError(input, "'" + s + "' is not a localization mode (fast | full)");
}

struct Localizer::Impl
{
    Impl(const Database& database, const LocalizerOptions& opts)
        : db(database), options(opts), extractor(frontend::createFeatureExtractor(database.features))
    {
        buildBuckets();
    }

    /** The ancestor at match_level of every vocabulary word (the tree is breadth-first with contiguous
     *  children, so parents follow from firstChild / numChildren), and per view the keypoints of each bucket
     *  (from the words the database stores per keypoint). */
    void buildBuckets()
    {
        const Vocabulary& voc = db.vocabulary;
        if (options.match_level == 0 || voc.empty()) return;
        const int n = voc.numNodes();
        std::vector<int> parent(size_t(n), -1), depth(size_t(n), 0);
        for (int v = 0; v < n; ++v)
            for (int c = 0; voc.firstChild(v) >= 0 && c < voc.numChildren(v); ++c)
            {
                parent[size_t(voc.firstChild(v) + c)] = v;
                depth[size_t(voc.firstChild(v) + c)] = depth[size_t(v)] + 1;
            }
        bucket_of_word.assign(voc.numWords(), 0);
        for (int v = 0; v < n; ++v)
        {
            if (voc.nodeWord(v) < 0) continue;
            int a = v;
            while (depth[size_t(a)] > options.match_level) a = parent[size_t(a)];
            bucket_of_word[size_t(voc.nodeWord(v))] = a;
        }
        view_buckets.resize(db.views.size());
        for (size_t i = 0; i < db.views.size(); ++i)
        {
            const std::vector<WordId>& words = db.views[i].words;
            for (size_t k = 0; k < words.size(); ++k) view_buckets[i][bucket_of_word[words[k]]].push_back(int(k));
        }
    }

    /** Matches the query with view `vid`: within vocabulary buckets (match_level), or all pairs. */
    std::vector<frontend::PointMatch> matchView(int vid) const
    {
        const frontend::Features& view = db.views[size_t(vid)].points;
        if (bucket_of_word.empty()) return frontend::matchPoints(query, view, options.matching);
        frontend::SearchRegion region;
        region.train_subsets.resize(query.size());
        const auto& buckets = view_buckets[size_t(vid)];
        for (size_t q = 0; q < query.size(); ++q)
            if (auto it = buckets.find(query_buckets[q]); it != buckets.end()) region.train_subsets[q] = it->second;
        return frontend::matchPoints(query, view, options.matching, &region);
    }

    /** Groups of the retrieved views (step 3), best summed score first. */
    std::vector<GroupReport> groupViews(std::vector<RetrievedView>& retrieved) const
    {
        std::vector<GroupReport> groups;
        std::vector<int> seed;  // the view that founded each group
        const double cos_heading = std::cos(options.group_heading_deg * kDegToRad);
        for (auto& r : retrieved)
        {
            const DatabaseView& v = db.views[size_t(r.view)];
            for (size_t g = 0; g < groups.size() && r.group < 0; ++g)
            {
                const DatabaseView& s = db.views[size_t(seed[g])];
                if ((viewPosition(v) - viewPosition(s)).norm() <= options.group_radius_m &&
                    viewForward(v).dot(viewForward(s)) >= cos_heading)
                    r.group = int(g);
            }
            if (r.group < 0)
            {
                r.group = int(groups.size());
                groups.emplace_back();
                seed.push_back(r.view);
            }
            groups[size_t(r.group)].views.push_back(r.view);
            groups[size_t(r.group)].score += r.score;
        }
        std::vector<int> order(groups.size());
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return groups[a].score > groups[b].score; });
        std::vector<int> new_index(groups.size());
        std::vector<GroupReport> sorted;
        for (size_t k = 0; k < order.size(); ++k)
        {
            new_index[size_t(order[k])] = int(k);
            sorted.push_back(std::move(groups[size_t(order[k])]));
            sorted.back().matched = -1;
        }
        for (auto& r : retrieved) r.group = new_index[size_t(r.group)];
        return sorted;
    }

    /** Steps 4-5 for one group: match its best views, vote, return the correspondences. */
    GroupCorrespondences matchGroup(const GroupReport& group) const
    {
        struct Candidate
        {
            Eigen::Vector3f p;
            float similarity;
        };
        std::map<int, std::vector<Candidate>> per_query;
        GroupCorrespondences out;
        const int n = std::min<int>(options.views_per_group, int(group.views.size()));
        for (int k = 0; k < n; ++k)
        {
            const int vid = group.views[size_t(k)];
            const DatabaseView& v = db.views[size_t(vid)];
            int lifted = 0;
            for (const auto& m : matchView(vid))
                if (v.lifted(size_t(m.train)))
                {
                    per_query[m.query].push_back({v.points_world[size_t(m.train)], m.similarity});
                    ++lifted;
                }
            out.view_matches.emplace_back(vid, lifted);
        }
        const float r2 = float(options.voting_radius_m * options.voting_radius_m);
        std::vector<int> votes_of;
        for (const auto& [q, cands] : per_query)
        {
            size_t best = 0;
            int best_votes = -1;
            for (size_t a = 0; a < cands.size(); ++a)
            {
                int votes = 0;
                for (const auto& b : cands) votes += (cands[a].p - b.p).squaredNorm() <= r2 ? 1 : 0;
                if (votes > best_votes || (votes == best_votes && cands[a].similarity > cands[best].similarity))
                {
                    best = a;
                    best_votes = votes;
                }
            }
            const auto& kp = query.keypoints[size_t(q)].pt;
            out.points2D.emplace_back(kp.x, kp.y);
            out.points3D.push_back(cands[best].p.cast<double>());
            votes_of.push_back(best_votes);
        }
        // Correspondences that several views agree on are far more often right (a wrong match rarely lands on
        // the same map point twice): keep only those when there are enough of them.
        const auto confirmed =
            std::count_if(votes_of.begin(), votes_of.end(), [&](int v) { return v >= options.min_votes; });
        if (options.min_votes > 1 && confirmed >= options.min_group_matches)
        {
            size_t w = 0;
            for (size_t i = 0; i < votes_of.size(); ++i)
                if (votes_of[i] >= options.min_votes)
                {
                    out.points2D[w] = out.points2D[i];
                    out.points3D[w] = out.points3D[i];
                    ++w;
                }
            out.points2D.resize(w);
            out.points3D.resize(w);
        }
        return out;
    }

    /** Re-ranks groups [0, n) that are not yet, PnP on the best pnp_groups, decides. */
    void evaluate(int n, const core::CameraModel& camera, LocalizationReport& r)
    {
        n = std::min<int>(n, int(r.groups.size()));
        auto t0 = Clock::now();
        std::vector<int> todo;
        for (int g = 0; g < n; ++g)
            if (r.groups[size_t(g)].matched < 0) todo.push_back(g);
        std::vector<GroupCorrespondences> found(todo.size());
        cv::parallel_for_(cv::Range(0, int(todo.size())), [&](const cv::Range& range) {
            for (int k = range.start; k < range.end; ++k) found[size_t(k)] = matchGroup(r.groups[size_t(todo[k])]);
        });
        for (size_t k = 0; k < todo.size(); ++k)
        {
            r.groups[size_t(todo[k])].matched = int(found[k].points2D.size());
            correspondences[todo[k]] = std::move(found[k]);
            for (const auto& [vid, count] : correspondences[todo[k]].view_matches)
                for (auto& rv : r.retrieved)
                    if (rv.view == vid) rv.matches = count;
        }
        r.ms.rerank += msSince(t0);

        t0 = Clock::now();
        std::vector<int> ranked;
        for (int g = 0; g < n; ++g)
            if (r.groups[size_t(g)].matched >= options.min_group_matches) ranked.push_back(g);
        std::stable_sort(ranked.begin(), ranked.end(),
                         [&](int a, int b) { return r.groups[size_t(a)].matched > r.groups[size_t(b)].matched; });
        ranked.resize(std::min<size_t>(ranked.size(), size_t(options.pnp_groups)));
        std::vector<int> pnp_todo;
        for (int g : ranked)
            if (r.groups[size_t(g)].inliers < 0) pnp_todo.push_back(g);
        const estimation::AbsolutePoseOptions po = options.pnpOptions();
        cv::parallel_for_(cv::Range(0, int(pnp_todo.size())), [&](const cv::Range& range) {
            for (int k = range.start; k < range.end; ++k)
            {
                GroupReport& g = r.groups[size_t(pnp_todo[size_t(k)])];
                const GroupCorrespondences& c = correspondences.at(pnp_todo[size_t(k)]);
                Eigen::Isometry3d T_cam_world;
                estimation::AbsolutePoseStats st;
                g.inliers = estimation::estimateAbsolutePose(po, c.points2D, c.points3D, camera, &T_cam_world, &st)
                                ? st.num_inliers
                                : 0;
                if (g.inliers > 0) g.T_world_cam = T_cam_world.inverse();
            }
        });
        r.ms.pnp += msSince(t0);
        decide(ranked, r);
    }

    /** Step 7. */
    void decide(const std::vector<int>& hypotheses, LocalizationReport& r) const
    {
        r.localized = false;
        int best = -1;
        for (int g : hypotheses)
            if (r.groups[size_t(g)].inliers > 0 &&
                (best < 0 || r.groups[size_t(g)].inliers > r.groups[size_t(best)].inliers))
                best = g;
        if (best < 0)
        {
            r.reason = hypotheses.empty() ? "no group with " + std::to_string(options.min_group_matches) +
                                                " or more 2D-3D correspondences"
                                          : "PnP found no pose";
            return;
        }
        const GroupReport& b = r.groups[size_t(best)];
        r.best_group = best;
        r.inliers = b.inliers;
        r.correspondences = b.matched;
        r.T_world_cam = b.T_world_cam;
        if (b.inliers < options.min_inliers)
        {
            r.reason = "best hypothesis has " + std::to_string(b.inliers) + " inliers (< min_inliers " +
                       std::to_string(options.min_inliers) + ")";
            return;
        }
        if (b.inliers < options.min_inlier_ratio * b.matched)
        {
            r.reason = "best hypothesis has " + std::to_string(b.inliers) + " inliers of " + std::to_string(b.matched) +
                       " correspondences (< min_inlier_ratio)";
            return;
        }
        double nearest = 1e300;
        for (int vid : b.views)
            nearest = std::min(nearest, (viewPosition(db.views[size_t(vid)]) - b.T_world_cam.translation()).norm());
        if (nearest > options.max_distance_to_views_m)
        {
            r.reason =
                "the pose lies " + std::to_string(nearest) + " m from its group's views (> max_distance_to_views_m)";
            return;
        }
        for (int g : hypotheses)
        {
            const GroupReport& o = r.groups[size_t(g)];
            if (g == best || o.inliers <= 0) continue;
            if ((o.T_world_cam.translation() - b.T_world_cam.translation()).norm() > options.ambiguity_distance_m &&
                o.inliers >= options.ambiguity_ratio * b.inliers)
            {
                r.reason = "ambiguous: group " + std::to_string(g) + " has " + std::to_string(o.inliers) +
                           " inliers at a pose " +
                           std::to_string((o.T_world_cam.translation() - b.T_world_cam.translation()).norm()) +
                           " m away (best " + std::to_string(b.inliers) + ")";
                return;
            }
        }
        r.localized = true;
        r.reason.clear();
    }

    const Database& db;
    LocalizerOptions options;
    std::unique_ptr<frontend::FeatureExtractor> extractor;
    frontend::Features query;
    cv::Mat blurred;
    std::vector<int> bucket_of_word;                                      ///< word -> node at match_level
    std::vector<std::unordered_map<int, std::vector<int>>> view_buckets;  ///< per view: node -> keypoints
    std::vector<int> query_buckets;                                       ///< per query keypoint
    std::map<int, GroupCorrespondences> correspondences;                  ///< per group, for the current query
};

Localizer::Localizer(const Database& db, const LocalizerOptions& options)
{
    options.check("Localizer options");
    core::require(!db.views.empty(), "the database", "has no views");
    impl_ = std::make_unique<Impl>(db, options);
}

Localizer::~Localizer() = default;

LocalizationReport Localizer::localize(const cv::Mat& gray, const core::CameraModel& camera, LocalizationMode mode)
{
    core::require(!gray.empty() && gray.type() == CV_8UC1, "the query image",
                  "must be a non-empty 8-bit grayscale image");
    camera.check("the query camera");
    core::require(gray.cols == camera.width && gray.rows == camera.height, "the query image",
                  "is " + std::to_string(gray.cols) + "x" + std::to_string(gray.rows) + " but the camera model " +
                      std::to_string(camera.width) + "x" + std::to_string(camera.height));
    Impl& m = *impl_;
    const LocalizerOptions& o = m.options;
    LocalizationReport r;
    m.correspondences.clear();
    const auto t_start = Clock::now();

    auto t0 = Clock::now();
    preprocessImage(gray, m.db.image_blur_sigma_px, m.blurred);
    m.extractor->extract(m.blurred, cv::Mat(), m.query);
    r.query_keypoints = int(m.query.size());
    r.ms.extract = msSince(t0);

    t0 = Clock::now();
    const std::vector<WordId> query_words = m.db.vocabulary.words(m.query.descriptors);  // descended once
    m.query_buckets.clear();
    if (!m.bucket_of_word.empty())
        for (WordId w : query_words) m.query_buckets.push_back(m.bucket_of_word[w]);
    const int first = mode == LocalizationMode::Fast ? o.fast_groups : o.full_groups;
    const int second = mode == LocalizationMode::Fast ? o.fast_groups_retry : o.full_groups_retry;
    for (const auto& hit : m.db.index.query(m.db.vocabulary.bowVector(query_words), o.retrieval_per_group * second))
        r.retrieved.push_back({hit.image, hit.score, -1, -1});
    r.groups = m.groupViews(r.retrieved);
    r.ms.retrieval = msSince(t0);

    if (r.groups.empty())
        r.reason = "no database view shares a visual word with the query";
    else
    {
        m.evaluate(first, camera, r);
        if (!r.localized && second > first && int(r.groups.size()) > first)
        {
            r.retried = true;
            m.evaluate(second, camera, r);
        }
    }
    r.ms.total = msSince(t_start);
    return r;
}

std::string describe(const LocalizationReport& r, const Database& db)
{
    std::ostringstream s;
    s << (r.localized ? "localized" : "not localized: " + r.reason) << "\n";
    if (r.best_group >= 0)
    {
        const auto& t = r.T_world_cam.translation();
        s << "  pose (best group " << r.best_group << "): t = [" << t.x() << " " << t.y() << " " << t.z()
          << "], inliers " << r.inliers << " of " << r.correspondences << "\n";
    }
    s << "  query keypoints " << r.query_keypoints << (r.retried ? ", retried with the larger budget" : "") << "\n";
    s << "  times ms: extract " << r.ms.extract << ", retrieval " << r.ms.retrieval << ", rerank " << r.ms.rerank
      << ", pnp " << r.ms.pnp << ", total " << r.ms.total << "\n";
    s << "  groups (retrieval order): id score views matched inliers\n";
    for (size_t g = 0; g < r.groups.size(); ++g)
    {
        const auto& gr = r.groups[g];
        if (gr.matched < 0) continue;
        s << "    " << g << " " << gr.score << " [";
        for (size_t k = 0; k < gr.views.size(); ++k) s << (k ? " " : "") << gr.views[k];
        s << "] " << gr.matched << " " << gr.inliers << "\n";
    }
    s << "  retrieved views: view score group matches x y z\n";
    for (const auto& rv : r.retrieved)
    {
        const auto& p = db.views[size_t(rv.view)].T_world_cam;
        s << "    " << rv.view << " " << rv.score << " " << rv.group << " " << rv.matches << " " << p.x() << " "
          << p.y() << " " << p.z() << "\n";
    }
    return s.str();
}

}  // namespace quasiloc::reloc
