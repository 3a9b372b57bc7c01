// map-build: see map_build_app.cpp and `map-build --help`.
#include <quasiloc/core/program_options.h>

#include "map_build_app.h"

int main(int argc, char** argv)
{
    return quasiloc::core::runProgram(argc, argv, quasiloc::map_build::usage(), quasiloc::map_build::run);
}
