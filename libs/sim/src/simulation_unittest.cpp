#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/map/lidar_map.h>
#include <quasiloc/sim/simulation.h>

using namespace quasiloc;
namespace fs = std::filesystem;

namespace
{
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
    return cfg;
}
}  // namespace

TEST(Simulation, ShortRunWritesEveryOutput)
{
    const fs::path out = fs::temp_directory_path() / "quasiloc_sim_unittest_run";
    fs::remove_all(out);
    const sim::SimulationResult r = sim::runSimulation(shortRun(out.string()), "test");
    EXPECT_EQ(r.frames, 21u);            // 1 s at 20 Hz, both ends
    EXPECT_EQ(r.imu_samples, 201u);      // 1 s at 200 Hz, both ends
    for (const char* f : {"lidar_map.map", "lidar_map_32beam.map", "V2_01_easy.rawlog", "gt.tum", "gt_body.tum",
                          "calib.ini", "sim-rawlog.ini", "inspection.png", "README.txt"})
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
    fs::remove_all(out);
}

TEST(Simulation, BadInputLeavesNoOutput)
{
    const fs::path out = fs::temp_directory_path() / "quasiloc_sim_unittest_bad";
    fs::remove_all(out);
    auto cfg = shortRun(out.string());
    cfg.write("Simulation", "trajectory", "/nonexistent/trajectory.tum");
    EXPECT_THROW(sim::runSimulation(cfg, "test"), core::InputError);
    auto cfg2 = shortRun(out.string());
    cfg2.write("World", "no_such_key", 1);
    EXPECT_THROW(sim::runSimulation(cfg2, "test"), core::InputError);
    auto cfg3 = shortRun(out.string());
    cfg3.write("Simulation", "start_offset_s", 1e4);  // past the end of the trajectory
    EXPECT_THROW(sim::runSimulation(cfg3, "test"), core::InputError);
    EXPECT_FALSE(fs::exists(out));
}
