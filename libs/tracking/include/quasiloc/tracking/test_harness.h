#pragma once
// The test harness of a tracking session: what the reliability tests do to a run that the product never does.
//   [FaultInjection]  faults in the frames the session reads (dataset/fault_injection.h): the source is wrapped;
//   [Kidnap]          the tracker restarted off its pose once, to test the loss recovery: a frame hook.
// The product program quasiloc-track reads neither section (and refuses them); quasiloc-track-harness, the unit
// tests and scripts/fault_table.py use this.
#include <memory>
#include <mrpt/config/CConfigFileBase.h>
#include <ostream>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/dataset/fault_injection.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/tracking/tracking_session.h>
#include <vector>

namespace quasiloc::tracking
{
/** [Kidnap]: off by default. */
struct KidnapOptions : public core::DeclaredOptions
{
    double kidnap_at_s = -1, kidnap_m = 1.0, kidnap_deg = 10;
    void declare(core::OptionTable& t) override;
};

struct HarnessOptions
{
    KidnapOptions kidnap;                   ///< [Kidnap]
    dataset::FaultInjectionOptions faults;  ///< [FaultInjection]

    /** Loads and checks both sections (unknown keys are errors naming `config_name`). */
    void load(const mrpt::config::CConfigFileBase& cfg, const std::string& config_name);
    std::vector<core::OptionsSection> sections() const;
};

/** `source` with the faults injected (itself when no fault is on). */
std::unique_ptr<dataset::FrameSource> withFaults(std::unique_ptr<dataset::FrameSource> source,
                                                 const dataset::FaultInjectionOptions& faults);

/** The kidnap as a frame hook: once, kidnap_at_s after the start, the tracker restarts kidnap_m to the camera's side
 *  and kidnap_deg turned about its y axis, with full confidence (a no-op hook when kidnap_at_s < 0). */
TrackingSession::FrameHook kidnapHook(const KidnapOptions& options, std::ostream& console);

/** The harness's hooks on a session (the faults are in its source: withFaults). */
void applyHarness(const HarnessOptions& options, TrackingSession& session, std::ostream& console);
}  // namespace quasiloc::tracking
