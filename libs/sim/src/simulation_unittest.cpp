#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/sim/material_labels.h>
#include <quasiloc/sim/simulation.h>
#include <quasiloc/sim/spectral_materials.h>
#include <sstream>

using namespace quasiloc;
namespace fs = std::filesystem;

namespace
{
std::string readText(const fs::path& path)
{
    std::ifstream f(path);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

/** Numeric rows of a csv ('#' comments skipped), parsed here independently of the library. */
std::vector<std::vector<double>> csvRows(const std::string& path)
{
    std::ifstream in(path);
    EXPECT_TRUE(in.good()) << path;
    std::vector<std::vector<double>> rows;
    std::string line;
    while (std::getline(in, line))
    {
        if (line.empty() || line[0] == '#') continue;
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream ss(line);
        std::vector<double> row;
        for (double v; ss >> v;) row.push_back(v);
        rows.push_back(row);
    }
    return rows;
}

/** Every section of sim-rawlog.ini loads strictly (as scripts re-read it), with the run's values. */
void expectEffectiveConfigLoadsBack(const mrpt::config::CConfigFileBase& eff, const std::string& out)
{
    sim::SimulationOptions so;
    sim::WorldOptions wo;
    sim::AppearanceOptions ao;
    sim::LidarOptions lo;
    sim::ImuNoiseOptions io;
    core::loadOptionsChecked(so, eff, "Simulation", "sim-rawlog.ini");
    core::loadOptionsChecked(wo, eff, "World", "sim-rawlog.ini");
    core::loadOptionsChecked(ao, eff, "Appearance", "sim-rawlog.ini");
    core::loadOptionsChecked(lo, eff, "Lidar", "sim-rawlog.ini");
    core::loadOptionsChecked(io, eff, "IMU", "sim-rawlog.ini");
    EXPECT_EQ(so.output_dir, out);
    EXPECT_EQ(so.trajectory, "");  // empty values are written without a comment
    EXPECT_EQ(so.start_offset_s, 10.0);
    EXPECT_EQ(wo.world, sim::ViconRoom::v2);
    EXPECT_EQ(wo.texture_size_px, 128);
    EXPECT_TRUE(lo.beam_map);
    EXPECT_EQ(io.bias_file, "");
    EXPECT_EQ(io.initial_gyro_bias, sim::ImuNoiseOptions().initial_gyro_bias);
    EXPECT_EQ(io.gyroscope_noise_density, 1.6968e-04);
}

mrpt::config::CConfigFileMemory shortRun(const std::string& out)
{
    mrpt::config::CConfigFileMemory cfg;
    cfg.write("Simulation", "output_dir", out);
    cfg.write("Simulation", "sequence", "V2_01_easy");
    cfg.write("Simulation", "shared_dir", std::string(QUASILOC_SHARED_DIR));
    cfg.write("Simulation", "duration_s", 1.0);
    cfg.write("Simulation", "start_offset_s", 10.0);
    cfg.write("Simulation", "verbose", false);
    cfg.write("World", "world", "v2");
    cfg.write("World", "texture_size_px", 128);
    cfg.write("Lidar", "density_per_m2", 100.0);
    cfg.write("Lidar", "cubemap_size_px", 256);
    cfg.write("Lidar", "beam_map", true);
    cfg.write("Lidar", "beam_num_scans", 1);
    cfg.write("Lidar", "beam_azimuth_steps", 360);
    cfg.write("Lidar", "map_source", "exact");  // the swept map is lidar_sweeps_unittest's
    return cfg;
}
}  // namespace

TEST(Simulation, ShortRunWritesEveryOutput)
{
    const fs::path out = fs::temp_directory_path() / "quasiloc_sim_unittest_run";
    fs::remove_all(out);
    const sim::SimulationResult r = sim::runSimulation(shortRun(out.string()), "test");
    EXPECT_EQ(r.frames, 21u);        // 1 s at 20 Hz, both ends
    EXPECT_EQ(r.imu_samples, 201u);  // 1 s at 200 Hz, both ends
    for (const char* f : {"lidar_map.map", "lidar_map_32beam.map", "V2_01_easy.rawlog", "gt.tum", "gt_body.tum",
                          "gt_imu_bias.csv", "calib.ini", "sim-rawlog.ini", "inspection.png", "README.txt"})
        EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
    size_t images = 0;
    for (const auto& e : fs::directory_iterator(out / "V2_01_easy_Images")) images += e.path().extension() == ".png";
    EXPECT_EQ(images, 2 * r.frames);
    const core::Trajectory gt = core::readTum((out / "gt.tum").string());
    const core::Trajectory gt_body = core::readTum((out / "gt_body.tum").string());
    EXPECT_EQ(gt.poses.size(), r.frames);
    EXPECT_EQ(gt_body.poses.size(), r.imu_samples);
    EXPECT_NEAR(gt.poses.back().t - gt.poses.front().t, 1.0, 1e-6);
    const map::LidarMap m = map::LidarMap::load((out / "lidar_map.map").string());
    EXPECT_EQ(m.size(), r.map_points);
    EXPECT_GE(r.world.min_clearance_m, 0.3 - 1e-4);
    // The effective configuration reproduces the run's options.
    mrpt::config::CConfigFileMemory eff;
    eff.setContent(std::string([&] {
        std::ifstream f(out / "sim-rawlog.ini");
        return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    }()));
    EXPECT_EQ(eff.read_string("World", "world", ""), "v2");
    EXPECT_EQ(eff.read_double("Simulation", "duration_s", 0), 1.0);
    EXPECT_EQ(eff.read_string("IMU", "bias", ""), "euroc_groundtruth");
    expectEffectiveConfigLoadsBack(eff, out.string());
    // The true biases: V2_01_easy's ground truth (bias = euroc_groundtruth by default), one row per IMU sample
    // at the gt_body.tum times.
    const auto bias_rows = csvRows((out / "gt_imu_bias.csv").string());
    ASSERT_EQ(bias_rows.size(), r.imu_samples);
    EXPECT_NEAR(bias_rows.front()[0], gt_body.poses.front().t, 1e-6);
    EXPECT_NEAR(bias_rows.back()[0], gt_body.poses.back().t, 1e-6);
    // V2_01_easy.csv 10 s after its start: b_w (-0.002294 0.024942 0.081665), b_a (-0.023391 0.120855 0.075464)
    const double file_gyro[] = {-0.002294, 0.024942, 0.081665}, file_acc[] = {-0.023391, 0.120855, 0.075464};
    for (int i = 0; i < 3; ++i)
    {
        EXPECT_NEAR(bias_rows.front()[1 + i], file_gyro[i], 1e-5);
        EXPECT_NEAR(bias_rows.front()[4 + i], file_acc[i], 1e-4);
    }
    EXPECT_NE(r.imu_description.find("groundtruth/body/V2_01_easy.csv"), std::string::npos) << r.imu_description;
    EXPECT_NE(readText(out / "README.txt").find("V2_01_easy.csv"), std::string::npos);
    // calib.ini [imu] holds the noise model only: not the true biases (a user's calibration has not measured them).
    const dataset::SensorCalibration calib = dataset::loadCalibration((out / "calib.ini").string());
    ASSERT_TRUE(calib.imu);
    EXPECT_EQ(calib.imu->gyroscope_noise_density, 1.6968e-04);
    EXPECT_EQ(calib.imu->gyroscope_bias, Eigen::Vector3d::Zero());
    EXPECT_EQ(calib.imu->gyroscope_bias_sigma, dataset::kUnknownGyroBiasSigma);
    fs::remove_all(out);
}

/** source = real: the semi-real sequence replays the real V1_01 IMU samples of the frames' span, unchanged. */
TEST(Simulation, RealImuSourceReplaysTheRealSamples)
{
    const fs::path out = fs::temp_directory_path() / "quasiloc_sim_unittest_real_imu";
    fs::remove_all(out);
    auto cfg = shortRun(out.string());
    cfg.write("Simulation", "sequence", "V1_01_easy");
    cfg.write("Simulation", "start_offset_s", 30.0);
    cfg.write("Simulation", "duration_s", 0.5);
    cfg.write("World", "world", "v1");
    cfg.write("Lidar", "beam_map", false);
    cfg.write("IMU", "source", "real");
    const sim::SimulationResult r = sim::runSimulation(cfg, "test");
    EXPECT_FALSE(fs::exists(out / "gt_imu_bias.csv"));  // the real sensor's biases are unknown
    EXPECT_NE(r.imu_description.find("real samples of"), std::string::npos) << r.imu_description;
    const core::Trajectory gt = core::readTum((out / "gt.tum").string());
    const core::Trajectory gt_body = core::readTum((out / "gt_body.tum").string());
    // Every real row with first frame <= t <= last frame, at the file's own timestamps.
    const auto real = csvRows(std::string(QUASILOC_SHARED_DIR) + "/data/euroc/V1_01_easy_micro/mav0/imu0/data.csv");
    std::vector<double> expected_t;
    for (const auto& row : real)
        if (row[0] * 1e-9 >= gt.poses.front().t - 1e-6 && row[0] * 1e-9 <= gt.poses.back().t + 1e-6)
            expected_t.push_back(row[0] * 1e-9);
    ASSERT_EQ(r.imu_samples, expected_t.size());
    ASSERT_EQ(gt_body.poses.size(), expected_t.size());
    for (size_t i = 0; i < expected_t.size(); ++i) EXPECT_NEAR(gt_body.poses[i].t, expected_t[i], 1e-6);
    // A sequence on another clock than the file is refused before anything is written.
    auto other = shortRun(out.string() + "_v2");
    other.write("IMU", "source", "real");
    EXPECT_THROW(sim::runSimulation(other, "test"), core::InputError);
    EXPECT_FALSE(fs::exists(out.string() + "_v2"));
    fs::remove_all(out);
}

TEST(Simulation, BadInputLeavesNoOutput)
{
    const fs::path out = fs::temp_directory_path() / "quasiloc_sim_unittest_bad";
    fs::remove_all(out);
    auto cfg = shortRun(out.string());
    cfg.write("Simulation", "trajectory", "/nonexistent/trajectory.tum");
    EXPECT_THROW(sim::runSimulation(cfg, "test"), core::InputError);
    for (const char* section : {"Simulation", "World", "Appearance", "Lidar", "IMU"})
    {
        auto typo = shortRun(out.string());
        typo.write(section, "no_such_key", 1);
        try
        {
            sim::runSimulation(typo, "test.ini");
            ADD_FAILURE() << "a typo in [" << section << "] was accepted";
        }
        catch (const core::InputError& e)
        {
            EXPECT_NE(std::string(e.what()).find("test.ini [" + std::string(section) + "] no_such_key"),
                      std::string::npos)
                << e.what();
        }
    }
    auto range = shortRun(out.string());
    range.write("Appearance", "gamma", 0.1);
    EXPECT_THROW(sim::runSimulation(range, "test"), core::InputError);
    auto cfg3 = shortRun(out.string());
    cfg3.write("Simulation", "start_offset_s", 1e4);  // past the end of the trajectory
    EXPECT_THROW(sim::runSimulation(cfg3, "test"), core::InputError);
    EXPECT_FALSE(fs::exists(out));
}

/** write_map_materials: one material per map point, beside the map; with the spectral set the map's reflectivity per
 *  material follows the table's near-infrared levels (times the sampler's range and incidence falloff, <= 1). */
TEST(Simulation, MapMaterialsLabelEveryPointOfTheMap)
{
    const fs::path out = fs::temp_directory_path() / "quasiloc_sim_unittest_materials";
    fs::remove_all(out);
    auto cfg = shortRun(out.string());
    cfg.write("Simulation", "duration_s", 0.2);
    cfg.write("Simulation", "write_map_materials", true);
    cfg.write("World", "materials", "spectral");
    cfg.write("Lidar", "beam_map", false);
    sim::runSimulation(cfg, "test");
    const map::LidarMap m = map::LidarMap::load((out / "lidar_map.map").string());
    const std::vector<uint16_t> labels = sim::loadMaterialLabels((out / sim::kMaterialLabelsFile).string(), m.size());
    std::vector<double> sum(sim::kNumMaterials, 0.0);
    std::vector<size_t> count(sim::kNumMaterials, 0);
    for (size_t i = 0; i < labels.size(); ++i)
    {
        ASSERT_LT(labels[i], sim::kNumMaterials);
        sum[labels[i]] += m.reflectivity(i);
        ++count[labels[i]];
    }
    EXPECT_GT(count[sim::kFloorCarpet], 100u);
    EXPECT_GT(count[sim::kWallPlaster] + count[sim::kConcrete] + count[sim::kCurtain] + count[sim::kWoodPanel], 100u);
    for (int id = 0; id < sim::kNumMaterials; ++id)
    {
        if (count[id] < 200) continue;
        const double mean = sum[id] / double(count[id]), level = sim::spectralMaterial(uint16_t(id)).nir_reflectance;
        EXPECT_LT(mean, level * 1.1 + 0.03) << id;  // falloffs only lower it
        EXPECT_GT(mean, level * 0.4) << id;         // within the room they lower it by less than this
    }
    EXPECT_NE(readText(out / "README.txt").find(sim::kMaterialLabelsFile), std::string::npos);
    fs::remove_all(out);
    // Without the key no label file is written (the default folder is unchanged).
    auto plain = shortRun(out.string());
    plain.write("Simulation", "duration_s", 0.1);
    plain.write("Lidar", "beam_map", false);
    sim::runSimulation(plain, "test");
    EXPECT_FALSE(fs::exists(out / sim::kMaterialLabelsFile));
    fs::remove_all(out);
}
