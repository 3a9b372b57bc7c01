// ROS 2 bags read from real recordings (../shared/data/ros2, written by rosbag2, the mcap Go library and the rosbags
// Python library): message counts as the recordings' README lists them, the values of known messages, the same
// messages from both storages of one recording, compressed bags, and bad bags (each an error naming the file).
#include <algorithm>
#include <fstream>
#include <map>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/bag_images.h>
#include <quasiloc/ros/cdr.h>

#include "rosbag2_test_helpers.h"

namespace fs = std::filesystem;
using namespace quasiloc::ros;
using namespace quasiloc::ros::test;

namespace
{
std::map<std::string, std::size_t> countsOf(const std::vector<Recorded>& v)
{
    std::map<std::string, std::size_t> n;
    for (const auto& m : v) ++n[m.topic];
    return n;
}

void copyTree(const std::string& from, const std::string& to)
{
    fs::copy(from, to, fs::copy_options::recursive);
    for (const auto& e : fs::recursive_directory_iterator(to))
        fs::permissions(e.path(), fs::perms::owner_write, fs::perm_options::add);
}
}  // namespace

TEST(Rosbag2, MessageCountsOfEveryRecordingAreThoseOfTheReadme)
{
    QUASILOC_REQUIRE_ROS2_DATA();
    const std::vector<std::pair<std::string, std::map<std::string, std::size_t>>> expected = {
        {"rosbag2_talker_sqlite3", {{"/rosout", 10}, {"/topic", 10}}},
        {"rosbag2_talker_mcap", {{"/rosout", 10}, {"/topic", 10}}},
        {"rosbag2_cdr_test_sqlite3", {{"/test_topic", 3}, {"/array_topic", 4}}},
        {"rosbag2_cdr_test_mcap", {{"/test_topic", 3}, {"/array_topic", 4}}},
        {"rosbag2_wbag_split_sqlite3",
         {{"AAA", 804},
          {"BBB", 742},
          {"CCC", 742},
          {"DDD", 753},
          {"EEE", 804},
          {"FFF", 772},
          {"GGG", 731},
          {"HHH", 726}}},
        {"rosbag2_wbag_split_mcap",
         {{"AAA", 804},
          {"BBB", 742},
          {"CCC", 742},
          {"DDD", 753},
          {"EEE", 804},
          {"FFF", 772},
          {"GGG", 731},
          {"HHH", 726}}},
        {"rosbag2_service_events_sqlite3",
         {{"/test_topic1", 1},
          {"/test_topic2", 1},
          {"/test_service1/_service_event", 4},
          {"/test_service2/_service_event", 4}}},
        {"rosbag2_service_events_mcap",
         {{"/test_topic1", 1},
          {"/test_topic2", 1},
          {"/test_service1/_service_event", 4},
          {"/test_service2/_service_event", 4}}},
        {"rosbag2_empty_bag_sqlite3", {}},
        {"rosbag2_seek_sqlite3", {{"topic1", 5}}},
        {"rosbag2_seek_mcap", {{"topic1", 5}}},
        {"rosbag2_file_compression_zstd", {{"/rosout", 392}, {"/topic", 383}}},
        {"rosbag2_message_compression_zstd", {{"/rosout", 758}, {"/topic", 369}}},
        {"rosbag2js_sensor_sample_sqlite3/sample.db3",
         {{"/text", 1}, {"/image", 1}, {"/image/compressed", 1}, {"/fix", 1}, {"/imu", 1}}},
        {"foxglove_chatter_db3/chatter.db3", {{"/chatter", 7}}},
    };
    for (const auto& [bag, counts] : expected)
    {
        const auto messages = readAll(ros2Data(bag));
        EXPECT_EQ(countsOf(messages), counts) << bag;
        EXPECT_TRUE(std::is_sorted(messages.begin(), messages.end(),
                                   [](const Recorded& a, const Recorded& b) { return a.t_ns < b.t_ns; }))
            << bag << ": not in time order";
    }
    for (const char* bag : {"rosbags_rs_all_types_sqlite3", "rosbags_rs_all_types_mcap"})
    {
        const auto counts = countsOf(readAll(ros2Data(bag)));
        EXPECT_EQ(counts.size(), 94u) << bag;
        for (const auto& [topic, n] : counts) EXPECT_EQ(n, 2u) << bag << " " << topic;
    }
}

