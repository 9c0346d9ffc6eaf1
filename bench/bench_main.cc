// main() of every benchmark binary: Google Benchmark's own (benchmark_main), after the process
// setup that the zbrdf CLI does in RunZbrdf (basis/freed_memory.h), so that what is timed runs as
// it does under `zbrdf`.
#include <benchmark/benchmark.h>

#include "basis/freed_memory.h"

int main(int argc, char** argv) {
  zbrdf::KeepFreedMemoryForReuse();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
