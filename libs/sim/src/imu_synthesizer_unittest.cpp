// ImuSynthesizer: options (INI, EuRoC yaml, check), noiseless IMU integrates back to the spline, agreement
// with the real EuRoC IMU, noise and bias random-walk statistics, determinism.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/sim/imu_synthesizer.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace
{
using quasiloc::dataset::ImuSample;
using quasiloc::sim::ImuNoiseOptions;
using quasiloc::sim::ImuSynthesizer;
using quasiloc::sim::ImuTruth;
using quasiloc::sim::TrajectorySpline;

const std::string kEuroc = std::string(QUASILOC_SHARED_DIR) + "/data/euroc";

const TrajectorySpline& v101Spline()
{
    static const TrajectorySpline spline =
        TrajectorySpline::fitCameraTrajectory(quasiloc::core::readTum(kEuroc + "/groundtruth/cam0/V1_01_easy.txt"),
                                              quasiloc::core::readEurocSensorPose(kEuroc + "/calib/cam0_sensor.yaml"));
    return spline;
}

ImuNoiseOptions noiseless()
{
    ImuNoiseOptions o;
    o.noise_enabled = false;
    o.initial_gyro_bias.setZero();  // exact samples: no bias either
    o.initial_acc_bias.setZero();
    return o;
}

TEST(ImuNoiseOptions, IniRoundTripYamlAndCheck)
{
    ImuNoiseOptions a;
    a.rate_hz = 400;
    a.gyroscope_noise_density = 1.234567890123e-4;
    a.accelerometer_random_walk = 0.1;
    a.gravity_m_s2 = 9.80665;
    a.noise_enabled = false;
    a.seed = 18446744073709551557ull;
    a.initial_gyro_bias = {0.001, -0.002, 0.003};
    a.initial_acc_bias = {-0.1, 0.2, 1e-17};
    a.source = quasiloc::sim::ImuSource::real;
    a.real_imu_csv = "/some/imu0/data.csv";
    a.bias = quasiloc::sim::ImuBiasModel::random_walk;
    mrpt::config::CConfigFileMemory cfg;
    a.saveToConfigFile(cfg, "imu");
    ImuNoiseOptions b;
    quasiloc::core::loadOptionsChecked(b, cfg, "imu", "test.ini");
    EXPECT_EQ(b.rate_hz, a.rate_hz);
    EXPECT_EQ(b.gyroscope_noise_density, a.gyroscope_noise_density);
    EXPECT_EQ(b.gyroscope_random_walk, a.gyroscope_random_walk);
    EXPECT_EQ(b.accelerometer_noise_density, a.accelerometer_noise_density);
    EXPECT_EQ(b.accelerometer_random_walk, a.accelerometer_random_walk);
    EXPECT_EQ(b.gravity_m_s2, a.gravity_m_s2);
    EXPECT_EQ(b.noise_enabled, a.noise_enabled);
    EXPECT_EQ(b.seed, a.seed);
    EXPECT_EQ(b.initial_gyro_bias, a.initial_gyro_bias);
    EXPECT_EQ(b.initial_acc_bias, a.initial_acc_bias);
    EXPECT_EQ(b.source, a.source);
    EXPECT_EQ(b.real_imu_csv, a.real_imu_csv);
    EXPECT_EQ(b.bias, a.bias);
    EXPECT_EQ(b.bias_file, a.bias_file);
    // Modes are names, not numbers; a key for the other mode is an error, not silently ignored.
    ImuNoiseOptions m;
    for (const char* bad : {"reel", "1", "synthetic_real"})  // names match without regard to case: "Real" is real
    {
        cfg.write("imu", "source", std::string(bad));
        EXPECT_THROW(m.loadFromConfigFile(cfg, "imu"), quasiloc::core::InputError) << bad;
    }
    cfg.write("imu", "source", std::string("synthetic"));
    cfg.write("imu", "bias", std::string("ground_truth"));
    EXPECT_THROW(m.loadFromConfigFile(cfg, "imu"), quasiloc::core::InputError);
    cfg.write("imu", "bias", std::string("random_walk"));
    cfg.write("imu", "bias_file", std::string("/x.csv"));
    m.loadFromConfigFile(cfg, "imu");
    EXPECT_THROW(m.check("x"), quasiloc::core::InputError);  // bias_file needs bias = euroc_groundtruth
    m.bias_file.clear();
    EXPECT_THROW(m.check("x"), quasiloc::core::InputError);  // real_imu_csv needs source = real
    m.real_imu_csv.clear();
    EXPECT_NO_THROW(m.check("x"));

    cfg.write("imu", "initial_acc_bias", std::string("[1 2]"));
    EXPECT_THROW(b.loadFromConfigFile(cfg, "imu"), quasiloc::core::InputError);
    cfg.write("imu", "gyro_noise", std::string("1"));  // unknown key
    EXPECT_THROW(quasiloc::core::loadOptionsChecked(b, cfg, "imu", "test.ini"), quasiloc::core::InputError);

    ImuNoiseOptions y;
    y.rate_hz = 1;
    y.loadFromEurocYaml(kEuroc + "/calib/imu0_sensor.yaml");
    EXPECT_EQ(y.rate_hz, 200);
    EXPECT_DOUBLE_EQ(y.gyroscope_noise_density, 1.6968e-04);
    EXPECT_DOUBLE_EQ(y.gyroscope_random_walk, 1.9393e-05);
    EXPECT_DOUBLE_EQ(y.accelerometer_noise_density, 2.0e-3);
    EXPECT_DOUBLE_EQ(y.accelerometer_random_walk, 3.0e-3);
    EXPECT_THROW(y.loadFromEurocYaml(kEuroc + "/calib/no_such_imu.yaml"), quasiloc::core::InputError);
    // A camera yaml has no IMU densities: the error names the missing key.
    try
    {
        y.loadFromEurocYaml(kEuroc + "/calib/cam0_sensor.yaml");
        ADD_FAILURE() << "camera yaml accepted as IMU yaml";
    }
    catch (const quasiloc::core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("gyroscope_noise_density"), std::string::npos) << e.what();
    }

    ImuNoiseOptions ok;
    EXPECT_NO_THROW(ok.check("x"));
    for (double ImuNoiseOptions::*field :
         {&ImuNoiseOptions::gyroscope_noise_density, &ImuNoiseOptions::gyroscope_random_walk,
          &ImuNoiseOptions::accelerometer_noise_density, &ImuNoiseOptions::accelerometer_random_walk})
    {
        ImuNoiseOptions bad;
        bad.*field = -1e-6;
        EXPECT_THROW(bad.check("x"), quasiloc::core::InputError);
    }
    ImuNoiseOptions bad_rate;
    bad_rate.rate_hz = 0;
    EXPECT_THROW(bad_rate.check("x"), quasiloc::core::InputError);
    bad_rate.rate_hz = -200;
    EXPECT_THROW(bad_rate.check("x"), quasiloc::core::InputError);
    EXPECT_THROW(ImuSynthesizer(v101Spline(), bad_rate), quasiloc::core::InputError);
}

