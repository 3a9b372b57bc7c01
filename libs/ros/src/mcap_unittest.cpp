// The MCAP reader on the specification's conformance files (../shared/data/ros2/mcap_conformance: indexed and not,
// with and without a summary) and on files our writer makes in each chunk compression; corrupt files (a chunk, the
// summary, the data section, a cut-off file) are errors naming the file.
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/mcap_reader.h>
#include <quasiloc/ros/mcap_writer.h>

#include "rosbag2_test_helpers.h"

namespace fs = std::filesystem;
using namespace quasiloc::ros;
using namespace quasiloc::ros::test;

namespace
{
struct Read
{
    std::vector<std::tuple<std::string, std::uint64_t, std::vector<std::uint8_t>>> messages;
    mcap::ReadStats stats;
    mcap::Summary summary;
};

Read readMcap(const std::string& path)
{
    mcap::Reader r(path);
    Read out;
    r.readMessages([&](const mcap::MessageView& m) {
        out.messages.emplace_back(m.channel->topic, m.log_time, std::vector<std::uint8_t>(m.data, m.data + m.size));
        return true;
    });
    out.stats = r.stats();
    out.summary = r.summary();
    return out;
}

/** 300 messages on two channels, 2 KB each (several chunks of 64 KB). */
std::string writeTestFile(const std::string& path, const std::string& compression)
{
    mcap::Writer::Options o;
    o.compression = compression;
    o.chunk_bytes = 64 * 1024;
    mcap::Writer w(path, o);
    const auto schema = w.addSchema("std_msgs/msg/String", "ros2msg", "string data\n");
    const auto a = w.addChannel("/a", schema, "cdr", {{"offered_qos_profiles", ""}});
    const auto b = w.addChannel("/b", schema, "cdr", {});
    for (int i = 0; i < 300; ++i)
    {
        std::vector<std::uint8_t> data(2048);
        for (std::size_t k = 0; k < data.size(); ++k) data[k] = std::uint8_t((i * 31 + int(k) * 7) % 251);
        w.write(i % 3 == 0 ? b : a, 1000 + std::uint64_t(i), 1000 + std::uint64_t(i), data);
    }
    w.close();
    return path;
}

void flipByteAt(const std::string& path, std::uint64_t offset)
{
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(std::streamoff(offset));
    char c;
    f.get(c);
    f.seekp(std::streamoff(offset));
    f.put(char(c ^ 0x5A));
}
}  // namespace

TEST(Mcap, EveryConformanceFileReads)
{
    QUASILOC_REQUIRE_ROS2_DATA();
    std::size_t files = 0, with_summary = 0, without = 0;
    for (const char* group : {"OneMessage", "OneAttachment", "OneMetadata"})
        for (const auto& e : fs::directory_iterator(ros2Data(std::string("mcap_conformance/") + group)))
        {
            if (e.path().extension() != ".mcap") continue;
            ++files;
            const Read r = readMcap(e.path().string());
            EXPECT_TRUE(r.stats.data_crc_checked) << e.path();
            (r.summary.present ? with_summary : without)++;
            EXPECT_TRUE(!r.summary.present || r.stats.summary_crc_checked) << e.path();
            if (std::string(group) == "OneMessage")
            {
                ASSERT_EQ(r.messages.size(), 1u) << e.path();
                EXPECT_EQ(std::get<0>(r.messages[0]), "example");
                EXPECT_EQ(std::get<1>(r.messages[0]), 2u);
                EXPECT_EQ(std::get<2>(r.messages[0]), (std::vector<std::uint8_t>{1, 2, 3}));
            }
            else
                EXPECT_TRUE(r.messages.empty()) << e.path();
        }
    EXPECT_EQ(files, 84u);
    EXPECT_EQ(without, 2u);  // OneMessage-ch and OneMessage-ch-mx: no summary, read linearly
    EXPECT_EQ(with_summary, 82u);
}

