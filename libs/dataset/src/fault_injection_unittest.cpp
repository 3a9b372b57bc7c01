// The fault injector on a synthetic stream: 20 Hz frames (each image filled with its frame number) and a 200 Hz IMU.
#include <gtest/gtest.h>

#include <cmath>
#include <quasiloc/core/error.h>
#include <quasiloc/dataset/fault_injection.h>

using namespace quasiloc;
using dataset::FaultInjectingSource;
using dataset::FaultInjectionOptions;
using dataset::StereoFrame;

namespace
{
constexpr double kT0 = 100.0, kFramePeriod = 0.05, kImuPeriod = 0.005;

class SyntheticSource : public dataset::FrameSource
{
   public:
    explicit SyntheticSource(int frames, Eigen::Vector3d gyro = Eigen::Vector3d::Zero()) : frames_(frames), gyro_(gyro)
    {
        rig_.left = rig_.right = core::CameraModel::pinhole(40, 30, 100, 100, 19.5, 14.5);
    }
    const core::StereoRig& rig() const override { return rig_; }
    std::string description() const override { return "synthetic"; }
    bool next(StereoFrame& f) override
    {
        if (k_ >= frames_) return false;
        f = StereoFrame{};
        f.index = size_t(k_);
        f.timestamp = kT0 + k_ * kFramePeriod;
        f.left = cv::Mat(30, 40, CV_8UC1, cv::Scalar(k_ % 50 + 10));
        f.right = cv::Mat(30, 40, CV_8UC1);
        for (int u = 0; u < 40; ++u) f.right.col(u).setTo(5 * u);  // a horizontal ramp: a turn shifts it
        for (int i = 9; i >= 0; --i)  // the samples since the previous frame, up to this one's time
            if (k_ > 0 || i == 0) f.imu.push_back({f.timestamp - i * kImuPeriod, {}, gyro_});
        ++k_;
        return true;
    }

   private:
    core::StereoRig rig_;
    int frames_, k_ = 0;
    Eigen::Vector3d gyro_;
};

std::vector<StereoFrame> readAll(const FaultInjectionOptions& o, int frames = 100,
                                 Eigen::Vector3d gyro = Eigen::Vector3d::Zero())
{
    FaultInjectingSource source(std::make_unique<SyntheticSource>(frames, gyro), o);
    std::vector<StereoFrame> out;
    StereoFrame f;
    while (source.next(f)) out.push_back(f);
    return out;
}

size_t imuSamples(const std::vector<StereoFrame>& frames)
{
    size_t n = 0;
    for (const auto& f : frames) n += f.imu.size();
    return n;
}
}  // namespace

TEST(FaultInjection, OffByDefaultTheFramesPassUnchanged)
{
    const FaultInjectionOptions o;
    EXPECT_FALSE(o.any());
    const auto frames = readAll(o);
    ASSERT_EQ(frames.size(), 100u);
    EXPECT_EQ(imuSamples(frames), 991u);
}

TEST(FaultInjection, ABurstDropsTheWindowsFramesButKeepsTheirImuSamples)
{
    FaultInjectionOptions o;
    o.drop_from_s = 1.0, o.drop_duration_s = 0.5;
    const auto frames = readAll(o);
    EXPECT_EQ(frames.size(), 90u);
    EXPECT_EQ(imuSamples(frames), 991u) << "a camera that drops frames leaves the IMU alone";
    for (const auto& f : frames) EXPECT_FALSE(f.timestamp - kT0 >= 1.0 - 1e-9 && f.timestamp - kT0 < 1.5 - 1e-9);
}

TEST(FaultInjection, RandomDropsTakeTheirShareAndFollowTheSeed)
{
    FaultInjectionOptions o;
    o.drop_from_s = 0.0, o.drop_duration_s = 100, o.drop_ratio = 0.1;
    const auto a = readAll(o, 1000), b = readAll(o, 1000);
    EXPECT_NEAR(double(a.size()), 900.0, 30.0);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].timestamp, b[i].timestamp);
}

TEST(FaultInjection, AnImuGapRemovesTheSamplesInsideIt)
{
    FaultInjectionOptions o;
    o.imu_gap_from_s = 1.0, o.imu_gap_duration_s = 0.1;
    const auto frames = readAll(o);
    EXPECT_EQ(frames.size(), 100u);
    EXPECT_NEAR(double(imuSamples(frames)), 991.0 - 20.0, 1.0);  // 0.1 s at 200 Hz (a sample on the edge may go)
    for (const auto& f : frames)
        for (const auto& s : f.imu) EXPECT_FALSE(s.t - kT0 >= 1.0 && s.t - kT0 < 1.1 - 1e-9) << s.t - kT0;
}

TEST(FaultInjection, BlackAndSaturatedImagesCoverTheirWindow)
{
    for (const auto fault : {dataset::ImageFault::Black, dataset::ImageFault::Saturated})
    {
        FaultInjectionOptions o;
        o.image_fault = fault, o.image_from_s = 1.0, o.image_duration_s = 1.0;
        int faulty = 0;
        for (const auto& f : readAll(o))
        {
            const double expected = fault == dataset::ImageFault::Black ? 0 : 255;
            if (std::abs(cv::mean(f.left)[0] - expected) < 0.5 && std::abs(cv::mean(f.right)[0] - expected) < 0.5)
                ++faulty;
        }
        EXPECT_EQ(faulty, 20);
    }
}

TEST(FaultInjection, DesyncTurnsTheRightImageByTheRotationOverTheDelay)
{
    FaultInjectionOptions o;
    o.desync_from_s = 1.0, o.desync_duration_s = 0.5, o.desync_ms = 20;
    // 1 rad/s about the camera's y axis (body = camera here): 0.02 rad in 20 ms, 2 px at f = 100 px; the ramp of
    // 5 grey levels per pixel then reads 10 more at the centre.
    const auto frames = readAll(o, 100, Eigen::Vector3d(0, 1, 0));
    ASSERT_EQ(frames.size(), 100u);
    int turned = 0;
    for (const auto& f : frames)
    {
        const int centre = f.right.at<uint8_t>(15, 20);
        if (centre == 100) continue;
        EXPECT_NEAR(centre, 110, 1);
        ++turned;
    }
    EXPECT_EQ(turned, 10);
    // Without rotation the right image is unchanged.
    for (const auto& f : readAll(o)) EXPECT_EQ(f.right.at<uint8_t>(15, 20), 100);
}

TEST(FaultInjection, DuplicateAndOutOfOrderTimestampsAreYielded)
{
    FaultInjectionOptions o;
    o.duplicate_at_s = 1.0, o.reorder_at_s = 2.0;
    const auto frames = readAll(o);
    ASSERT_EQ(frames.size(), 101u);
    EXPECT_EQ(imuSamples(frames), 991u);
    int repeated = 0, backwards = 0;
    for (size_t i = 1; i < frames.size(); ++i)
    {
        repeated += frames[i].timestamp == frames[i - 1].timestamp;
        backwards += frames[i].timestamp < frames[i - 1].timestamp;
        EXPECT_EQ(frames[i].index, i);
    }
    EXPECT_EQ(repeated, 1);
    EXPECT_EQ(backwards, 1);
}

TEST(FaultInjection, OptionsOutOfRangeAreRejected)
{
    FaultInjectionOptions o;
    o.drop_ratio = 1.5;
    EXPECT_THROW(FaultInjectingSource(std::make_unique<SyntheticSource>(1), o), core::InputError);
}