/** Body state for strapdown integration. */
struct NavState
{
    Eigen::Vector4d q;  ///< quaternion coefficients (x, y, z, w) of R_world_body
    Eigen::Vector3d p, v;
};

NavState derivative(const NavState& x, const Eigen::Vector3d& gyro, const Eigen::Vector3d& acc,
                    const Eigen::Vector3d& g_world)
{
    const Eigen::Quaterniond q(x.q);  // (x, y, z, w) coefficient order
    NavState d;
    d.q = (q * Eigen::Quaterniond(0, gyro.x(), gyro.y(), gyro.z())).coeffs() * 0.5;
    d.p = x.v;
    d.v = q.normalized().toRotationMatrix() * acc + g_world;
    return d;
}

NavState axpy(const NavState& x, double h, const NavState& d) { return {x.q + h * d.q, x.p + h * d.p, x.v + h * d.v}; }

/** Classic RK4 over pairs of samples: step 2/rate, the middle sample is the midpoint evaluation. */
NavState integrateRk4(NavState x, const std::vector<ImuSample>& imu, size_t k, const Eigen::Vector3d& g_world)
{
    const ImuSample &s0 = imu[k], &s1 = imu[k + 1], &s2 = imu[k + 2];
    const double h = s2.t - s0.t;
    const NavState k1 = derivative(x, s0.gyro, s0.acc, g_world);
    const NavState k2 = derivative(axpy(x, h / 2, k1), s1.gyro, s1.acc, g_world);
    const NavState k3 = derivative(axpy(x, h / 2, k2), s1.gyro, s1.acc, g_world);
    const NavState k4 = derivative(axpy(x, h, k3), s2.gyro, s2.acc, g_world);
    x.q += h / 6 * (k1.q + 2 * k2.q + 2 * k3.q + k4.q);
    x.p += h / 6 * (k1.p + 2 * k2.p + 2 * k3.p + k4.p);
    x.v += h / 6 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v);
    x.q.normalize();
    return x;
}

