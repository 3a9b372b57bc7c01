// Fuzz target: the EuRoC csv readers. The same bytes as imu0/data.csv (readEurocImuCsv), as a ground-truth body csv
// (readEurocBiasCsv, readGroundTruthCam0), and as cam0/data.csv + cam1/data.csv + imu0/data.csv of an ASL folder
// whose sensor.yaml files are valid (readEurocSequence, as euroc2rawlog reads a folder).
#include <quasiloc/dataset/euroc.h>
#include <quasiloc/dataset/euroc_imu_csv.h>
#include <quasiloc/dataset/ground_truth.h>

#include "fuzz_common.h"

namespace
{
// EuRoC V1_01's cam0 sensor.yaml, shortened (T_BS: x = 0 for cam0, 0.11 m for cam1: a valid rig).
std::string cameraYaml(const char* x)
{
    return std::string(R"(%YAML:1.0
sensor_type: camera
T_BS:
  cols: 4
  rows: 4
  data: [1.0, 0.0, 0.0, )") +
           x + R"(, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]
rate_hz: 20
resolution: [752, 480]
camera_model: pinhole
intrinsics: [458.654, 457.296, 367.215, 248.375]
distortion_model: radial-tangential
distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
)";
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    static const bool yaml_written = [] {
        fuzz::writeText("asl/mav0/cam0/sensor.yaml", cameraYaml("0.0"));
        fuzz::writeText("asl/mav0/cam1/sensor.yaml", cameraYaml("0.11"));
        return true;
    }();
    (void)yaml_written;
    const std::string csv = fuzz::writeInput(data, size, "data.csv");
    fuzz::expectCleanError([&] { (void)dataset::readEurocImuCsv(csv); });
    fuzz::expectCleanError([&] { (void)dataset::readEurocBiasCsv(csv); });
    fuzz::expectCleanError([&] { (void)dataset::readGroundTruthCam0(csv, mrpt::poses::CPose3D()); });
    for (const char* sub : {"cam0", "cam1", "imu0"})
        fuzz::writeInput(data, size, std::string("asl/mav0/") + sub + "/data.csv");
    fuzz::expectCleanError([&] { (void)dataset::readEurocSequence((fuzz::scratchDir() / "asl").string()); });
    return 0;
}
