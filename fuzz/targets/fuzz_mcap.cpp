// Fuzz target: the MCAP reader (libs/ros mcap_reader.h: bag2rawlog's ROS 2 MCAP storage): the footer and summary,
// then every record of the data section, chunks decompressed (zstd, lz4) and CRC-checked.
#include <quasiloc/ros/mcap_reader.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "bag.mcap");
    fuzz::expectCleanError([&] {
        ros::mcap::Reader reader(path);
        std::size_t bytes = 0;
        reader.readMessages([&](const ros::mcap::MessageView& m) {
            bytes += m.size;
            (void)reader.typeOf(*m.channel);
            return true;
        });
    });
    return 0;
}
