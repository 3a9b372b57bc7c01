#include <iomanip>
#include <quasiloc/core/error.h>
#include <quasiloc/tracking/test_harness.h>

namespace quasiloc::tracking
{
using core::Range;

void KidnapOptions::declare(core::OptionTable& t)
{
    t.add("kidnap_at_s", kidnap_at_s, "s", Range::any(),
          "a test of loss recovery: this long after the start the tracker is restarted off its pose (< 0: never)");
    t.add("kidnap_m", kidnap_m, "m", Range::any(), "to its side by this");
    t.add("kidnap_deg", kidnap_deg, "deg", Range::any(), "turned by this about the camera's y axis");
}

void HarnessOptions::load(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name)
{
    core::loadOptionsChecked(kidnap, cfg, "Kidnap", config_name);
    core::loadOptionsChecked(faults, cfg, "FaultInjection", config_name);
}

std::vector<core::OptionsSection> HarnessOptions::sections() const
{
    return {{"Kidnap", &kidnap}, {"FaultInjection", &faults}};
}

std::unique_ptr<dataset::FrameSource> withFaults(std::unique_ptr<dataset::FrameSource> source,
                                                 const dataset::FaultInjectionOptions& faults)
{
    if (!faults.any()) return source;
    return std::make_unique<dataset::FaultInjectingSource>(std::move(source), faults);
}

TrackingSession::FrameHook kidnapHook(const KidnapOptions& options, std::ostream& console)
{
    if (options.kidnap_at_s < 0) return {};
    auto done = std::make_shared<bool>(false);
    return [options, &console, done](const FrameReport& r, TrackingSession& session) {
        if (*done || r.t < session.startTime() + options.kidnap_at_s) return;
        *done = true;
        Eigen::Isometry3d T_wrong = r.T_world_cam0;
        T_wrong.translation() += r.T_world_cam0.linear() * Eigen::Vector3d(options.kidnap_m, 0, 0);
        T_wrong.linear() =
            T_wrong.linear() *
            Eigen::AngleAxisd(options.kidnap_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
        console << "kidnapped at t " << std::fixed << std::setprecision(3) << r.t << ": restarted " << options.kidnap_m
                << " m to the side, " << options.kidnap_deg << " deg turned" << std::endl;
        session.restartTrackerAt(r.t, T_wrong);
    };
}

void applyHarness(const HarnessOptions& options, TrackingSession& session, std::ostream& console)
{
    if (auto hook = kidnapHook(options.kidnap, console)) session.setFrameHook(std::move(hook));
}
}  // namespace quasiloc::tracking
