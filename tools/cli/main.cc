// zbrdf: BRDF acquisition with zonal basis illumination. `zbrdf --help` lists the subcommands.
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "basis/error.h"
#include "tools/cli/command.h"

namespace {

void PrintUsage() {
  std::cout << "usage: zbrdf <command> [options]   (zbrdf <command> --help for each)\n\n"
               "Measure, simulate, fit and export BRDFs captured with zonal basis "
               "illumination.\n\ncommands:\n";
  for (const auto& [name, command] : zbrdf::cli::CommandTable()) {
    std::cout << "  " << name << std::string(name.size() < 16 ? 16 - name.size() : 1, ' ')
              << command.summary << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h" ||
      std::string(argv[1]) == "help") {
    PrintUsage();
    return argc < 2 ? 2 : 0;
  }
  const std::string name = argv[1];
  auto& table = zbrdf::cli::CommandTable();
  auto it = table.find(name);
  if (it == table.end()) {
    std::cerr << "zbrdf: unknown command '" << name << "' (zbrdf --help lists them)\n";
    return 2;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  try {
    return it->second.run(args);
  } catch (const zbrdf::InputError& e) {
    std::cerr << "zbrdf " << name << ": error: " << e.what() << "\n";
    return 2;
  } catch (const zbrdf::DeviceError& e) {
    std::cerr << "zbrdf " << name << ": device error: " << e.what() << "\n";
    return 3;
  } catch (const zbrdf::NumericalError& e) {
    std::cerr << "zbrdf " << name << ": numerical failure: " << e.what() << "\n";
    return 4;
  } catch (const std::exception& e) {
    std::cerr << "zbrdf " << name << ": error: " << e.what() << "\n";
    return 1;
  }
}