TEST(Rosbag2, BothStoragesOfOneRecordingGiveTheSameMessages)
{
    QUASILOC_REQUIRE_ROS2_DATA();
    // The MCAP files of these were converted from the SQLite3 ones: the same messages, byte for byte, same times.
    for (const std::string name : {"talker", "cdr_test", "wbag_split", "seek"})
    {
        auto a = readAll(ros2Data("rosbag2_" + name + "_sqlite3"));
        auto b = readAll(ros2Data("rosbag2_" + name + "_mcap"));
        ASSERT_FALSE(a.empty()) << name;
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        EXPECT_TRUE(a == b) << name << ": " << a.size() << " and " << b.size() << " messages";
    }
    // These two were recorded twice, once per storage: the same topics, types and counts (times differ).
    for (const std::string name : {"rosbag2_service_events", "rosbags_rs_all_types"})
    {
        const auto a = openMessageSource(ros2Data(name + "_sqlite3"));
        const auto b = openMessageSource(ros2Data(name + "_mcap"));
        EXPECT_EQ(a->topicTypes(), b->topicTypes()) << name;
        EXPECT_EQ(countsOf(readAll(ros2Data(name + "_sqlite3"))), countsOf(readAll(ros2Data(name + "_mcap")))) << name;
    }
}

TEST(Rosbag2, BasicTypesOfTheCdrTestBagDecode)
{
    QUASILOC_REQUIRE_ROS2_DATA();
    for (const char* bag : {"rosbag2_cdr_test_sqlite3", "rosbag2_cdr_test_mcap"})
    {
        const auto messages = readAll(ros2Data(bag), {"/test_topic"});
        ASSERT_EQ(messages.size(), 3u) << bag;
        for (const auto& m : messages)
        {
            EXPECT_EQ(m.type, "test_msgs/BasicTypes");
            // test_msgs/BasicTypes: bool, byte, char, float32, float64, int8, uint8, int16, uint16, int32, uint32,
            // int64, uint64; rosbag2's test wrote int32_value = 123 and left the rest 0.
            cdr::Reader r(m.payload.data(), m.payload.size(), bag);
            EXPECT_FALSE(r.boolean());
            EXPECT_EQ(r.u8(), 0);
            EXPECT_EQ(r.u8(), 0);
            EXPECT_EQ(r.f32(), 0.0f);
            EXPECT_EQ(r.f64(), 0.0);
            EXPECT_EQ(r.u8(), 0);
            EXPECT_EQ(r.u8(), 0);
            EXPECT_EQ(r.u16(), 0);
            EXPECT_EQ(r.u16(), 0);
            EXPECT_EQ(r.i32(), 123);
            EXPECT_EQ(r.u32(), 0u);
            EXPECT_EQ(r.i64(), 0);
            EXPECT_EQ(r.u64(), 0u);
            EXPECT_EQ(r.remaining(), 0u);
        }
    }
}

TEST(Rosbag2, TheSensorSampleImageImuAndCompressedImageDecode)
{
    QUASILOC_REQUIRE_ROS2_DATA();
    const auto bag = openMessageSource(ros2Data("rosbag2js_sensor_sample_sqlite3/sample.db3"));
    EXPECT_EQ(bag->topicTypes().at("/image"), "sensor_msgs/Image");  // legacy type names read as they are
    int seen = 0;
    bag->read({"/image", "/image/compressed", "/imu"}, [&](const BagMessage& m) -> bool {
        ++seen;
        if (m.topic() == "/image")
        {
            const ImageMsg img = m.image();
            EXPECT_EQ(img.width, 640u);
            EXPECT_EQ(img.height, 480u);
            EXPECT_EQ(img.encoding, "bgr8");
            EXPECT_EQ(img.step, 1920u);
            EXPECT_EQ(img.header.stamp_ns, 0);  // the publisher left it unset: bag2rawlog takes the bag time
            EXPECT_EQ(img.data.size(), 921600u);
            if (img.data.size() < 3) return true;
            EXPECT_EQ(std::vector<std::uint8_t>(img.data.begin(), img.data.begin() + 3),
                      (std::vector<std::uint8_t>{150, 190, 220}));
            const cv::Mat gray = grayFromImageMsg(img, 8, m.where());
            EXPECT_EQ(gray.cols, 640);
            EXPECT_EQ(gray.rows, 480);
        }
        else if (m.topic() == "/imu")
        {
            const ImuMsg imu = m.imu();
            EXPECT_EQ(imu.header.stamp_ns, 1553411909072940288LL);
            EXPECT_EQ(imu.header.frame_id, "base_imu_link");
            EXPECT_DOUBLE_EQ(imu.orientation.x(), -0.00303694183385077);
            EXPECT_DOUBLE_EQ(imu.orientation.y(), -0.821769774654061);
            EXPECT_DOUBLE_EQ(imu.orientation.z(), 0.569725663340332);
            EXPECT_DOUBLE_EQ(imu.orientation.w(), -0.009893582805554232);
            EXPECT_EQ(imu.linear_acceleration, Eigen::Vector3d::Zero());
        }
        else
        {
            const CompressedImageMsg c = m.compressedImage();
            EXPECT_EQ(c.format, "bgr8; jpeg compressed bgr8");
            const cv::Mat gray = grayFromCompressedMsg(c, m.where());
            EXPECT_GT(gray.cols, 0);
        }
        return true;
    });
    EXPECT_EQ(seen, 3);
}

