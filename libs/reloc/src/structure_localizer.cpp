// Global localization of one camera image by structure (structure_localizer.h).
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/estimation/absolute_pose.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/reloc/structure_localizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "structure_matching.h"
#include "structure_retrieval.h"

namespace quasiloc::reloc
{
namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

cv::Mat toGray(const cv::Mat& image)
{
    cv::Mat gray;
    if (image.channels() == 3)
        cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    else
        gray = image;
    return gray;
}

/** A view's retrieval score at its best shift. */
struct ViewScore
{
    int view = -1;
    GridShift shift;
};
}  // namespace

struct StructureLocalizer::Impl
{
    const map::LidarMap& map;
    StructureLocalizerOptions o;
    core::CameraModel camera, coarse_camera;
    quasi::QuasiRenderer renderer;
    std::vector<Eigen::Isometry3d> views;
    std::vector<std::array<OrientationGrid, 2>> view_grids;  ///< rank-equalised reflectivity, depth edges
    frontend::CrossModalDescriptorOptions descriptors;
    double setup_s = 0;
    StructureDiagnostics last;
    LocalizationReport last_report;

    Impl(const map::LidarMap& m, const std::vector<mrpt::poses::CPose3D>& T_world_views, const core::CameraModel& c,
         const quasi::QuasiOptions& q, const StructureLocalizerOptions& options)
        : map(m), o(options), camera(c), coarse_camera(c.downscaled(options.downscale)), renderer(m, q)
    {
        const auto t0 = Clock::now();
        quasi::QuasiImage image;
        for (const auto& T : T_world_views)
        {
            views.push_back(core::toIsometry(T));
            renderer.render(T, coarse_camera, image, false);
            const std::vector<cv::Mat> channels = structureChannels(image, o);
            view_grids.push_back({orientationGrid(channels[0], image.valid, coarseCell(), descriptors),
                                  orientationGrid(channels[1], image.valid, coarseCell(), descriptors)});
        }
        setup_s = msSince(t0) * 1e-3;
    }

    int coarseCell() const { return std::max(2, int(std::lround(o.cell_px / o.downscale))); }

