// zbrdf version: prints the software version (also recorded in every session.json).
#include <iostream>

#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

int RunVersion(const std::vector<std::string>& args) {
  CommandLine cl("version", "Print the zbrdf version.");
  if (!cl.Parse(args)) return 0;
  std::cout << "zbrdf " << ZBRDF_VERSION << "\n";
  return 0;
}

const CommandRegistration kVersionCommand({"version", "print the zbrdf version", RunVersion});

}  // namespace
}  // namespace zbrdf::cli
