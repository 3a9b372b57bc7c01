// Fuzz target: the rosbag2 SQLite3 storage reader (libs/ros sqlite_bag.h, on Debian's libsqlite3): the topics
// table, then every message in timestamp order, then the counts per topic.
#include <quasiloc/ros/sqlite_bag.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "bag.db3");
    fuzz::expectCleanError([&] {
        ros::SqliteBagFile bag(path);
        std::size_t bytes = 0;
        bag.read({}, [&](const ros::SqliteBagFile::Message& m) {
            bytes += m.size;
            return true;
        });
        (void)bag.messageCounts();
    });
    return 0;
}
