#pragma once
// Static IMU initialization: when the platform stands still at the start, the mean angular rate is the gyroscope
// bias and the mean specific force points up (as OpenVINS's static initializer and Basalt's start do; VINS-Mono
// instead solves the gyroscope bias from the first frames' visual rotations).
//
// Standstill detector. Real platforms vibrate while they stand: EuRoC's MAV on the ground (V1_01, motors running)
// shows per-sample gyroscope deviations up to 0.08 rad/s and accelerometer deviations up to 1 m/s^2, so a
// per-sample variance test cannot tell standing from flying. What separates them is the low-passed signal: the
// means of consecutive blocks of block_s seconds. On V1_01's IMU (1 s windows, 0.25 s blocks) the largest block
// mean's deviation from the window mean is at most 0.013 rad/s and 0.09 m/s^2 while standing and at least
// 0.05 rad/s as soon as it moves; the bounds sit between (max_gyro_block_dev_rad_s, max_acc_block_dev_m_s2).
//
// The means leave out the last block: a motion that begins there may not show in the detector yet.
// The bias estimate's sigma: the spread of the block means over sqrt(blocks) (vibration is not white noise), at
// least the white-noise limit density / sqrt(T) and min_gyro_bias_sigma (slow drifts the blocks do not show).
#include <Eigen/Core>
#include <optional>
#include <quasiloc/dataset/frame.h>
#include <string>
#include <vector>

namespace quasiloc::tracking
{
struct StandstillOptions
{
    double min_still_s = 0.5;  ///< shortest span that counts as standing
    double block_s = 0.25;
    double max_gyro_block_dev_rad_s = 0.025;
    double max_acc_block_dev_m_s2 = 0.25;
    double min_gyro_bias_sigma = 3e-4;  ///< rad/s
    /** The standing span kept: a longer one no longer narrows the estimate (its sigma is at min_gyro_bias_sigma
     *  after about 1 s of EuRoC's noise), and the tracker re-examines the span on every frame while it stands. */
    double max_span_s = 10;
};

/** What a standing span of IMU samples tells. */
struct StaticImuEstimate
{
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();            ///< body frame, rad/s
    double gyro_bias_sigma = 0;                                     ///< rad/s, per axis
    Eigen::Vector3d mean_specific_force = Eigen::Vector3d::Zero();  ///< body frame: up times gravity (plus the
                                                                    ///< accelerometer bias)
    double span_s = 0;
};

/** The IMU biases a tracker starts from, with their uncertainty (per axis), and where they came from. */
struct ImuBiasPrior
{
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero(), acc_bias = Eigen::Vector3d::Zero();
    double gyro_sigma = 0.1, acc_sigma = 0.2;  ///< rad/s, m/s^2
    std::string source = "unknown";
};

/** The calibration's prior with the gyroscope bias (and its sigma) of a static estimate, when there is one; the
 *  accelerometer bias stays the calibration's (a standing IMU sees it only mixed with the tilt). */
ImuBiasPrior withStaticEstimate(const ImuBiasPrior& calibration, const std::optional<StaticImuEstimate>& estimate);

/** The estimate when `samples` (in time order) span at least min_still_s and stand still by the detector;
 *  otherwise nullopt and, if `why`, the reason. gyro_noise_density [rad/s/sqrt(Hz)] sets the white-noise floor. */
std::optional<StaticImuEstimate> staticImuEstimate(const std::vector<dataset::ImuSample>& samples,
                                                   double gyro_noise_density, const StandstillOptions& options,
                                                   std::string* why = nullptr);

/** Collects the samples from the start for as long as the platform stands still (the last max_span_s of them); the
 *  first span that moves ends the collection for good (a standstill later in the flight is no start). */
class StaticInitializer
{
   public:
    StaticInitializer(double gyro_noise_density, const StandstillOptions& options = {})
        : gyro_noise_density_(gyro_noise_density), options_(options)
    {}
    void add(const std::vector<dataset::ImuSample>& samples);
    /** The estimate over the samples so far, if they stand still and span min_still_s. */
    std::optional<StaticImuEstimate> estimate() const;
    bool moved() const { return moved_; }

   private:
    double gyro_noise_density_;
    StandstillOptions options_;
    std::vector<dataset::ImuSample> samples_;
    bool moved_ = false;
    std::optional<StaticImuEstimate> estimate_;
};

/** Whether the platform stands now: the detector over the last span_s of IMU samples, on every frame (where
 *  StaticInitializer looks at the start only). A robot that stops and goes stands many times; its velocity is then
 *  zero, which the IMU alone cannot tell apart from a slow drift. The detector needs the whole span standing, so a
 *  stop is seen span_s after it begins and a start within a block. */
class StandstillWatch
{
   public:
    StandstillWatch(double gyro_noise_density, double span_s, const StandstillOptions& options = {});
    /** Adds the samples since the last call (in time order); true when the last span_s of them stand still. */
    bool add(const std::vector<dataset::ImuSample>& samples);

   private:
    double gyro_noise_density_;
    double span_s_;
    StandstillOptions options_;
    std::vector<dataset::ImuSample> samples_;
};

}  // namespace quasiloc::tracking
