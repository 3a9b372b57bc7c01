// Fuzz target: the relocalization database (.qdb) through Database::load. Like the map file a gz-compressed
// MRPT archive, read as is when not compressed: the seeds are stored uncompressed.
#include <quasiloc/reloc/database.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    const std::string path = fuzz::writeInput(data, size, "database.qdb");
    fuzz::expectCleanError([&] { (void)reloc::Database::load(path).views.size(); });
    return 0;
}
