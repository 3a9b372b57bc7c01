#include "line_profile.h"

#include "cost_profile.h"

#include <opencv2/imgproc.hpp>
#include <quasiloc/core/pose.h>
#include <quasiloc/tracking/map_lines.h>

namespace quasiloc::bench
{
LineProfile profileMapLines(const CrossModalSequence& seq, quasi::QuasiRenderer& renderer,
                            const frontend::LineOptions& lines, double window_px, double step_m, double step_deg)
{
    LineProfile p;
    tracking::MapLineOptions mo;
    tracking::MapLineExtractor extractor(seq.camera, mo, lines);
    frontend::LineDetector camera_detector(lines);
    quasi::QuasiImage q;
    for (const QueryFrame& fr : seq.frames)
    {
        renderer.render(core::fromIsometry(fr.T_world_cam), seq.camera, q);
        const std::vector<tracking::MapLine> map = extractor.mapLines(q.depth, fr.T_world_cam);
        cv::Mat gray = fr.image;
        if (gray.channels() == 3) cv::cvtColor(fr.image, gray, cv::COLOR_BGR2GRAY);
        const std::vector<frontend::LineSegment> camera = camera_detector.detect(gray);
        p.camera_segments += double(camera.size());
        p.map_lines += double(map.size());
        const size_t at_truth =
            tracking::associateMapLines(camera, map, seq.camera, fr.T_world_cam, window_px, 1.0, mo).size();
        p.associated_at_truth += double(at_truth);
        for (int k = 0; k < 12; ++k)
        {
            const Eigen::Isometry3d T = fr.T_world_cam * axisStep(k, step_m, step_deg);
            const size_t away = tracking::associateMapLines(camera, map, seq.camera, T, window_px, 1.0, mo).size();
            p.associated_one_step += double(away);
            ++p.steps;
            p.truth_more += at_truth > away;
        }
    }
    const double n = std::max<double>(1, double(seq.frames.size()));
    p.camera_segments /= n, p.map_lines /= n, p.associated_at_truth /= n;
    p.associated_one_step /= std::max(1, p.steps);
    return p;
}
}  // namespace quasiloc::bench