TEST(Rosbag2, EveryMessageTypeBag2rawlogReadsDecodesFromBothStorages)
{
    QUASILOC_REQUIRE_ROS2_DATA();
    for (const char* bag : {"rosbags_rs_all_types_sqlite3", "rosbags_rs_all_types_mcap"})
    {
        const auto src = openMessageSource(ros2Data(bag));
        std::map<std::string, int> decoded;
        std::vector<std::string> topics;
        for (const auto& [topic, type] : src->topicTypes()) topics.push_back(topic);
        src->read(topics, [&](const BagMessage& m) -> bool {
            const std::string& t = m.type();
            // Each decodes (the synthetic Image's data is shorter than step x height: not checked here).
            if (t == types::kImage)
            {
                EXPECT_FALSE(m.image().encoding.empty());
            }
            if (t == types::kCompressedImage) m.compressedImage();
            if (t == types::kImu)
            {
                EXPECT_TRUE(m.imu().angular_velocity.allFinite());
            }
            if (t == types::kCameraInfo) m.cameraInfo();
            if (t == types::kPoseStamped || t == types::kTransformStamped || t == types::kOdometry)
            {
                EXPECT_TRUE(m.pose().position.allFinite());
            }
            if (t == types::kTFMessage) m.transforms();
            ++decoded[t];
            return true;
        });
        for (const char* t : {types::kImage, types::kCompressedImage, types::kImu, types::kCameraInfo,
                              types::kPoseStamped, types::kTransformStamped, types::kOdometry, types::kTFMessage})
            EXPECT_EQ(decoded[t], 2) << bag << " " << t;
    }
}

TEST(Rosbag2, AnUnknownStorageOrCompressionIsAnErrorNamingTheMetadata)
{
    QUASILOC_REQUIRE_ROS2_DATA();
    TempDir dir;
    const std::string bag = dir.path + "/talker";
    copyTree(ros2Data("rosbag2_talker_mcap"), bag);
    const std::string yaml = bag + "/metadata.yaml";
    const auto rewrite = [&](const std::string& from, const std::string& to) {
        std::ifstream in(ros2Data("rosbag2_talker_mcap/metadata.yaml"));
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        text.replace(text.find(from), from.size(), to);
        std::ofstream(yaml) << text;
    };
    rewrite("storage_identifier: mcap", "storage_identifier: leveldb");
    std::string e = errorOf([&] { openMessageSource(bag); });
    EXPECT_NE(e.find("metadata.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find("'leveldb'"), std::string::npos) << e;
    rewrite("compression_format: ''\n  compression_mode: ''", "compression_format: bz2\n  compression_mode: FILE");
    e = errorOf([&] { openMessageSource(bag); });
    EXPECT_NE(e.find("'bz2'"), std::string::npos) << e;
    // A bare file that is neither.
    std::ofstream(dir.path + "/x.bin") << "not a bag at all";
    e = errorOf([&] { openMessageSource(dir.path + "/x.bin"); });
    EXPECT_NE(e.find("x.bin"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown storage"), std::string::npos) << e;
}

TEST(Rosbag2, ATruncatedOrCorruptStorageFileIsAnErrorNamingIt)
{
    QUASILOC_REQUIRE_ROS2_DATA();
    TempDir dir;
    for (const std::string f : {"rosbag2_talker_mcap/talker.mcap", "rosbag2_talker_sqlite3/talker.db3"})
    {
        const std::string cut = dir.path + "/cut_" + fs::path(f).filename().string();
        fs::copy_file(ros2Data(f), cut);
        fs::permissions(cut, fs::perms::owner_write, fs::perm_options::add);
        fs::resize_file(cut, fs::file_size(cut) / 2);
        const std::string e = errorOf([&] { readAll(cut); });
        EXPECT_NE(e.find(cut), std::string::npos) << e;
    }
}
