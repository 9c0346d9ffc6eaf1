#!/usr/bin/env bash
# The fuzz stage (docs/fuzzing.md): builds the libFuzzer targets of fuzz/ with clang, ASan and
# UBSan into build-fuzz/, then runs each on a copy of its seed corpus (fuzz/corpus/<target>/,
# never modified) for SECONDS (default 60), two at a time. Fails naming the target and the input
# that crashed, hung (> 10 s) or ran out of memory (> 2 GB), with the command that reproduces it.
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]     e.g. bash scripts/fuzz.sh 600 rig_fuzz
# Environment: ZBRDF_FUZZ_JOBS (targets at a time, 2), ZBRDF_FUZZ_BUILD_DIR (build-fuzz),
# ZBRDF_FUZZ_SEED (libFuzzer's -seed; 0, the default, draws a new one each run),
# ZBRDF_FUZZ_RUNS_FILE (lines "target count": run that many inputs instead of SECONDS, stopping
# after 2 x SECONDS at the latest. The test command uses fuzz/ci_runs.txt), ZBRDF_FUZZ_BUILD_ONLY
# (1: build the targets and stop; the test command builds them in the background this way).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
seconds=${1:-60}
shift || true
jobs=${ZBRDF_FUZZ_JOBS:-2}
build=${ZBRDF_FUZZ_BUILD_DIR:-build-fuzz}
seed=${ZBRDF_FUZZ_SEED:-0}
runs_file=${ZBRDF_FUZZ_RUNS_FILE:-}
if [[ -n $runs_file && ! -f $runs_file ]]; then
  echo "fuzz: ZBRDF_FUZZ_RUNS_FILE $runs_file does not exist" >&2
  exit 2
fi
if ! [[ $seconds =~ ^[0-9]+$ ]] || ((seconds < 1)); then
  echo "fuzz: SECONDS must be a positive whole number, got '$seconds'" >&2
  exit 2
fi
if ! command -v clang++ >/dev/null; then
  echo "fuzz: clang++ not found; run scripts/setup.sh (it installs clang and libclang-rt-14-dev)" >&2
  exit 2
fi

start=$SECONDS
generator=()
command -v ninja >/dev/null && [[ ! -f $build/CMakeCache.txt ]] && generator=(-G Ninja)
cmake -S . -B "$build" "${generator[@]}" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=Release -DZBRDF_BUILD_FUZZERS=ON -DZBRDF_BUILD_TESTS=OFF \
  -DZBRDF_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --target zbrdf_fuzzers -j "$jobs"
build_s=$((SECONDS - start))
if [[ ${ZBRDF_FUZZ_BUILD_ONLY:-0} == 1 ]]; then
  echo "fuzz: built the targets in ${build_s} s (ZBRDF_FUZZ_BUILD_ONLY=1: not running them)"
  exit 0
fi