struct IntegrationError
{
    double position_m = 0, rotation_rad = 0, velocity_m_s = 0;
};

/** Integrates noiseless IMU over [t0, t0 + duration] from the spline's true state and compares with the
 *  spline after every step. */
IntegrationError integrateAgainstSpline(const TrajectorySpline& spline, double t0, double duration)
{
    ImuSynthesizer synth(spline, noiseless());
    const auto imu = synth.generate(t0, t0 + duration);
    const auto s0 = spline.evaluate(imu.front().t);
    NavState x{Eigen::Quaterniond(s0.R_world_body).coeffs(), s0.p_world, s0.v_world};
    const Eigen::Vector3d g_world(0, 0, -noiseless().gravity_m_s2);
    IntegrationError err;
    for (size_t k = 0; k + 2 < imu.size(); k += 2)
    {
        x = integrateRk4(x, imu, k, g_world);
        const auto truth = spline.evaluate(imu[k + 2].t);
        const Eigen::AngleAxisd dR(Eigen::Quaterniond(x.q).toRotationMatrix().transpose() * truth.R_world_body);
        err.position_m = std::max(err.position_m, (x.p - truth.p_world).norm());
        err.velocity_m_s = std::max(err.velocity_m_s, (x.v - truth.v_world).norm());
        err.rotation_rad = std::max(err.rotation_rad, std::abs(dR.angle()));
    }
    return err;
}

/** The test: noiseless 200 Hz IMU integrated with RK4 reproduces the trajectory over 10 s. */
TEST(ImuSynthesizer, NoiselessImuIntegratesBackToTrajectory)
{
    const TrajectorySpline& spline = v101Spline();
    IntegrationError worst;
    for (double offset : {5.0, 30.0, 60.0, 90.0, 130.0})  // starts on the knot grid
    {
        const auto e = integrateAgainstSpline(spline, spline.tStart() + offset, 10.0);
        std::printf(
            "[ rk4      ] t0 = start + %5.1f s, 10 s: max error position %.3e m, velocity %.3e m/s, "
            "rotation %.3e rad\n",
            offset, e.position_m, e.velocity_m_s, e.rotation_rad);
        worst.position_m = std::max(worst.position_m, e.position_m);
        worst.rotation_rad = std::max(worst.rotation_rad, e.rotation_rad);
    }
    EXPECT_LT(worst.position_m, 1e-3);
    EXPECT_LT(worst.rotation_rad, 1e-5);

    // Off the knot grid the jerk jumps inside RK4 steps: lower order there, still sub-millimetre.
    const auto off = integrateAgainstSpline(spline, spline.tStart() + 60.0025, 10.0);
    std::printf("[ rk4      ] off-grid start: max error position %.3e m, velocity %.3e m/s, rotation %.3e rad\n",
                off.position_m, off.velocity_m_s, off.rotation_rad);
    EXPECT_LT(off.position_m, 1e-3);
    EXPECT_LT(off.rotation_rad, 1e-4);
}

}  // namespace