    /** The view turned so that the camera's centre looks along the view's ray through its centre + the shift. */
    Eigen::Isometry3d guessOf(int view, const GridShift& s) const
    {
        const double cell = coarseCell() * double(o.downscale);
        const Eigen::Vector2d centre(camera.cx + s.dx * cell, camera.cy + s.dy * cell);
        const Eigen::Vector3d ray = camera.unproject(centre).normalized();
        Eigen::Isometry3d T = views[size_t(view)];
        T.linear() = T.linear() * Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), ray).toRotationMatrix();
        return T;
    }

    std::vector<ViewScore> retrieve(const cv::Mat& gray) const
    {
        cv::Mat coarse;
        cv::resize(gray, coarse, cv::Size(coarse_camera.width, coarse_camera.height), 0, 0, cv::INTER_AREA);
        const OrientationGrid cam = orientationGrid(coarse, cv::Mat(), coarseCell(), descriptors);
        std::vector<ViewScore> scores(views.size());
        for (size_t v = 0; v < views.size(); ++v)
            scores[v] = {int(v), bestGridShift(cam, {&view_grids[v][0], &view_grids[v][1]}, o.max_shift_x_cells,
                                               o.max_shift_y_cells, o.min_overlap)};
        const bool peak = o.retrieval_score == StructureRetrievalScore::Peak;
        std::stable_sort(scores.begin(), scores.end(), [peak](const ViewScore& a, const ViewScore& b) {
            return peak ? a.shift.peak > b.shift.peak : a.shift.score > b.shift.score;
        });
        return scores;
    }

    /** The best guesses, each at least the separation away from the better ones. */
    std::vector<StructureCandidate> selectCandidates(const std::vector<ViewScore>& ranked) const
    {
        std::vector<StructureCandidate> out;
        const double sep_rad = o.candidate_separation_deg * M_PI / 180;
        for (const ViewScore& s : ranked)
        {
            if (int(out.size()) >= o.candidates) break;
            if (s.shift.score <= -2) continue;
            StructureCandidate c;
            c.view = s.view;
            c.retrieval_score = o.retrieval_score == StructureRetrievalScore::Peak ? s.shift.peak : s.shift.score;
            c.T_world_guess = guessOf(s.view, s.shift);
            bool near = false;
            for (const StructureCandidate& k : out)
                near =
                    near || (core::translationDistance(k.T_world_guess, c.T_world_guess) < o.candidate_separation_m &&
                             core::rotationDistanceRad(k.T_world_guess, c.T_world_guess) < sep_rad);
            if (!near) out.push_back(c);
        }
        return out;
    }

    /** Match, lift, PnP per iteration; the guess moves when the PnP has min_step_inliers. */
    void refine(StructureCandidate& c, const frontend::DescriptorField& camera_field, double& ms_match, double& ms_pnp)
    {
        Eigen::Isometry3d guess = c.T_world_guess;
        quasi::QuasiImage q;
        estimation::AbsolutePoseOptions po;
        po.max_reproj_error_px = o.pnp_reproj_px;
        po.max_iterations = o.pnp_max_iterations;
        po.min_inliers = 4;
        for (size_t it = 0; it < o.iteration_sigma_m.size(); ++it)
        {
            auto t0 = Clock::now();
            renderer.render(core::fromIsometry(guess), camera, q, false);
            const GuessCorrespondences all = matchAtGuess(camera_field, q, map, camera, o.iteration_sigma_m[it],
                                                          o.iteration_sigma_deg[it] * M_PI / 180, o);
            const GuessCorrespondences m = consensusOfDisplacements(all, all.guess_px, o.consensus_px);
            ms_match += msSince(t0);
            t0 = Clock::now();
            c.matches = int(m.camera_px.size());
            c.inliers = 0;
            Eigen::Isometry3d T_cam_world;
            estimation::AbsolutePoseStats stats;
            const bool ok = c.matches >= 4 &&
                            estimation::estimateAbsolutePose(po, m.camera_px, m.p_world, camera, &T_cam_world, &stats);
            ms_pnp += msSince(t0);
            if (!ok || stats.num_inliers < o.min_step_inliers) break;
            c.inliers = stats.num_inliers;
            guess = T_cam_world.inverse();
            ++c.iterations;
        }
        c.T_world_cam = guess;
    }

    void fillTruth(const Eigen::Isometry3d& truth, const std::vector<ViewScore>& ranked)
    {
        for (StructureCandidate& c : last.candidates)
        {
            c.guess_error_m = core::translationDistance(c.T_world_guess, truth);
            c.guess_error_deg = core::rotationDistanceRad(c.T_world_guess, truth) * 180 / M_PI;
            c.error_m = core::translationDistance(c.T_world_cam, truth);
            c.error_deg = core::rotationDistanceRad(c.T_world_cam, truth) * 180 / M_PI;
        }
        double nearest = INFINITY;
        for (size_t v = 0; v < views.size(); ++v)
        {
            const double d = (views[v].translation() - truth.translation()).norm() +
                             0.5 * core::rotationDistanceRad(views[v], truth);  // 1 m ~ 2 rad
            if (d < nearest) nearest = d, last.nearest_view = int(v);
        }
        for (size_t rank = 0; rank < ranked.size(); ++rank)
        {
            const Eigen::Isometry3d g = guessOf(ranked[rank].view, ranked[rank].shift);
            if (last.first_good_rank < 0 && core::translationDistance(g, truth) < 0.5 &&
                core::rotationDistanceRad(g, truth) < 10 * M_PI / 180)
                last.first_good_rank = int(rank);
            if (ranked[rank].view == last.nearest_view)
            {
                last.nearest_view_rank = int(rank);
                last.nearest_guess_error_m = core::translationDistance(g, truth);
                last.nearest_guess_error_deg = core::rotationDistanceRad(g, truth) * 180 / M_PI;
            }
        }
    }

    LocalizationReport localize(const cv::Mat& image, const Eigen::Isometry3d* truth)
    {
        const auto t_all = Clock::now();
        LocalizationReport r;
        last = {};
        auto t0 = Clock::now();
        const cv::Mat gray = toGray(image);
        const frontend::DescriptorField camera_field =
            frontend::computeDescriptorField(gray, frontend::DescriptorKind::OrientationField, descriptors);
        r.ms.extract = msSince(t0);
        t0 = Clock::now();
        const std::vector<ViewScore> ranked = retrieve(gray);
        last.candidates = selectCandidates(ranked);
        r.ms.retrieval = msSince(t0);
        for (StructureCandidate& c : last.candidates) refine(c, camera_field, r.ms.rerank, r.ms.pnp);
        if (truth) fillTruth(*truth, ranked);
        decide(r);
        r.ms.total = msSince(t_all);
        last_report = r;
        return r;
    }

    void decide(LocalizationReport& r) const
    {
        const int n_it = int(o.iteration_sigma_m.size());
        const StructureCandidate* best = nullptr;
        for (const StructureCandidate& c : last.candidates)
            if (c.iterations == n_it && (!best || c.inliers > best->inliers)) best = &c;
        if (!best)
        {
            r.reason = last.candidates.empty() ? "no view retrieved" : "no candidate converged";
            return;
        }
        r.T_world_cam = best->T_world_cam;
        r.inliers = best->inliers;
        r.correspondences = best->matches;
        r.best_group = int(best - last.candidates.data());
        if (best->inliers < o.min_inliers)
            r.reason = "too few inliers (" + std::to_string(best->inliers) + ")";
        else if (best->inliers < o.min_inlier_ratio * best->matches)
            r.reason =
                "inlier ratio too low (" + std::to_string(best->inliers) + "/" + std::to_string(best->matches) + ")";
        else
            r.localized = true;
    }
};

