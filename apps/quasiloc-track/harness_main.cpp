// quasiloc-track-harness: quasiloc-track under the test harness (libs/tracking/test_harness.h): the same program
// with [FaultInjection] (faults in the frames it reads) and [Kidnap] (the tracker restarted off its pose once), for
// the reliability tests (tests/e2e/track_faults_short.sh, scripts/fault_table.py, docs/reliability.md). Not a
// product program: quasiloc-track refuses those sections.
//
//     quasiloc-track-harness <config.ini> [--set Section.key=value]... [--print-timing]
#include <quasiloc/core/program_options.h>

#include "track_app.h"

namespace
{
const char* kUsage =
    "usage: quasiloc-track-harness <config.ini> [--set Section.key=value]... [--print-timing]\n"
    "quasiloc-track with the test harness's [FaultInjection] and [Kidnap] sections (docs/reliability.md).";

int run(const quasiloc::core::CommandLine& cmd) { return quasiloc::app::runTrack(cmd, true); }
}  // namespace

int main(int argc, char** argv) { return quasiloc::core::runProgram(argc, argv, kUsage, run); }
