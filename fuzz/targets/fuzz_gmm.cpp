// Fuzz target: GMMLoc .gmm maps (protobuf wire format decoded by hand), from memory.
#include <quasiloc/map/gmm.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using namespace quasiloc;
    fuzz::expectCleanError([&] { (void)map::decodeGmm(fuzz::bytesOf(data, size), "fuzz-input.gmm").size(); });
    return 0;
}
