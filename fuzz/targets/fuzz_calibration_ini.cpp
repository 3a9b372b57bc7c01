// Fuzz target: the calibration INI every program reads (stereo rig and [imu]) through loadCalibration.
#include <quasiloc/dataset/calibration.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "calibration.ini");
    fuzz::expectCleanError([&] { (void)dataset::loadCalibration(path); });
    return 0;
}
