// The IMU's bias models and the real-IMU replay: biases that follow EuRoC's ground-truth file, the random walk's
// start, which model a configuration resolves to, the real samples returned unchanged.
#include <gtest/gtest.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/sim/imu_synthesizer.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace
{
using quasiloc::core::InputError;
using quasiloc::sim::ImuBiasModel;
using quasiloc::sim::ImuBiasTrajectory;
using quasiloc::sim::ImuNoiseOptions;
using quasiloc::sim::ImuSynthesizer;
using quasiloc::sim::ImuTruth;
using quasiloc::sim::TrajectorySpline;

const std::string kShared = QUASILOC_SHARED_DIR;
const std::string kEuroc = kShared + "/data/euroc";

const TrajectorySpline& splineOf(const std::string& sequence)
{
    static std::map<std::string, TrajectorySpline> cache;
    auto it = cache.find(sequence);
    if (it == cache.end())
        it = cache
                 .emplace(sequence, TrajectorySpline::fitCameraTrajectory(
                                        quasiloc::core::readTum(kEuroc + "/groundtruth/cam0/" + sequence + ".txt"),
                                        quasiloc::core::readEurocSensorPose(kEuroc + "/calib/cam0_sensor.yaml")))
                 .first;
    return it->second;
}

/** Rows "t_ns, 16 numbers" of a ground-truth body csv, parsed here independently of the library. */
struct BiasRow
{
    long long t_ns;
    Eigen::Vector3d bg, ba;
};
std::vector<BiasRow> readBiasRows(const std::string& path)
{
    std::ifstream in(path);
    EXPECT_TRUE(in.good()) << path;
    std::vector<BiasRow> rows;
    std::string line;
    while (std::getline(in, line))
    {
        if (line.empty() || line[0] == '#') continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream ss(line);
        BiasRow r;
        double skip;
        ss >> r.t_ns;
        for (int i = 0; i < 10; ++i) ss >> skip;
        ss >> r.bg.x() >> r.bg.y() >> r.bg.z() >> r.ba.x() >> r.ba.y() >> r.ba.z();
        rows.push_back(r);
    }
    return rows;
}

/** Linear interpolation of the rows at t (rows' first / last value outside), computed here independently. */
void interpolateRows(const std::vector<BiasRow>& rows, double t, Eigen::Vector3d& bg, Eigen::Vector3d& ba)
{
    if (t <= rows.front().t_ns * 1e-9 || t >= rows.back().t_ns * 1e-9)
    {
        const BiasRow& end = t <= rows.front().t_ns * 1e-9 ? rows.front() : rows.back();
        bg = end.bg;
        ba = end.ba;
        return;
    }
    size_t i = 0;
    while (rows[i + 1].t_ns * 1e-9 <= t) ++i;
    const double w = (t - rows[i].t_ns * 1e-9) / ((rows[i + 1].t_ns - rows[i].t_ns) * 1e-9);
    bg = (1 - w) * rows[i].bg + w * rows[i + 1].bg;
    ba = (1 - w) * rows[i].ba + w * rows[i + 1].ba;
}

ImuNoiseOptions noiseless()
{
    ImuNoiseOptions o;
    o.noise_enabled = false;
    return o;
}
}  // namespace