StructureLocalizer::StructureLocalizer(const map::LidarMap& map, const std::vector<mrpt::poses::CPose3D>& T_world_views,
                                       const core::CameraModel& camera, const quasi::QuasiOptions& quasi_options,
                                       const StructureLocalizerOptions& options)
{
    options.check("StructureLocalizer");
    core::require(!T_world_views.empty(), "StructureLocalizer", "no view to localize against");
    impl_ = std::make_unique<Impl>(map, T_world_views, camera, quasi_options, options);
}

StructureLocalizer::~StructureLocalizer() = default;

LocalizationReport StructureLocalizer::localize(const cv::Mat& image, const Eigen::Isometry3d* T_world_cam_truth)
{
    return impl_->localize(image, T_world_cam_truth);
}

const StructureDiagnostics& StructureLocalizer::lastDiagnostics() const { return impl_->last; }

std::string StructureLocalizer::summary() const
{
    std::ostringstream s;
    s << impl_->views.size() << " views rendered and described in " << impl_->setup_s << " s ("
      << impl_->coarse_camera.width << "x" << impl_->coarse_camera.height << ", grid "
      << impl_->view_grids.front()[0].cols << "x" << impl_->view_grids.front()[0].rows << " cells)";
    return s.str();
}

std::string StructureLocalizer::describeLast() const
{
    const StructureDiagnostics& d = impl_->last;
    const LocalizationReport& r = impl_->last_report;
    std::ostringstream s;
    s.precision(3);
    s << (r.localized ? "localized" : "not localized: " + r.reason) << "; inliers " << r.inliers << "/"
      << r.correspondences;
    if (d.nearest_view >= 0)
        s << "; retrieval: first guess within 0.5 m / 10 deg at rank " << d.first_good_rank << ", nearest view "
          << d.nearest_view << " at rank " << d.nearest_view_rank << " (its guess " << d.nearest_guess_error_m
          << " m / " << d.nearest_guess_error_deg << " deg off)";
    for (const StructureCandidate& c : d.candidates)
    {
        s << "\n    view " << c.view << " score " << c.retrieval_score << ": iterations " << c.iterations
          << ", matches " << c.matches << ", inliers " << c.inliers;
        if (std::isfinite(c.error_m))
            s << ", guess " << c.guess_error_m << " m / " << c.guess_error_deg << " deg -> " << c.error_m << " m / "
              << c.error_deg << " deg";
    }
    return s.str();
}

}  // namespace quasiloc::reloc
