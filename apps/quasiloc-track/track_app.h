#pragma once
// quasiloc-track's run, shared by the product program (main.cpp) and its test harness (harness_main.cpp).
#include <quasiloc/core/program_options.h>

namespace quasiloc::app
{
/** Options -> session -> outputs. `harness`: the test harness's sections ([Kidnap], [FaultInjection],
 *  tracking/test_harness.h) are read and applied; without it, keys in them are an InputError. */
int runTrack(const core::CommandLine& cmd, bool harness);
}  // namespace quasiloc::app
