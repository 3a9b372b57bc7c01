// Fuzz target: the YAML readers (all on yaml-cpp, core/yaml_read.h): EuRoC camera sensor.yaml (camera model, then
// the rig's T_BS), EuRoC imu0 sensor.yaml, and Kalibr camchain / imu YAML. The same bytes go to each.
#include <quasiloc/core/camera_model.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/kalibr.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "sensor.yaml");
    fuzz::expectCleanError([&] { (void)core::CameraModel::fromEurocYaml(path); });
    fuzz::expectCleanError([&] { (void)core::StereoRig::fromEuroc(path, path); });
    fuzz::expectCleanError([&] { (void)dataset::imuCalibrationFromYaml(path); });
    fuzz::expectCleanError([&] { (void)dataset::stereoRigFromKalibr(path); });
    fuzz::expectCleanError([&] { (void)dataset::imuCalibrationFromKalibr(path); });
    return 0;
}
