#!/usr/bin/env bash
# The test command: installs what is missing, builds, and runs the whole suite with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# The fuzz stage's clang build (below) starts now, in the background and at idle priority
# (SCHED_IDLE: it runs only on a core that the main build and the tests leave idle, e.g. while
# tests wait for Slurm daemons, browsers or simulated network loss). It stays in this session:
# where the kernel groups scheduling by session (autogroup), a new session would get an equal
# share of the CPU whatever its priority. Job control gives it a process group of its own, which
# is stopped as a whole if this script ends early. Its output: build-fuzz/background-build.log.
idle=(nice -n 19)
if chrt --idle 0 true 2>/dev/null; then idle=(chrt --idle 0); fi
mkdir -p build-fuzz
set -m
ZBRDF_FUZZ_BUILD_ONLY=1 "${idle[@]}" bash scripts/fuzz.sh </dev/null >build-fuzz/background-build.log 2>&1 &
fuzz_build=$!
set +m
trap 'kill -- -"$fuzz_build" 2>/dev/null || true' EXIT
bash scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j "$jobs" "$@"
if ! wait "$fuzz_build"; then
  cat build-fuzz/background-build.log >&2
  echo "test: the fuzz targets did not build (build-fuzz/background-build.log above)" >&2
  exit 1
fi
trap - EXIT
cat build-fuzz/background-build.log
# Then every reader of untrusted input under libFuzzer for a bounded time (docs/fuzzing.md):
# a clang build in build-fuzz/, each target for the input count in fuzz/ci_runs.txt (about 20 s
# each on 2 cores, at most 2 x ZBRDF_FUZZ_SECONDS) with a fixed seed, so that every machine does
# the same amount of fuzzing. The issue asked for about 60 s per target;
# that would take the whole suite past its 15-minute budget on 2 cores. `bash scripts/fuzz.sh 600`
# fuzzes longer with fresh seeds.
ZBRDF_FUZZ_SEED=${ZBRDF_FUZZ_SEED:-1} ZBRDF_FUZZ_RUNS_FILE=${ZBRDF_FUZZ_RUNS_FILE:-fuzz/ci_runs.txt} \
  bash scripts/fuzz.sh "${ZBRDF_FUZZ_SECONDS:-30}"
