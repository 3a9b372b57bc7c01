// Fuzz target: TUM trajectories (quasiloc-eval's estimates and ground truth, the programs' ground truth).
#include <quasiloc/core/trajectory_io.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "trajectory.tum");
    fuzz::expectCleanError([&] { (void)core::readTum(path); });
    return 0;
}
