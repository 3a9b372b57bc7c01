// Static initialization: the gyroscope bias and the up direction from a standing IMU that vibrates like a real
// one; the detector refuses a moving one.
#include <gtest/gtest.h>

#include <quasiloc/tracking/static_initialization.h>
#include <random>

using namespace quasiloc;

namespace
{
const Eigen::Vector3d kGyroBias(-0.0023, 0.0249, 0.0817);  // EuRoC V1_01's ground-truth gyroscope bias, rad/s
const Eigen::Vector3d kUpBody = Eigen::Vector3d(0.93, 0.01, -0.37).normalized();  // V1_01 standing

/** 200 Hz standing samples over `seconds`: EuRoC white noise (ADIS16448 densities) plus rotor vibration at 37 and
 *  83 Hz of the amplitudes seen on V1_01's ground (0.05 rad/s, 0.8 m/s^2); `rate` is added to the gyroscope
 *  (zero: standing). */
std::vector<dataset::ImuSample> imuSamples(double seconds, const std::function<Eigen::Vector3d(double)>& rate)
{
    std::mt19937 rng(7);
    std::normal_distribution<double> n(0, 1);
    const double dt = 0.005, sg = 1.6968e-4 / std::sqrt(dt), sa = 2e-3 / std::sqrt(dt);
    std::vector<dataset::ImuSample> out;
    for (int k = 0; k * dt < seconds; ++k)
    {
        const double t = 100 + k * dt;
        const Eigen::Vector3d vib(std::sin(2 * M_PI * 37 * t), std::sin(2 * M_PI * 83 * t + 1),
                                  std::cos(2 * M_PI * 37 * t));
        dataset::ImuSample s;
        s.t = t;
        s.gyro = kGyroBias + rate(t) + 0.05 * vib + sg * Eigen::Vector3d(n(rng), n(rng), n(rng));
        s.acc = 9.81 * kUpBody + 0.8 * vib + sa * Eigen::Vector3d(n(rng), n(rng), n(rng));
        out.push_back(s);
    }
    return out;
}

Eigen::Vector3d standing(double) { return Eigen::Vector3d::Zero(); }
}  // namespace

TEST(StaticInitialization, RecoversAnEurocGyroscopeBiasFromTwoSecondsOfStandingData)
{
    const auto samples = imuSamples(2.0, standing);
    std::string why;
    const auto e = tracking::staticImuEstimate(samples, 1.6968e-4, {}, &why);
    ASSERT_TRUE(e) << why;
    EXPECT_LT((e->gyro_bias - kGyroBias).cwiseAbs().maxCoeff(), 0.002) << e->gyro_bias.transpose();
    EXPECT_LT(e->gyro_bias_sigma, 0.002);
    EXPECT_LT(std::acos(e->mean_specific_force.normalized().dot(kUpBody)) * 180 / M_PI, 0.5);
}

TEST(StaticInitialization, TheDetectorRefusesAPlatformThatTurns)
{
    // A slow turn (0.1 rad/s, reversing every second) is motion, however small the vibration.
    const auto samples = imuSamples(2.0, [](double t) { return Eigen::Vector3d(0, 0, 0.1 * std::sin(M_PI * t)); });
    std::string why;
    EXPECT_FALSE(tracking::staticImuEstimate(samples, 1.6968e-4, {}, &why));
    EXPECT_NE(why.find("moving"), std::string::npos) << why;
}

TEST(StaticInitialization, KeepsTheStandingSpanOnceThePlatformMoves)
{
    auto samples = imuSamples(3.0, [](double t) { return Eigen::Vector3d(0, t > 101.5 ? 0.3 : 0.0, 0); });
    tracking::StaticInitializer init(1.6968e-4);
    for (size_t i = 0; i < samples.size(); i += 10)
        init.add({samples.begin() + long(i), samples.begin() + long(std::min(samples.size(), i + 10))});
    EXPECT_TRUE(init.moved());
    ASSERT_TRUE(init.estimate());
    EXPECT_LT((init.estimate()->gyro_bias - kGyroBias).cwiseAbs().maxCoeff(), 0.002);
    EXPECT_LT(init.estimate()->span_s, 1.6);
}

TEST(StaticInitialization, TooShortASpanGivesNoEstimate)
{
    std::string why;
    EXPECT_FALSE(tracking::staticImuEstimate(imuSamples(0.3, standing), 1.6968e-4, {}, &why));
    EXPECT_NE(why.find("span"), std::string::npos) << why;
}

TEST(StaticInitialization, TheWatchSeesEveryStandstillNotOnlyTheFirst)
{
    // Standing 2 s, turning at 0.3 rad/s for 1 s, standing 2 s: the watch (1 s span) says standing, moving, standing.
    const auto samples =
        imuSamples(5.0, [](double t) { return Eigen::Vector3d(0, t >= 102 && t < 103 ? 0.3 : 0.0, 0); });
    tracking::StandstillWatch watch(1.6968e-4, 1.0);
    std::vector<std::pair<double, bool>> said;
    for (size_t i = 0; i < samples.size(); i += 10)
    {
        const std::vector<dataset::ImuSample> frame(samples.begin() + long(i),
                                                    samples.begin() + long(std::min(samples.size(), i + 10)));
        said.emplace_back(frame.back().t, watch.add(frame));
    }
    const auto at = [&said](double t) {
        for (const auto& [t_frame, standing] : said)
            if (t_frame >= t) return standing;
        return said.back().second;
    };
    EXPECT_FALSE(at(100.5));  // less than a span yet
    EXPECT_TRUE(at(101.9));
    EXPECT_FALSE(at(102.3));  // the turn shows within a block or two
    EXPECT_FALSE(at(103.8));  // the span still holds the turn
    EXPECT_TRUE(at(104.9));
}