TEST(Mcap, WrittenFilesReadBackInEachChunkCompression)
{
    TempDir dir;
    std::vector<std::size_t> sizes;
    for (const std::string c : {"", "zstd", "lz4"})
    {
        const std::string path = writeTestFile(dir.path + "/c_" + (c.empty() ? "none" : c) + ".mcap", c);
        sizes.push_back(fs::file_size(path));
        const Read r = readMcap(path);
        ASSERT_EQ(r.messages.size(), 300u) << c;
        EXPECT_GT(r.stats.chunks, 5u) << c;
        EXPECT_EQ(r.stats.chunk_crcs_checked, r.stats.chunks) << c;
        EXPECT_EQ(r.stats.compressions.at(c), r.stats.chunks) << c;
        EXPECT_TRUE(r.stats.data_crc_checked && r.stats.summary_crc_checked) << c;
        EXPECT_TRUE(r.summary.has_statistics);
        EXPECT_EQ(r.summary.message_count, 300u);
        EXPECT_EQ(r.summary.channel_message_counts.at(1), 100u);  // /b: every third message
        for (std::size_t i = 0; i < r.messages.size(); ++i)
        {
            EXPECT_EQ(std::get<1>(r.messages[i]), 1000 + i);
            EXPECT_EQ(std::get<2>(r.messages[i])[1], std::uint8_t((int(i) * 31 + 7) % 251));
        }
    }
    EXPECT_LT(sizes[1], sizes[0]);
    EXPECT_LT(sizes[2], sizes[0]);
}

TEST(Mcap, AChunkWhoseCrcFailsIsAnErrorNamingTheFileAndTheChunk)
{
    TempDir dir;
    for (const std::string c : {"", "zstd", "lz4"})
    {
        const std::string path = writeTestFile(dir.path + "/bad_" + (c.empty() ? "none" : c) + ".mcap", c);
        // 100 bytes into the first chunk's records (after its compression string and records length).
        std::ifstream in(path, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const auto at =
            c.empty() ? std::string::npos : bytes.find(std::string(1, char(c.size())) + std::string(3, '\0') + c);
        flipByteAt(path, c.empty() ? 2000 : at + 4 + c.size() + 8 + 100);
        const std::string e = errorOf([&] { readMcap(path); });
        EXPECT_NE(e.find(path), std::string::npos) << e;
        EXPECT_NE(e.find("chunk at byte"), std::string::npos) << e;
        EXPECT_TRUE(!c.empty() || e.find("chunk CRC mismatch") != std::string::npos) << e;
    }
}

TEST(Mcap, ACorruptSummaryOrDataSectionIsAnErrorNamingTheFile)
{
    TempDir dir;
    const std::string a = writeTestFile(dir.path + "/summary.mcap", "");
    flipByteAt(a, fs::file_size(a) - 60);  // a summary offset record
    std::string e = errorOf([&] { mcap::Reader r(a); });
    EXPECT_NE(e.find("summary CRC mismatch"), std::string::npos) << e;
    const std::string b = writeTestFile(dir.path + "/data.mcap", "");
    flipByteAt(b, 22);  // inside the Header record's profile "ros2": outside any chunk
    e = errorOf([&] { readMcap(b); });
    EXPECT_NE(e.find("data section CRC mismatch"), std::string::npos) << e;
    EXPECT_NE(e.find(b), std::string::npos) << e;
}

TEST(Mcap, ATruncatedFileIsAnErrorNamingIt)
{
    TempDir dir;
    const std::string path = writeTestFile(dir.path + "/cut.mcap", "zstd");
    for (const double keep : {0.9, 0.5, 0.01})
    {
        fs::resize_file(path, std::uintmax_t(fs::file_size(path) * keep));
        const std::string e = errorOf([&] { readMcap(path); });
        EXPECT_NE(e.find(path), std::string::npos) << e;
        EXPECT_TRUE(e.find("truncated") != std::string::npos || e.find("not an MCAP") != std::string::npos) << e;
    }
}
