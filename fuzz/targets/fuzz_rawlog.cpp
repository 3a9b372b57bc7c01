// Fuzz target: rawlogs through our reader (dataset::openRawlog, the frame source of quasiloc-track), reading every
// frame. Stored uncompressed (gzip reads that as is) so that mutations reach the MRPT archive.
#include <quasiloc/dataset/frame_source.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "seq/fuzz.rawlog");
    fuzz::expectCleanError([&] {
        // MRPT reads the classes the reader does not parse in a child process; an input of at most 16 KB is read
        // in milliseconds, so a child that has not answered in 1 s will not: killed sooner than the default 10 s.
        dataset::FrameSourceOptions options;
        options.mrpt_object_timeout_s = 1;
        auto source = dataset::openRawlog(path, options);
        dataset::StereoFrame frame;
        for (int i = 0; i < 64 && source->next(frame); ++i)
        {}
        (void)source->warnings();
    });
    return 0;
}