TEST(ImuBias, BiasesEqualTheGroundTruthFileInterpolatedAtSampleTimes)
{
    const std::string path = kEuroc + "/groundtruth/body/V1_02_medium.csv";
    const auto rows = readBiasRows(path);
    const TrajectorySpline& spline = splineOf("V1_02_medium");
    const auto file = ImuBiasTrajectory::fromEuroc(quasiloc::dataset::readEurocBiasCsv(path));
    ImuNoiseOptions opt;                          // noise on: the biases are still the file's, white noise on top
    const double t0 = spline.tStart() + 20.0025;  // between the file's rows: real interpolation
    ImuSynthesizer noisy(spline, opt, file), clean(spline, noiseless(), file);
    ImuNoiseOptions zero_bias = noiseless();
    zero_bias.initial_gyro_bias.setZero();
    zero_bias.initial_acc_bias.setZero();
    ImuSynthesizer exact(spline, zero_bias);
    std::vector<ImuTruth> truth, truth_clean;
    const auto s = noisy.generate(t0, t0 + 30, &truth);
    const auto c = clean.generate(t0, t0 + 30, &truth_clean);
    const auto e = exact.generate(t0, t0 + 30);
    ASSERT_EQ(s.size(), 6001u);
    ASSERT_EQ(truth.size(), s.size());
    double max_err_g = 0, max_err_a = 0;
    Eigen::Vector3d mean_residual = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < s.size(); ++i)
    {
        Eigen::Vector3d bg, ba;
        interpolateRows(rows, s[i].t, bg, ba);
        max_err_g = std::max(max_err_g, (truth[i].gyro_bias - bg).cwiseAbs().maxCoeff());
        max_err_a = std::max(max_err_a, (truth[i].acc_bias - ba).cwiseAbs().maxCoeff());
        EXPECT_EQ(truth[i].gyro_bias, truth_clean[i].gyro_bias);
        // Noiseless: the sample is the exact one plus the file's biases.
        EXPECT_LT((c[i].gyro - e[i].gyro - bg).norm(), 1e-9);  // t ~ 1.4e9 s: weights good to ~1e-4
        EXPECT_LT((c[i].acc - e[i].acc - ba).norm(), 1e-9);
        mean_residual += (s[i].acc - e[i].acc - ba) / static_cast<double>(s.size());
    }
    std::printf(
        "[ gt bias  ] V1_02_medium 30 s: max |truth - file interpolated| gyro %.2e rad/s, acc %.2e m/s^2; "
        "bias at start gyro (%.5f %.5f %.5f) acc (%.5f %.5f %.5f), at end acc (%.5f %.5f %.5f)\n",
        max_err_g, max_err_a, truth.front().gyro_bias.x(), truth.front().gyro_bias.y(), truth.front().gyro_bias.z(),
        truth.front().acc_bias.x(), truth.front().acc_bias.y(), truth.front().acc_bias.z(), truth.back().acc_bias.x(),
        truth.back().acc_bias.y(), truth.back().acc_bias.z());
    EXPECT_LT(max_err_g, 1e-9);
    EXPECT_LT(max_err_a, 1e-9);
    // The white noise is on top, zero-mean (sigma 0.028 m/s^2 per sample, 6001 samples).
    EXPECT_LT(mean_residual.norm(), 3e-3);
    // EuRoC's biases, not zero.
    EXPECT_NEAR(truth.front().gyro_bias.z(), 0.0758, 1e-3);
}

TEST(ImuBias, BiasTrajectoryInterpolatesAndHoldsItsEnds)
{
    const ImuBiasTrajectory b({10.0, 11.0, 13.0}, {{0, 0, 0}, {1, 2, 3}, {3, 2, 1}},
                              {{0, 0, 0}, {-1, 0, 1}, {1, 0, -1}}, "test");
    Eigen::Vector3d g, a;
    b.at(5.0, g, a);  // before: the first value
    EXPECT_EQ(g, Eigen::Vector3d(0, 0, 0));
    b.at(10.5, g, a);
    EXPECT_TRUE(g.isApprox(Eigen::Vector3d(0.5, 1, 1.5)));
    EXPECT_TRUE(a.isApprox(Eigen::Vector3d(-0.5, 0, 0.5)));
    b.at(12.0, g, a);
    EXPECT_TRUE(g.isApprox(Eigen::Vector3d(2, 2, 2)));
    b.at(13.0, g, a);
    EXPECT_EQ(g, Eigen::Vector3d(3, 2, 1));
    b.at(99.0, g, a);  // after: the last value
    EXPECT_EQ(a, Eigen::Vector3d(1, 0, -1));
    EXPECT_THROW(ImuBiasTrajectory({1.0, 1.0}, {{0, 0, 0}, {0, 0, 0}}, {{0, 0, 0}, {0, 0, 0}}, "dup"), InputError);
    EXPECT_THROW(ImuBiasTrajectory({}, {}, {}, "empty"), InputError);
}

TEST(ImuBias, RandomWalkStartsAtTheConfiguredBiases)
{
    const TrajectorySpline& spline = splineOf("V1_01_easy");
    ImuNoiseOptions opt;
    EXPECT_EQ(opt.initial_gyro_bias, Eigen::Vector3d(-0.0023, 0.0249, 0.0817));  // EuRoC's, not zero
    EXPECT_EQ(opt.initial_acc_bias, Eigen::Vector3d(-0.021, 0.122, 0.079));
    opt.initial_gyro_bias = {0.01, -0.02, 0.03};
    opt.initial_acc_bias = {0.1, -0.2, 0.3};
    ImuSynthesizer synth(spline, opt);
    std::vector<ImuTruth> truth;
    const double t0 = spline.tStart() + 30;
    synth.generate(t0, t0 + 10, &truth);
    ASSERT_EQ(truth.size(), 2001u);
    EXPECT_EQ(truth.front().gyro_bias, opt.initial_gyro_bias);
    EXPECT_EQ(truth.front().acc_bias, opt.initial_acc_bias);
    // It walks: after 10 s the acc bias has moved by about random_walk * sqrt(10 s) = 0.0095 m/s^2 per axis.
    const double moved = (truth.back().acc_bias - opt.initial_acc_bias).norm();
    std::printf("[ walk     ] acc bias moved %.4f m/s^2 in 10 s (expected ~%.4f)\n", moved,
                opt.accelerometer_random_walk * std::sqrt(10.0 * 3));
    EXPECT_GT(moved, 1e-4);
    EXPECT_LT(moved, 0.1);
}

