#pragma once
// Shared by the ROS 2 bag unit tests: the recordings of ../shared/data/ros2 (README.md there lists them; read in
// place, never copied), a temporary folder, and a reader of every message of a bag.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <quasiloc/ros/message_source.h>
#include <string>
#include <tuple>
#include <vector>

namespace quasiloc::ros::test
{
inline std::string ros2Data(const std::string& relative)
{
    return (std::filesystem::path(QUASILOC_SHARED_DIR) / "data" / "ros2" / relative).string();
}

/** Skips the test (a clear message) when the shared data is not on this machine. */
#define QUASILOC_REQUIRE_ROS2_DATA()                                       \
    if (!std::filesystem::is_directory(quasiloc::ros::test::ros2Data(""))) \
    GTEST_SKIP() << "no " << quasiloc::ros::test::ros2Data("") << " (QUASILOC_SHARED_DIR)"

struct TempDir
{
    std::string path;
    TempDir()
    {
        std::string tmpl = (std::filesystem::temp_directory_path() / "quasiloc_ros2_XXXXXX").string();
        if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
        path = tmpl;
    }
    ~TempDir() { std::filesystem::remove_all(path); }
};

struct Recorded
{
    std::string topic, type;
    std::int64_t t_ns;
    std::vector<std::uint8_t> payload;
    bool operator<(const Recorded& o) const
    {
        return std::tie(t_ns, topic, payload) < std::tie(o.t_ns, o.topic, o.payload);
    }
    bool operator==(const Recorded& o) const
    {
        return std::tie(t_ns, topic, type, payload) == std::tie(o.t_ns, o.topic, o.type, o.payload);
    }
};

inline std::vector<Recorded> readAll(const std::string& path, const std::vector<std::string>& topics = {})
{
    std::vector<Recorded> v;
    openMessageSource(path)->read(topics, [&](const BagMessage& m) {
        v.push_back({m.topic(), m.type(), m.timeNs(), m.payload()});
        return true;
    });
    return v;
}

inline std::string errorOf(const std::function<void()>& f)
{
    try
    {
        f();
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return "(no error)";
}

}  // namespace quasiloc::ros::test
