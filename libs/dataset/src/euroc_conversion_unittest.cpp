#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <mrpt/config/CConfigFileMemory.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/core/trajectory_io.h>
#include <quasiloc/dataset/euroc.h>
#include <quasiloc/dataset/calibration.h>
#include <quasiloc/dataset/euroc_conversion.h>
#include <quasiloc/dataset/frame_source.h>
#include <quasiloc/dataset/ground_truth.h>
#include <quasiloc/dataset/timestamps.h>

#include "test_helpers.h"

namespace fs = std::filesystem;
using namespace quasiloc;
using namespace quasiloc::dataset;
using quasiloc::dataset::test::eurocCam0Groundtruth;
using quasiloc::dataset::test::microEurocFolder;
using quasiloc::dataset::test::TempDir;

namespace
{
Euroc2RawlogOptions options(const TempDir& dir, int max_frames)
{
    Euroc2RawlogOptions o;
    o.input = microEurocFolder();
    o.output = dir / "out/seq.rawlog";
    o.max_frames = max_frames;
    return o;
}

size_t imuRowsUpTo(const EurocSequence& seq, std::int64_t t_ns)
{
    return std::upper_bound(seq.imu_t_ns.begin(), seq.imu_t_ns.end(), t_ns) - seq.imu_t_ns.begin();
}
}  // namespace

TEST(EurocConversion, FirstFramesReadBackPixelExact)
{
    TempDir dir;
    const auto r = convertEurocToRawlog(options(dir, 10));
    const EurocSequence seq = readEurocSequence(microEurocFolder());
    EXPECT_EQ(r.stereo_written, 10u);
    EXPECT_EQ(r.imu_written, imuRowsUpTo(seq, seq.pairs[9].t_ns));
    EXPECT_TRUE(fs::is_regular_file(dir / "out/seq.rawlog"));
    EXPECT_TRUE(fs::is_directory(dir / "out/seq_Images"));
    EXPECT_EQ(r.calib_path, dir / "out/seq_calib.ini");
    EXPECT_TRUE(r.gt_path.empty());

    auto src = openRawlog(r.rawlog_path);
    // Rig from the stereo observations equals the one from sensor.yaml.
    EXPECT_DOUBLE_EQ(src->rig().left.fx, seq.rig.left.fx);
    EXPECT_DOUBLE_EQ(src->rig().right.dist[1], seq.rig.right.dist[1]);
    EXPECT_LT(core::translationDistance(src->rig().T_left_right, seq.rig.T_left_right), 1e-9);
    EXPECT_LT(core::rotationDistanceRad(src->rig().T_body_left, seq.rig.T_body_left), 1e-9);

    StereoFrame frame;
    size_t n = 0, imu_seen = 0;
    while (src->next(frame))
    {
        ASSERT_LT(n, 10u);
        EXPECT_NEAR(frame.timestamp, nsToSeconds(seq.pairs[n].t_ns), 1e-6);
        const cv::Mat left = cv::imread(seq.pairs[n].left_png, cv::IMREAD_UNCHANGED);
        const cv::Mat right = cv::imread(seq.pairs[n].right_png, cv::IMREAD_UNCHANGED);
        EXPECT_EQ(cv::norm(frame.left, left, cv::NORM_INF), 0.0);
        EXPECT_EQ(cv::norm(frame.right, right, cv::NORM_INF), 0.0);
        for (const auto& s : frame.imu)
        {
            const ImuSample& ref = seq.imu[imu_seen++];
            EXPECT_NEAR(s.t, ref.t, 1e-6);
            EXPECT_EQ(s.acc, ref.acc);  // doubles are serialized exactly
            EXPECT_EQ(s.gyro, ref.gyro);
        }
        ++n;
    }
    EXPECT_EQ(n, 10u);
    EXPECT_EQ(imu_seen, r.imu_written);
    EXPECT_TRUE(src->warnings().empty());

    // The calibration INI holds the same rig and the IMU's noise model from imu0/sensor.yaml (biases unmeasured).
    const SensorCalibration calib = loadCalibration(r.calib_path);
    EXPECT_DOUBLE_EQ(calib.rig.left.cy, seq.rig.left.cy);
    EXPECT_LT(core::translationDistance(calib.rig.T_body_left, seq.rig.T_body_left), 1e-9);
    ASSERT_TRUE(calib.imu);
    EXPECT_EQ(calib.imu->rate_hz, 200);
    EXPECT_DOUBLE_EQ(calib.imu->gyroscope_noise_density, 1.6968e-04);
    EXPECT_DOUBLE_EQ(calib.imu->accelerometer_random_walk, 3.0e-3);
    EXPECT_EQ(calib.imu->gyroscope_bias_sigma, kUnknownGyroBiasSigma);
}