TEST(ImuBias, ResolvesTheBiasModelOfASequence)
{
    ImuNoiseOptions o;  // bias = euroc_groundtruth
    const TrajectorySpline& v102 = splineOf("V1_02_medium");
    const double t0 = v102.tStart() + 1, t1 = t0 + 5;
    auto r = quasiloc::sim::resolveImuBias(o, kShared, "V1_02_medium", t0, t1, "test.ini");
    ASSERT_TRUE(r.trajectory.has_value());
    EXPECT_NE(r.description.find("V1_02_medium.csv"), std::string::npos) << r.description;
    std::printf("[ resolve  ] V1_02_medium: %s\n", r.description.c_str());
    // V1_01 has no ground-truth bias file: the random walk from the initial biases.
    r = quasiloc::sim::resolveImuBias(o, kShared, "V1_01_easy", 1403715280.0, 1403715285.0, "test.ini");
    EXPECT_FALSE(r.trajectory.has_value());
    EXPECT_NE(r.description.find("random walk"), std::string::npos) << r.description;
    std::printf("[ resolve  ] V1_01_easy: %s\n", r.description.c_str());
    o.bias = ImuBiasModel::random_walk;
    EXPECT_FALSE(quasiloc::sim::resolveImuBias(o, kShared, "V1_02_medium", t0, t1, "test.ini").trajectory);
    // An explicit file must exist, and be on the simulated clock.
    o.bias = ImuBiasModel::euroc_groundtruth;
    o.bias_file = "/nonexistent/body.csv";
    EXPECT_THROW(quasiloc::sim::resolveImuBias(o, kShared, "V1_02_medium", t0, t1, "test.ini"), InputError);
    o.bias_file = kEuroc + "/groundtruth/body/V2_01_easy.csv";
    try
    {
        quasiloc::sim::resolveImuBias(o, kShared, "V1_02_medium", t0, t1, "test.ini");
        ADD_FAILURE() << "a bias file on another clock accepted";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("V2_01_easy.csv"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("no overlap"), std::string::npos) << e.what();
    }
}

TEST(ImuBias, RealReplayReturnsTheFileSamplesExactly)
{
    const std::string path = kEuroc + "/V1_01_easy_micro/mav0/imu0/data.csv";
    const auto real = quasiloc::dataset::readEurocImuCsv(path);
    // Frames of a simulated V1_01 span on the ground-truth clock, not on the IMU's grid.
    const std::int64_t t0 = 1403715300'002142976 + 1234567, t1 = t0 + 2'000'000'000;
    const auto sel = quasiloc::sim::selectRealImu(real, t0, t1, 200);
    ASSERT_EQ(sel.t_ns.size(), sel.samples.size());
    ASSERT_GE(sel.t_ns.size(), 399u);
    EXPECT_GE(sel.t_ns.front(), t0);
    EXPECT_LT(sel.t_ns.front() - 5'000'256, t0);  // the first sample of the span
    EXPECT_LE(sel.t_ns.back(), t1);
    EXPECT_GT(sel.t_ns.back() + 5'000'256, t1);
    const auto first = std::find(real.t_ns.begin(), real.t_ns.end(), sel.t_ns.front()) - real.t_ns.begin();
    for (size_t i = 0; i < sel.t_ns.size(); ++i)
    {
        EXPECT_EQ(sel.t_ns[i], real.t_ns[first + i]);
        EXPECT_EQ(sel.samples[i].gyro, real.samples[first + i].gyro);
        EXPECT_EQ(sel.samples[i].acc, real.samples[first + i].acc);
        EXPECT_EQ(sel.samples[i].t, real.samples[first + i].t);
    }
    // A span the file does not cover (another sequence's clock) names the file.
    try
    {
        quasiloc::sim::selectRealImu(real, 1413393213480760576, 1413393214480760576, 200);
        ADD_FAILURE() << "a span outside the real IMU file accepted";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}

TEST(ImuBias, FrameTimesSnapOntoNearbyImuTicksOnly)
{
    const std::vector<std::int64_t> ticks = {1000000, 6000000, 11000000};
    std::vector<std::int64_t> frames = {999872, 6000128, 8500000, 11000000, 11000999, 11001001};
    EXPECT_EQ(quasiloc::sim::snapToImuTicks(frames, ticks), 3u);
    EXPECT_EQ(frames, (std::vector<std::int64_t>{1000000, 6000000, 8500000, 11000000, 11000000, 11001001}));
}