namespace
{
/** The real EuRoC IMU of V1_01_easy (body = imu0 frame), rows "t_ns, wx, wy, wz, ax, ay, az". */
std::vector<ImuSample> readRealImu()
{
    const std::string path = kEuroc + "/V1_01_easy_micro/mav0/imu0/data.csv";
    std::ifstream in(path);
    EXPECT_TRUE(in.good()) << path;
    std::vector<ImuSample> out;
    std::string line;
    while (std::getline(in, line))
    {
        if (line.empty() || line[0] == '#') continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream ss(line);
        long long t_ns;
        ImuSample s;
        ss >> t_ns >> s.gyro.x() >> s.gyro.y() >> s.gyro.z() >> s.acc.x() >> s.acc.y() >> s.acc.z();
        s.t = t_ns * 1e-9;
        out.push_back(s);
    }
    return out;
}

/** Frames and gravity against reality: the synthetic IMU (noiseless) follows the real one of the same flight
 *  once both are averaged over 0.5 s (propeller vibration) and the real sensor's constant bias is removed. */
TEST(ImuSynthesizer, FollowsRealEurocImu)
{
    const TrajectorySpline& spline = v101Spline();
    const auto real = readRealImu();
    ASSERT_GT(real.size(), 29000u);
    const Eigen::Vector3d g_world(0, 0, -9.81);
    const size_t block = 100;
    std::vector<Eigen::Matrix<double, 6, 1>> diffs, synthetic;
    Eigen::Matrix<double, 6, 1> sum_real = Eigen::Matrix<double, 6, 1>::Zero(), sum_syn = sum_real;
    size_t count = 0;
    for (const auto& r : real)
    {
        if (r.t < spline.tStart() || r.t > spline.tEnd()) continue;
        const auto st = spline.evaluate(r.t);
        sum_real << sum_real.head<3>() + r.gyro, sum_real.tail<3>() + r.acc;
        sum_syn << sum_syn.head<3>() + st.omega_body,
            sum_syn.tail<3>() + st.R_world_body.transpose() * (st.a_world - g_world);
        if (++count == block)
        {
            diffs.push_back((sum_real - sum_syn) / block);
            synthetic.push_back(sum_syn / block);
            sum_real.setZero();
            sum_syn.setZero();
            count = 0;
        }
    }
    auto meanAndRms = [](const std::vector<Eigen::Matrix<double, 6, 1>>& v, Eigen::Matrix<double, 6, 1>& mean,
                         double& rms_gyro, double& rms_acc) {
        mean.setZero();
        for (const auto& d : v) mean += d / v.size();
        rms_gyro = rms_acc = 0;
        for (const auto& d : v)
        {
            rms_gyro += (d - mean).head<3>().squaredNorm() / v.size();
            rms_acc += (d - mean).tail<3>().squaredNorm() / v.size();
        }
        rms_gyro = std::sqrt(rms_gyro);
        rms_acc = std::sqrt(rms_acc);
    };
    Eigen::Matrix<double, 6, 1> bias, mean_signal;
    double rms_gyro, rms_acc, signal_gyro, signal_acc;
    meanAndRms(diffs, bias, rms_gyro, rms_acc);
    meanAndRms(synthetic, mean_signal, signal_gyro, signal_acc);
    std::printf(
        "[ real imu ] %zu blocks of 0.5 s: real - synthetic mean (bias) gyro [%.4f %.4f %.4f] rad/s, "
        "acc [%.3f %.3f %.3f] m/s^2; RMS after removing it: gyro %.4f rad/s, acc %.3f m/s^2 "
        "(RMS of the signal's variation: gyro %.4f rad/s, acc %.3f m/s^2)\n",
        diffs.size(), bias[0], bias[1], bias[2], bias[3], bias[4], bias[5], rms_gyro, rms_acc, signal_gyro, signal_acc);
    // A frame error (world rate, R instead of R^T, gravity sign) gives offsets of the size of g or of the
    // signal itself; the real ADIS16448's biases are a few 0.01 rad/s and ~0.1 m/s^2.
    EXPECT_LT(bias.head<3>().norm(), 0.15);
    EXPECT_LT(bias.tail<3>().norm(), 0.5);
    EXPECT_LT(rms_gyro, 0.1 * signal_gyro);
    EXPECT_LT(rms_acc, 0.5 * signal_acc);  // measured 0.31: vibration left after 0.5 s averaging
}
}  // namespace

