// rawlog-quasi: renders a quasi-image at every camera frame of a rawlog (ground-truth pose) and writes a
// rawlog with the quasi-images (CObservationImage, label "quasi") beside the camera images.
#include <cstdio>
#include <filesystem>
#include <quasiloc/core/program_options.h>
#include <quasiloc/quasi/rawlog_quasi.h>

using namespace quasiloc;

int main(int argc, char** argv)
{
    const char* usage =
        "Usage: rawlog-quasi <config.ini> [--set Section.key=value]... [--print-timing]\n"
        "Sections: [RawlogQuasi] (input_rawlog, map_file, groundtruth, output_rawlog, png_dir, ...) and\n"
        "[QuasiImage] (renderer options). See libs/quasi/include/quasiloc/quasi/rawlog_quasi.h.";
    return core::runProgram(argc, argv, usage, [](const core::CommandLine& cmd) {
        const auto cfg = core::loadConfig(cmd);
        quasi::RawlogQuasiOptions options;
        quasi::QuasiOptions quasi_options;
        core::loadOptionsChecked(options, cfg, "RawlogQuasi", cmd.config_path);
        core::loadOptionsChecked(quasi_options, cfg, "QuasiImage", cmd.config_path);
        mrpt::config::CConfigFileMemory effective;
        options.saveToConfigFile(effective, "RawlogQuasi");
        quasi_options.saveToConfigFile(effective, "QuasiImage");
        const auto r = quasi::runRawlogQuasi(options, quasi_options,
                                             "# rawlog-quasi effective configuration\n" + effective.getContent());
        std::printf("observations copied: %zu (stereo frames %zu)\n", r.observations_copied, r.stereo_frames);
        std::printf("quasi-images written: %zu (frames without pose: %zu)\n", r.quasi_images, r.frames_without_pose);
        std::printf("render time: mean %.2f ms, max %.2f ms\n", r.mean_render_ms, r.max_render_ms);
        std::printf("provenance reprojection error: sparse max %.4f px, completed max %.4f px\n", r.max_sparse_error_px,
                    r.max_completed_error_px);
        if (r.pngs_written) std::printf("PNGs written: %zu in %s\n", r.pngs_written, options.png_dir.c_str());
        std::printf("output: %s\n", options.output_rawlog.c_str());
        for (const auto& w : r.warnings) std::printf("warning: %s\n", w.c_str());
        if (cmd.print_timing) std::printf("%s", r.timing_table.c_str());
        return 0;
    });
}