if (($# > 0)); then
  targets=("$@")
else
  mapfile -t targets < <(grep -v '^$' "$build/fuzz/fuzz_targets.txt")
fi
if [[ -n $runs_file ]]; then
  how="for the input count in $runs_file (at most $((2 * seconds)) s)"
else
  how="for ${seconds} s"
fi

runs="$build/fuzz/runs"
# What every run of a target gets, the fuzzing and a finding's second run alike: UBSan findings
# abort with a stack trace, an input may take 10 s and 2 GB.
ubsan_options=print_stacktrace=1:halt_on_error=1
limits=(-timeout=10 -rss_limit_mb=2048)
# Each target runs on a CPU of its own while there are no more targets at a time than CPUs this
# process may use: unpinned, two targets' processes share and swap both CPUs, and every mmap and
# munmap of ASan's allocator (one per block over 128 kB: OpenEXR's line buffers, zstd's
# contexts) then flushes the other CPU's TLB as well, by an interrupt that costs a hypervisor call
# on a VM. Measured on 2 cores, dbrdf_file_fuzz and frame_file_fuzz side by side, twice each:
# unpinned 59 s and 27 s for the first's 60000 inputs, 170k and 293k of the second's 300000 in its
# 60 s; pinned 25 s twice, and 298k and 300k. Pinning changes no input a target runs.
mapfile -t usable_cpus < <(awk '/^Cpus_allowed_list:/ {
    n = split($2, parts, ",")
    for (i = 1; i <= n; i++) {
      if (split(parts[i], r, "-") == 2) { for (c = r[1]; c <= r[2]; c++) print c } else print parts[i]
    }
  }' /proc/self/status 2>/dev/null)
pin_targets=0
if command -v taskset >/dev/null && ((${#usable_cpus[@]} > 0 && jobs <= ${#usable_cpus[@]})); then
  pin_targets=1
fi
pinned=""
((pin_targets)) && pinned=", each on a CPU of its own"
echo "fuzz: built ${#targets[@]} targets in ${build_s} s; running each $how, seed $seed, $jobs at a time$pinned"
declare -A cpu_of_job  # a running target's process id -> the CPU it is pinned to
# A usable CPU that no running target is pinned to (empty where targets are not pinned).
free_cpu() {
  ((pin_targets)) || return 0
  local running=" $(jobs -rp | tr '\n' ' ') " taken=" " pid cpu
  for pid in "${!cpu_of_job[@]}"; do
    if [[ $running == *" $pid "* ]]; then taken+="${cpu_of_job[$pid]} "; fi
  done
  for cpu in "${usable_cpus[@]}"; do
    if [[ $taken != *" $cpu "* ]]; then
      echo "$cpu"
      return 0
    fi
  done
}

# One target: a scratch copy of the seeds (libFuzzer adds what it finds to it), findings and the
# log in runs/<target>/; its exit status in runs/<target>/status. On CPU $2 if one is given.
run_target() {
  local target=$1 dir="$runs/$1" pin=()
  [[ -n ${2:-} ]] && pin=(taskset -c "$2")
  rm -rf "$dir"
  mkdir -p "$dir/corpus" "$dir/findings"
  if [[ -d fuzz/corpus/$target ]]; then cp -r "fuzz/corpus/$target/." "$dir/corpus/"; fi
  local status=0 budget=(-max_total_time="$seconds")
  if [[ -n $runs_file ]]; then
    local count
    count=$(awk -v t="$target" '$1 == t { print $2 }' "$runs_file")
    if [[ -z $count ]]; then
      echo "fuzz: $target has no line in $runs_file; add one ('$target COUNT')" >&2
      echo 2 >"$dir/status"
      return
    fi
    budget=(-runs="$count" -max_total_time=$((2 * seconds)))
  fi
  # ASan records no call stack at each allocation while fuzzing (malloc_context_size=0): 6% less
  # time over every target's corpus, 10-25% on the YAML readers (docs/fuzzing.md). A finding's
  # report then lacks its allocation and free stacks, so each finding is run once more with them
  # below.
  ASAN_OPTIONS=${ASAN_OPTIONS:-malloc_context_size=0} UBSAN_OPTIONS=$ubsan_options "${pin[@]}" \
    "$build/fuzz/$target" "${budget[@]}" -seed="$seed" "${limits[@]}" \
    -print_final_stats=1 -artifact_prefix="$dir/findings/" "$dir/corpus" >"$dir/log" 2>&1 ||
    status=$?
  echo "$status" >"$dir/status"
  local runs_done
  runs_done=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$dir/log" | grep -o '[0-9]*$' || true)
  echo "fuzz: $target: exit $status, ${runs_done:-?} inputs, corpus $(ls "$dir/corpus" | wc -l) files"
}

for target in "${targets[@]}"; do
  if [[ ! -x $build/fuzz/$target ]]; then
    echo "fuzz: no target '$target'; targets are the fuzz/*_fuzz.cc files" >&2
    exit 2
  fi
  while (($(jobs -rp | wc -l) >= jobs)); do wait -n || true; done
  cpu=$(free_cpu)
  run_target "$target" "$cpu" &
  [[ -n $cpu ]] && cpu_of_job[$!]=$cpu
done
wait

failed=0
for target in "${targets[@]}"; do
  dir="$runs/$target"
  if [[ $(cat "$dir/status" 2>/dev/null || echo missing) != 0 ]]; then
    failed=1
    echo "fuzz: FAILED: $target (log: $dir/log)" >&2
    grep -E 'ERROR: |SUMMARY: |terminate called|what\(\):|runtime error:' "$dir/log" | head -n 8 >&2 || true
    for finding in "$dir"/findings/*; do
      [[ -e $finding ]] || continue
      echo "  input: $root/$finding" >&2
      echo "  reproduce: $root/$build/fuzz/$target $root/$finding" >&2
      # The same input with ASan's allocation and free stacks (see run_target).
      UBSAN_OPTIONS=$ubsan_options "$build/fuzz/$target" "${limits[@]}" "$finding" \
        >"$finding.log" 2>&1 || true
      echo "  its report with allocation stacks: $root/$finding.log" >&2
    done
  fi
done
echo "fuzz: build ${build_s} s, build and run $((SECONDS - start)) s"
if ((failed)); then
  echo "fuzz: a reader crashed, hung or ran out of memory on an input above; fix the reader to" \
    "throw InputError and add the input as a regression test (docs/fuzzing.md)" >&2
  exit 1
fi
echo "fuzz: all ${#targets[@]} targets passed"