TEST(EurocConversion, FullMicroSequenceCounts)
{
    TempDir dir;
    const auto r = convertEurocToRawlog(options(dir, 0));
    const EurocSequence seq = readEurocSequence(microEurocFolder());
    EXPECT_EQ(r.stereo_written, seq.pairs.size());
    EXPECT_EQ(r.imu_written, seq.imu.size());  // the whole imu0/data.csv, also after the last frame
    EXPECT_EQ(r.skipped_rows, seq.cam1_rows - seq.pairs.size());
    ASSERT_EQ(r.skipped_rows_report.size(), 1u);

    auto src = openRawlog(r.rawlog_path);
    StereoFrame frame;
    size_t frames = 0, imu = 0;
    while (src->next(frame))
    {
        ++frames;
        imu += frame.imu.size();
    }
    EXPECT_EQ(frames, seq.pairs.size());
    EXPECT_EQ(imu, imuRowsUpTo(seq, seq.pairs.back().t_ns));
}

TEST(EurocConversion, TumGroundTruthRestrictedAndAttached)
{
    TempDir dir;
    Euroc2RawlogOptions o = options(dir, 0);
    o.groundtruth = eurocCam0Groundtruth();
    o.gt_out = dir / "gt.tum";
    const auto r = convertEurocToRawlog(o);
    ASSERT_EQ(r.gt_path, o.gt_out);
    const core::Trajectory written = core::readTum(r.gt_path);
    const core::Trajectory input = core::readTum(o.groundtruth);
    ASSERT_FALSE(written.poses.empty());
    EXPECT_NE(written.header.find("T_world_cam0"), std::string::npos);
    for (size_t i = 1; i < written.poses.size(); ++i) EXPECT_GT(written.poses[i].t, written.poses[i - 1].t);
    EXPECT_GE(written.poses.front().t, r.first_frame_t - 1.0);
    EXPECT_LE(written.poses.back().t, r.last_frame_t + 1.0);
    // Every input pose in the span is there (duplicates once), unchanged.
    size_t in_span = 0;
    for (size_t i = 0; i < input.poses.size(); ++i)
        if (input.poses[i].t >= r.first_frame_t - 1.0 && input.poses[i].t <= r.last_frame_t + 1.0 &&
            (i == 0 || input.poses[i].t != input.poses[i - 1].t))
            ++in_span;
    EXPECT_EQ(written.poses.size(), in_span);

    // Read back with the written ground truth: frames get a pose when one is within 5 ms (no extrapolation
    // before ground truth begins).
    FrameSourceOptions so;
    so.groundtruth_tum = r.gt_path;
    auto src = openRawlog(r.rawlog_path, so);
    StereoFrame frame;
    size_t with_gt = 0;
    while (src->next(frame))
    {
        const bool covered = frame.timestamp >= written.poses.front().t - 0.005;
        EXPECT_EQ(frame.T_world_cam0.has_value(), covered) << "frame " << frame.index;
        if (!frame.T_world_cam0) continue;
        ++with_gt;
        mrpt::poses::CPose3D ref;
        ASSERT_TRUE(core::interpolatePose(written, frame.timestamp, ref, 0.005));
        EXPECT_LT(core::translationDistance(*frame.T_world_cam0, ref), 1e-6);
    }
    EXPECT_EQ(with_gt, r.frames_with_gt);
    EXPECT_GT(with_gt, 0u);
    EXPECT_LT(with_gt, r.stereo_written);  // the micro sequence begins before its ground truth
    ASSERT_EQ(src->warnings().size(), 1u);
    EXPECT_NE(src->warnings()[0].find("without a ground-truth pose"), std::string::npos);
}

TEST(EurocConversion, EurocBodyGroundTruthIsMultipliedByTBodyCam0)
{
    TempDir dir;
    const EurocSequence seq = readEurocSequence(microEurocFolder());
    // A synthetic state_groundtruth_estimate0/data.csv (T_world_body) over the first frames.
    const mrpt::poses::CPose3D T_world_body(1.0, 2.0, 0.5, 0.3, -0.1, 0.2);
    const Eigen::Quaterniond q = core::quaternionOf(T_world_body);
    {
        std::ofstream csv(dir / "body.csv");
        csv.precision(17);
        csv << "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
               "v_x, v_y, v_z, bw_x, bw_y, bw_z, ba_x, ba_y, ba_z\n";
        for (size_t i = 0; i < 5; ++i)
            csv << seq.pairs[i].t_ns << "," << T_world_body.x() << "," << T_world_body.y() << "," << T_world_body.z()
                << "," << q.w() << "," << q.x() << "," << q.y() << "," << q.z() << ",0,0,0,0,0,0,0,0,0\n";
    }
    Euroc2RawlogOptions o = options(dir, 5);
    o.groundtruth = dir / "body.csv";
    const auto r = convertEurocToRawlog(o);
    EXPECT_EQ(r.gt_kind, "EuRoC body csv x T_body_cam0");
    EXPECT_EQ(r.frames_with_gt, 5u);
    const core::Trajectory written = core::readTum(r.gt_path);
    ASSERT_EQ(written.poses.size(), 5u);
    const mrpt::poses::CPose3D expected = T_world_body + seq.rig.T_body_left;
    for (const auto& p : written.poses)
    {
        EXPECT_LT(core::translationDistance(p.pose, expected), 1e-6);
        EXPECT_LT(core::rotationDistanceRad(p.pose, expected), 1e-6);
    }
}

