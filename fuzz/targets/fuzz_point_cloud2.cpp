// Fuzz target: map-build's bag scans (libs/ros point_cloud2.h): a sensor_msgs/PointCloud2 CDR message (with its
// encapsulation header) decoded by cdr::readPointCloud2, then its points by scanFromPointCloud2 (field roles, types,
// byte order, point_step / row_step, organised rows, truncated data; libs/map point_records.h). Seeds: messages of
// the drivers' layouts written by cdr::encode (fuzz/seeds/make_seeds.cpp).
#include <quasiloc/ros/point_cloud2.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc::ros;
    quasiloc::fuzz::expectCleanError([&] {
        cdr::Reader r(data, size, "fuzz");
        (void)scanFromPointCloud2(cdr::readPointCloud2(r), "fuzz");
    });
    return 0;
}
