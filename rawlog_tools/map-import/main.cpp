// map-import: see map_import_app.h and `map-import --help`.
#include <quasiloc/core/program_options.h>

#include "map_import_app.h"

int main(int argc, char** argv)
{
    return quasiloc::core::runProgram(argc, argv, quasiloc::map_import::usage(), quasiloc::map_import::run,
                                      /*config_required=*/false);
}