TEST(EurocConversion, BadInputLeavesNoOutput)
{
    TempDir dir;
    Euroc2RawlogOptions o = options(dir, 3);
    o.input = dir / "no_such_folder";
    test::expectInputErrorMentioning([&] { convertEurocToRawlog(o); }, "no_such_folder");
    o = options(dir, 3);
    o.groundtruth = dir / "missing_gt.txt";
    test::expectInputErrorMentioning([&] { convertEurocToRawlog(o); }, "missing_gt.txt");
    // Ground truth of another time span.
    std::ofstream(dir / "other.txt") << "10.0 0 0 0 0 0 0 1\n11.0 0 0 0 0 0 0 1\n";
    o.groundtruth = dir / "other.txt";
    test::expectInputErrorMentioning([&] { convertEurocToRawlog(o); }, "other.txt");
    o = options(dir, 3);
    o.max_frames = -1;
    test::expectInputErrorMentioning([&] { convertEurocToRawlog(o); }, "max_frames");
    EXPECT_FALSE(fs::exists(dir / "out/seq.rawlog"));
    EXPECT_FALSE(fs::exists(dir / "out/seq_Images"));
    EXPECT_FALSE(fs::exists(dir / "out/seq_calib.ini"));
}

TEST(RawlogSource, CorruptRawlogOrImagesNameTheFile)
{
    TempDir dir;
    test::expectInputErrorMentioning([&] { openRawlog(dir / "none.rawlog"); }, "none.rawlog");
    std::ofstream(dir / "garbage.rawlog") << "this is not a rawlog at all, just some text bytes";
    test::expectInputErrorMentioning([&] { openRawlog(dir / "garbage.rawlog"); }, "garbage.rawlog");

    // Truncated rawlogs, plain (level 0: the cut falls inside an observation) and gzipped.
    const auto readAll = [](const std::string& path) {
        auto src = openRawlog(path);
        StereoFrame f;
        while (src->next(f))
        {}
    };
    for (int level : {0, 1})
    {
        Euroc2RawlogOptions o = options(dir, 3);
        o.gz_compression_level = level;
        const auto r = convertEurocToRawlog(o);
        const std::string cut = dir / ("out/cut" + std::to_string(level) + ".rawlog");
        fs::copy_file(r.rawlog_path, cut);
        fs::copy(r.images_folder, dir / ("out/cut" + std::to_string(level) + "_Images"));
        readAll(cut);  // intact copy reads fine
        fs::resize_file(cut, fs::file_size(cut) - 100);
        test::expectInputErrorMentioning([&] { readAll(cut); }, cut);
    }
    const auto r = convertEurocToRawlog(options(dir, 3));

    // An image of the wrong size in the images folder.
    const EurocSequence seq = readEurocSequence(microEurocFolder());
    const std::string second_right = r.images_folder + "/stereo_" + std::to_string(seq.pairs[1].t_ns) + "_right.png";
    ASSERT_TRUE(fs::is_regular_file(second_right));
    cv::imwrite(second_right, cv::Mat(100, 200, CV_8UC1, cv::Scalar(3)));
    auto src = openRawlog(r.rawlog_path);
    StereoFrame f;
    EXPECT_TRUE(src->next(f));
    test::expectInputErrorMentioning([&] { src->next(f); }, second_right);
}

TEST(EurocConversion, OptionsLoadStrictlyAndTheSavedOnesLoadBack)
{
    Euroc2RawlogOptions o;
    o.input = "/data/mav0";
    o.max_frames = 7;
    o.gt_margin_s = 0.25;
    mrpt::config::CConfigFileMemory saved;
    o.saveToConfigFile(saved, "Euroc2Rawlog");
    Euroc2RawlogOptions back;
    core::loadOptionsChecked(back, saved, "Euroc2Rawlog", "x_euroc2rawlog.ini");
    EXPECT_EQ(back.input, o.input);
    EXPECT_EQ(back.groundtruth, "");  // empty stays empty
    EXPECT_EQ(back.max_frames, 7);
    EXPECT_EQ(back.gt_margin_s, 0.25);
    mrpt::config::CConfigFileMemory typo;
    typo.setContent("[Euroc2Rawlog]\ninput = a\nmax_frame = 3\n");
    test::expectInputErrorMentioning([&] { core::loadOptionsChecked(back, typo, "Euroc2Rawlog", "my.ini"); },
                                     "my.ini [Euroc2Rawlog] max_frame");
    mrpt::config::CConfigFileMemory bad;
    bad.setContent("[Euroc2Rawlog]\ngz_compression_level = 10\n");
    test::expectInputErrorMentioning([&] { core::loadOptionsChecked(back, bad, "Euroc2Rawlog", "my.ini"); },
                                     "my.ini [Euroc2Rawlog] gz_compression_level");
}
