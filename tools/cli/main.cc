// zbrdf: BRDF acquisition with zonal basis illumination. `zbrdf --help` lists the subcommands.
#include "tools/cli/command.h"

int main(int argc, char** argv) { return zbrdf::cli::RunZbrdf(argc, argv); }
