// Fuzz target: the LidarMap file (map-import's output, every program's map input) through LidarMap::load. The
// file is a gz-compressed MRPT archive; gzip reads an uncompressed file as is, so the seeds are stored
// uncompressed and the mutations reach the archive itself.
#include <quasiloc/map/lidar_map.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "map.bin");
    fuzz::expectCleanError([&] { (void)map::LidarMap::load(path).size(); });
    return 0;
}
