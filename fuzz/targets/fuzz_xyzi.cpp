// Fuzz target: the Xyzi cloud reader, as map-import runs it (readCloud's checks, then the reflectivity
// normalisation), on the bytes in memory.
#include <quasiloc/map/map_import.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    fuzz::expectCleanError([&] {
        const map::RawCloud cloud =
            map::readCloudBytes(fuzz::bytesOf(data, size), map::CloudFormat::Xyzi, "fuzz-input");
        map::IntensityNormalisation norm = map::chooseIntensityNormalisation(cloud.intensity, 0.0);
        const map::LidarMap m = map::toLidarMap(cloud, norm);
        (void)m.size();
    });
    return 0;
}
