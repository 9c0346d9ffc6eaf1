// zbrdf-faults: the zbrdf command line with a write fault planned (basis/atomic_file.h), for the
// crash-test harness (crash_test.cc) to run the real commands and break them.
//
//   ZBRDF_WRITE_FAULT=KIND:OPERATION[:FRACTION[:PATH_PART]] zbrdf-faults <command> [options]
//
// KIND is nospace, eio, short or kill; OPERATION the 1-based write operation it hits (counting
// only paths containing PATH_PART, if given); FRACTION the share of the bytes written first
// (default 0.5). Without the variable it is zbrdf. On exit it prints to stderr
// "zbrdf-faults: N write operations".
#include <cstdio>
#include <cstdlib>
#include <string>

#include "basis/atomic_file.h"
#include "tools/cli/command.h"

namespace {

void PrintWriteOperations() {
  std::fprintf(stderr, "zbrdf-faults: %lld write operations\n",
               static_cast<long long>(zbrdf::WriteOperationCount()));
}

}  // namespace

int main(int argc, char** argv) {
  if (const char* spec = std::getenv("ZBRDF_WRITE_FAULT")) {
    std::string parts[4];
    int n = 0;
    for (const char* c = spec; *c != '\0' && n < 4; ++c) {
      if (*c == ':' && n < 3) {
        ++n;
      } else {
        parts[n] += *c;
      }
    }
    zbrdf::WriteFaultPlan plan;
    try {
      plan.fault = zbrdf::ParseWriteFault(parts[0]);
      plan.operation = std::stoll(parts[1]);
      plan.fraction = parts[2].empty() ? 0.5 : std::stod(parts[2]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "zbrdf-faults: bad ZBRDF_WRITE_FAULT '%s': %s\n", spec, e.what());
      return 2;
    }
    plan.path_contains = parts[3];
    zbrdf::SetWriteFaultPlan(plan);
  }
  std::atexit(PrintWriteOperations);
  return zbrdf::cli::RunZbrdf(argc, argv);
}