namespace
{
/** Pooled sum of squares over the 3 axes of a sensor. */
struct Moments
{
    double sum2 = 0;
    size_t n = 0;
    void add(const Eigen::Vector3d& v)
    {
        sum2 += v.squaredNorm();
        n += 3;
    }
    double rms() const { return std::sqrt(sum2 / n); }
};

/** Overlapping Allan variance of each axis of x at cluster size m (samples), averaged over the axes. */
double allanVariance(const std::vector<Eigen::Vector3d>& x, size_t m)
{
    std::vector<Eigen::Vector3d> cum(x.size() + 1, Eigen::Vector3d::Zero());
    for (size_t i = 0; i < x.size(); ++i) cum[i + 1] = cum[i] + x[i];
    double sum = 0;
    size_t n = 0;
    for (size_t k = 0; k + 2 * m <= x.size(); ++k, n += 3)
        sum += ((cum[k + 2 * m] - 2 * cum[k + m] + cum[k]) / m).squaredNorm() / 2;
    return sum / n;
}

/** Several seeds x 100 s at the EuRoC densities: white noise and bias random walk measured three ways
 *  (with the true biases removed, from the data alone, from the true biases' increments at several lags). */
TEST(ImuSynthesizer, NoiseStatisticsMatchDensities)
{
    const TrajectorySpline& spline = v101Spline();
    const double t0 = spline.tStart() + 20, t1 = t0 + 100;
    ImuSynthesizer clean_synth(spline, noiseless());
    const auto clean = clean_synth.generate(t0, t1);
    ImuNoiseOptions opt;
    opt.loadFromEurocYaml(kEuroc + "/calib/imu0_sensor.yaml");
    const double dt = 1.0 / opt.rate_hz;
    const double sd_gyro = opt.gyroscope_noise_density / std::sqrt(dt);
    const double sd_acc = opt.accelerometer_noise_density / std::sqrt(dt);
    const double step_gyro = opt.gyroscope_random_walk * std::sqrt(dt);
    const double step_acc = opt.accelerometer_random_walk * std::sqrt(dt);

    const size_t lags[] = {1, 200, 1000};  // 5 ms, 1 s, 5 s
    Moments white_gyro, white_acc, diff_gyro, diff_acc, block_residual_acc;
    Moments bias_gyro[3], bias_acc[3];
    double allan_acc = 0;
    const int num_seeds = 8;
    const size_t cluster = 1000, block = 200;
    for (int seed = 1; seed <= num_seeds; ++seed)
    {
        opt.seed = 1000 + seed;
        ImuSynthesizer synth(spline, opt);
        std::vector<ImuTruth> truth;
        const auto noisy = synth.generate(t0, t1, &truth);
        ASSERT_EQ(noisy.size(), clean.size());
        ASSERT_EQ(truth.size(), noisy.size());
        std::vector<Eigen::Vector3d> e_gyro(noisy.size()), e_acc(noisy.size());
        for (size_t i = 0; i < noisy.size(); ++i)
        {
            ASSERT_EQ(noisy[i].t, clean[i].t);
            e_gyro[i] = noisy[i].gyro - clean[i].gyro;
            e_acc[i] = noisy[i].acc - clean[i].acc;
            white_gyro.add(e_gyro[i] - truth[i].gyro_bias);
            white_acc.add(e_acc[i] - truth[i].acc_bias);
            if (i > 0)
            {
                diff_gyro.add(e_gyro[i] - e_gyro[i - 1]);
                diff_acc.add(e_acc[i] - e_acc[i - 1]);
            }
        }
        for (int l = 0; l < 3; ++l)  // non-overlapping increments of the true biases
            for (size_t i = 0; i + lags[l] < truth.size(); i += lags[l])
            {
                bias_gyro[l].add(truth[i + lags[l]].gyro_bias - truth[i].gyro_bias);
                bias_acc[l].add(truth[i + lags[l]].acc_bias - truth[i].acc_bias);
            }
        // The bias is in the measurement: 1 s means of (noisy - clean) follow the true bias.
        for (size_t i = 0; i + block <= noisy.size(); i += block)
        {
            Eigen::Vector3d r = Eigen::Vector3d::Zero();
            for (size_t j = i; j < i + block; ++j) r += (e_acc[j] - truth[j].acc_bias) / block;
            block_residual_acc.add(r);
        }
        allan_acc += allanVariance(e_acc, cluster) / num_seeds;
    }
    // From the data alone: first differences hold 2 sigma^2 + step^2; the Allan variance at m samples holds
    // sigma^2 / m + step^2 (2 m^2 + 1) / (6 m).
    const double sd_gyro_data = std::sqrt((diff_gyro.rms() * diff_gyro.rms() - step_gyro * step_gyro) / 2);
    const double sd_acc_data = std::sqrt((diff_acc.rms() * diff_acc.rms() - step_acc * step_acc) / 2);
    const double m = cluster;
    const double step_acc_allan = std::sqrt((allan_acc - sd_acc_data * sd_acc_data / m) * 6 * m / (2 * m * m + 1));
    std::printf("[ noise    ] %d seeds x %zu samples; measured / configured:\n", num_seeds, clean.size());
    std::printf("[ noise    ] gyro white (bias removed) %.4e / %.4e rad/s (%.2f%%), from data %.4e (%.2f%%)\n",
                white_gyro.rms(), sd_gyro, 100 * (white_gyro.rms() / sd_gyro - 1), sd_gyro_data,
                100 * (sd_gyro_data / sd_gyro - 1));
    std::printf("[ noise    ] acc  white (bias removed) %.4e / %.4e m/s^2 (%.2f%%), from data %.4e (%.2f%%)\n",
                white_acc.rms(), sd_acc, 100 * (white_acc.rms() / sd_acc - 1), sd_acc_data,
                100 * (sd_acc_data / sd_acc - 1));
    for (int l = 0; l < 3; ++l)
    {
        const double sl = std::sqrt(static_cast<double>(lags[l]));
        std::printf(
            "[ noise    ] bias increments over %4zu steps: gyro %.4e / %.4e (%.2f%%), acc %.4e / %.4e "
            "(%.2f%%), %zu values each\n",
            lags[l], bias_gyro[l].rms(), step_gyro * sl, 100 * (bias_gyro[l].rms() / (step_gyro * sl) - 1),
            bias_acc[l].rms(), step_acc * sl, 100 * (bias_acc[l].rms() / (step_acc * sl) - 1), bias_acc[l].n);
        EXPECT_NEAR(bias_gyro[l].rms() / (step_gyro * sl), 1.0, 0.1);
        EXPECT_NEAR(bias_acc[l].rms() / (step_acc * sl), 1.0, 0.1);
    }
    std::printf(
        "[ noise    ] acc bias step from the data alone (Allan variance at %zu samples): %.4e / %.4e "
        "(%.2f%%); 1 s means of (noisy - clean - true bias): RMS %.4e, expected %.4e\n",
        cluster, step_acc_allan, step_acc, 100 * (step_acc_allan / step_acc - 1), block_residual_acc.rms(),
        sd_acc / std::sqrt(static_cast<double>(block)));
    EXPECT_NEAR(white_gyro.rms() / sd_gyro, 1.0, 0.1);
    EXPECT_NEAR(white_acc.rms() / sd_acc, 1.0, 0.1);
    EXPECT_NEAR(sd_gyro_data / sd_gyro, 1.0, 0.1);
    EXPECT_NEAR(sd_acc_data / sd_acc, 1.0, 0.1);
    EXPECT_NEAR(step_acc_allan / step_acc, 1.0, 0.1);
    EXPECT_NEAR(block_residual_acc.rms() / (sd_acc / std::sqrt(static_cast<double>(block))), 1.0, 0.1);
}

TEST(ImuSynthesizer, DeterministicForASeed)
{
    const TrajectorySpline& spline = v101Spline();
    const double t0 = spline.tStart() + 30, tm = t0 + 1.0, t1 = t0 + 2.0;
    ImuNoiseOptions opt;
    opt.seed = 42;
    ImuSynthesizer a(spline, opt), b(spline, opt), split(spline, opt);
    std::vector<ImuTruth> truth_a, truth_b;
    const auto sa = a.generate(t0, t1, &truth_a), sb = b.generate(t0, t1, &truth_b);
    // Two consecutive calls continue the same noise stream; the shared endpoint tm is not repeated.
    auto s_split = split.generate(t0, tm);
    const auto second = split.generate(tm, t1);
    s_split.insert(s_split.end(), second.begin(), second.end());
    ASSERT_EQ(sa.size(), 401u);
    ASSERT_EQ(sb.size(), sa.size());
    ASSERT_EQ(s_split.size(), sa.size());
    for (size_t i = 0; i < sa.size(); ++i)
    {
        EXPECT_EQ(sa[i].t, sb[i].t);
        EXPECT_EQ(sa[i].acc, sb[i].acc);
        EXPECT_EQ(sa[i].gyro, sb[i].gyro);
        EXPECT_EQ(truth_a[i].acc_bias, truth_b[i].acc_bias);
        EXPECT_EQ(sa[i].acc, s_split[i].acc);
        EXPECT_EQ(sa[i].gyro, s_split[i].gyro);
    }
    opt.seed = 43;
    ImuSynthesizer c(spline, opt);
    const auto sc = c.generate(t0, t1);
    ASSERT_EQ(sc.size(), sa.size());
    size_t num_different = 0;
    for (size_t i = 0; i < sa.size(); ++i) num_different += (sa[i].acc != sc[i].acc) && (sa[i].gyro != sc[i].gyro);
    EXPECT_EQ(num_different, sa.size());
    // The noiseless samples sit between: noise of the expected size, not zero.
    const auto clean = ImuSynthesizer(spline, noiseless()).generate(t0, t1);
    ASSERT_EQ(clean.size(), sa.size());
    EXPECT_GT((sa[10].acc - truth_a[10].acc_bias - clean[10].acc).norm(), 1e-4);
    EXPECT_LT((sa[10].acc - truth_a[10].acc_bias - clean[10].acc).norm(), 0.2);
}
}  // namespace
