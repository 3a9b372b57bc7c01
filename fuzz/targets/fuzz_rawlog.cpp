// Fuzz target: rawlogs through our reader (dataset::openRawlog, the frame source of quasiloc-track), reading every
// frame. Stored uncompressed (gzip reads that as is) so that mutations reach the MRPT archive.
#include <quasiloc/dataset/frame_source.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "seq/fuzz.rawlog");
    fuzz::expectCleanError([&] {
        auto source = dataset::openRawlog(path);
        dataset::StereoFrame frame;
        for (int i = 0; i < 64 && source->next(frame); ++i)
        {
        }
        (void)source->warnings();
    });
    return 0;
}
