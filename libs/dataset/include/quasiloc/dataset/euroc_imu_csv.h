#pragma once
// The two EuRoC csv files with IMU-rate rows, read strictly:
//   imu0/data.csv                              t_ns, w_x, w_y, w_z [rad/s], a_x, a_y, a_z [m/s^2] (gyro first)
//   state_groundtruth_estimate0/data.csv       t_ns, p xyz, q wxyz, v xyz, b_w xyz [rad/s], b_a xyz [m/s^2]
//     (shared/data/euroc/groundtruth/body/<sequence>.csv; only the bias columns are kept here)
// Every problem is an InputError naming the file (and "<file>:<line>"): missing file, malformed line (wrong
// column count, a timestamp that is not an integer, a value that is not a finite number), a timestamp equal to
// the previous row's (duplicate) or earlier (non-monotonic), an interval longer than kMaxImuGapPeriods nominal
// periods (gap), no data row.
//
// Gap bound: 2.5 nominal periods (12.5 ms at 200 Hz): one dropped sample (2 periods) passes, two in a row do
// not. Measured: the real V1_01_easy imu0/data.csv (29,120 rows, 145.595 s) has intervals of 4.999936 ms and
// 5.000192 ms only (largest 1.00004 periods); the five ground-truth body csv files 4.99968 .. 5.000192 ms.
#include <Eigen/Core>
#include <cstdint>
#include <quasiloc/dataset/frame.h>
#include <string>
#include <vector>

namespace quasiloc::dataset
{
constexpr double kEurocImuRateHz = 200;    ///< the ADIS16448 of every EuRoC sequence
constexpr double kMaxImuGapPeriods = 2.5;  ///< an interval above this many nominal periods is an error

struct EurocImuCsv
{
    std::string path;
    std::vector<std::int64_t> t_ns;  ///< strictly increasing, parallel to samples
    std::vector<ImuSample> samples;  ///< t in seconds from t_ns
};

struct EurocBiasCsv
{
    std::string path;
    std::vector<std::int64_t> t_ns;                    ///< strictly increasing
    std::vector<Eigen::Vector3d> gyro_bias, acc_bias;  ///< b_w [rad/s], b_a [m/s^2], body (IMU) frame
};

/** imu0/data.csv. `nominal_rate_hz` (> 0) sets the gap bound. */
EurocImuCsv readEurocImuCsv(const std::string& path, double nominal_rate_hz = kEurocImuRateHz);

/** The bias columns of a ground-truth state csv (17 columns). `nominal_rate_hz` sets the gap bound. */
EurocBiasCsv readEurocBiasCsv(const std::string& path, double nominal_rate_hz = kEurocImuRateHz);

}  // namespace quasiloc::dataset
