#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/stereo_rig.h>
#include <quasiloc/sim/lidar_sampler.h>
#include <quasiloc/sim/stereo_renderer.h>
#include <quasiloc/sim/world_builder.h>

using namespace quasiloc;

namespace
{
const std::string kShared = QUASILOC_SHARED_DIR;

const sim::World& testWorld()
{
    static const sim::World w = [] {
        sim::WorldOptions o;
        o.texture_size_px = 256;
        return sim::buildWorld(o, kShared, 3, sim::loadRoomTrajectoryPositions(kShared, "v1"));
    }();
    return w;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b)
{
    double ma = 0, mb = 0;
    for (size_t i = 0; i < a.size(); ++i)
    {
        ma += a[i];
        mb += b[i];
    }
    ma /= a.size();
    mb /= b.size();
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < a.size(); ++i)
    {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}
}  // namespace

TEST(LidarSampler, ReflectivityIsCorrelatedWithAlbedoButNotEqual)
{
    sim::LidarOptions o;
    o.density_per_m2 = 300;
    o.cubemap_size_px = 512;
    sim::LidarStats st;
    sim::LidarPointInfo info;
    const map::LidarMap m = sim::sampleSurveyMap(testWorld(), o, 5, &st, &info);
    ASSERT_GT(m.size(), 50000u);
    ASSERT_EQ(info.albedo.size(), m.size());
    EXPECT_NO_THROW(m.check("simulated map"));
    EXPECT_GT(st.not_visible, 0u);              // scan shadows exist
    EXPECT_LT(st.not_visible, st.sampled / 2);  // but most surfaces are seen
    std::vector<double> refl, albedo;
    for (size_t i = 0; i < m.size(); ++i)
    {
        refl.push_back(m.reflectivity(i));
        albedo.push_back(info.albedo[i]);
    }
    const double r = correlation(refl, albedo);
    std::cout << "correlation(LiDAR reflectivity, camera albedo) over " << m.size() << " points: " << r << "\n";
    EXPECT_GT(r, 0.3);
    EXPECT_LT(r, 0.8);
}

TEST(LidarSampler, DeterministicForASeedAndNoisy)
{
    sim::LidarOptions o;
    o.density_per_m2 = 50;
    o.cubemap_size_px = 256;
    const map::LidarMap a = sim::sampleSurveyMap(testWorld(), o, 9);
    const map::LidarMap b = sim::sampleSurveyMap(testWorld(), o, 9);
    const map::LidarMap c = sim::sampleSurveyMap(testWorld(), o, 10);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
    {
        ASSERT_EQ(a.point(i), b.point(i));
        ASSERT_EQ(a.reflectivity(i), b.reflectivity(i));
    }
    EXPECT_TRUE(a.size() != c.size() || a.point(0) != c.point(0));
    // Range noise: points scatter around the floor plane by ~range_noise_mm, not more.
    const float floor_z = testWorld().room.min().z();
    double sum2 = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::abs(a.point(i).z() - floor_z) < 0.02f)
        {
            sum2 += std::pow(a.point(i).z() - floor_z, 2);
            ++n;
        }
    ASSERT_GT(n, 100u);
    const double rms_mm = 1e3 * std::sqrt(sum2 / n);
    EXPECT_GT(rms_mm, 0.2);
    EXPECT_LT(rms_mm, 2 * o.range_noise_mm);
}

TEST(LidarSampler, BeamMapIsSparseAndOnSurfaces)
{
    sim::LidarOptions o;
    o.beam_num_scans = 2;
    o.beam_azimuth_steps = 360;
    o.cubemap_size_px = 256;
    sim::LidarStats st;
    const map::LidarMap m = sim::sampleBeamMap(testWorld(), o, 1, &st);
    EXPECT_EQ(st.sampled, 2u * 32u * 360u);
    EXPECT_GT(m.size(), st.sampled * 9 / 10);  // a closed room returns almost every beam
    const auto b = m.bounds();
    const Eigen::AlignedBox3f room = testWorld().room;
    EXPECT_GT(b.min.x(), room.min().x() - 0.2f);
    EXPECT_LT(b.max.z(), room.max().z() + 0.2f);
}

TEST(StereoRenderer, DeterministicForASeedAndFrame)
{
    const std::string calib = kShared + "/data/euroc/calib/";
    const core::StereoRig rig = core::StereoRig::fromEuroc(calib + "cam0_sensor.yaml", calib + "cam1_sensor.yaml");
    sim::AppearanceOptions ao;
    const mrpt::poses::CPose3D T(0.5, 1.0, 1.3, 0.3, 0.0, -1.6);  // x y z yaw pitch roll: looking across the room
    cv::Mat l1, r1, l2, r2, l3, r3;
    sim::StereoRenderer a(testWorld(), rig, ao, 4);
    a.render({T}, 1.0, 17, l1, r1);
    a.render({T}, 1.0, 17, l2, r2);
    sim::StereoRenderer b(testWorld(), rig, ao, 4);
    b.render({T}, 1.0, 18, l3, r3);
    ASSERT_EQ(l1.size(), cv::Size(752, 480));
    ASSERT_EQ(l1.type(), CV_8UC1);
    EXPECT_EQ(cv::norm(l1, l2, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(r1, r2, cv::NORM_INF), 0.0);
    EXPECT_GT(cv::norm(l1, l3, cv::NORM_L1), 0.0);               // other frame: other noise
    EXPECT_LT(cv::norm(l1, l3, cv::NORM_L1) / l1.total(), 4.0);  // ... but the same scene
    EXPECT_GT(cv::norm(l1, r1, cv::NORM_L1) / l1.total(), 4.0);  // stereo: a different view
    cv::Scalar mean, stddev;
    cv::meanStdDev(l1, mean, stddev);
    EXPECT_GT(mean[0], 40);
    EXPECT_LT(mean[0], 200);
    EXPECT_GT(stddev[0], 10);  // textured, not flat
}
