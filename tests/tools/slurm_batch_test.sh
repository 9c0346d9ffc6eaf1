#!/usr/bin/env bash
# fit-all on a real Slurm: a single-node cluster started on this machine (scripts/slurm_local.sh,
# loopback only, every daemon stopped by its PID at the end), docs/cluster.md.
#   1. a 4-task array plus its merge job writes the same fit-all.csv as the local run;
#   2. a shard cancelled in the middle of an item, resubmitted by `zbrdf batch resubmit`, completes
#      only its missing items: the items finished before are not redone (their results keep their
#      inode and time) and the table again equals the local one.
# Exit 77 (CTest: skipped) only where the daemons cannot start, with the reason.
#   bash slurm_batch_test.sh ZBRDF SOURCE_DIR WORK_DIR
set -euo pipefail
zbrdf=$1 source_dir=$2 work=$3
script="$source_dir/scripts/slurm_local.sh"

if ! reason=$(bash "$script" check 2>&1); then
  echo "SKIPPED: no local Slurm cluster: $reason"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work"
state=$(mktemp -d /tmp/zbrdf-slurm-test.XXXXXX)
chmod 755 "$state"  # munged wants its socket's folders searchable by all
cleanup() { bash "$script" stop "$state" >/dev/null 2>&1 || true; rm -rf "$state"; }
trap cleanup EXIT
if ! started=$(bash "$script" start "$state" 2>"$work/start.err"); then
  echo "SKIPPED: the Slurm daemons did not start: $(cat "$work/start.err")"
  exit 77
fi
eval "$started"  # export SLURM_CONF=...
export SLURM_CONF

fail() { echo "FAILED: $*" >&2; exit 1; }
json_get() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))$2)" "$1"; }
# Waits until none of the given job ids is queued or running (at most $2 s).
wait_jobs() {
  local jobs=$1 limit=$2 t=0
  while [[ -n $(squeue -h -j "$jobs" -o %i 2>/dev/null) ]]; do
    sleep 0.2
    t=$((t + 1))
    ((t < limit * 5)) || fail "jobs $jobs still queued after $limit s: $(squeue -j "$jobs")"
  done
}

materials='lambert:0.5,ggx:alpha=0.4,F0=0.5,kd=0.2,ggx:alpha=0.2,F0=0.04,kd=0.3,lambert:0.2'
common=(fit-all --rig "$source_dir/rig/rigs/thesis.yaml" --materials "$materials" --order 2
        --models ggx --preset fast)
slurm=(--executor slurm --cpus-per-task 1 --mem 1G --json)

# The local run (also fills the shared transport cache the jobs then read).
"$zbrdf" "${common[@]}" --out "$work/local" --jobs 2 >"$work/local.log" 2>&1 ||
  fail "local fit-all: $(tail -5 "$work/local.log")"

# 1. Four shards and a merge.
start_s=$SECONDS
"$zbrdf" "${common[@]}" --out "$work/array" --shards 4 "${slurm[@]}" >"$work/array.json" ||
  fail "submission failed"
array=$(json_get "$work/array.json" "['array_job']")
merge=$(json_get "$work/array.json" "['merge_job']")
wait_jobs "$array,$merge" 240
echo "4-task array + merge: $((SECONDS - start_s)) s"
[[ -f $work/array/fit-all.csv ]] || fail "no fit-all.csv after the merge job; its log: $(cat "$work/array/slurm/"merge-*.out 2>/dev/null)"
diff "$work/local/fit-all.csv" "$work/array/fit-all.csv" || fail "the array's table differs from the local one"
for i in 0 1 2 3; do
  grep -q "fit-all shard $i/4: 1 materials" "$work/array/slurm/shard-$i.out" ||
    fail "shard $i's log: $(cat "$work/array/slurm/shard-$i.out")"
done

# 2. Two shards (0: items 0 and 2; 1: items 1 and 3); shard 0 is cancelled while in item 2.
# Its jobs build their transports (the cache off in the environment sbatch passes on), so that
# item 2 lasts seconds rather than the ~1 s a cached fast capture now takes, and the cancel lands
# in it even on a loaded machine. The results are the same: a cached transport is the built one
# bit for bit (TransportCacheTest).
ZBRDF_TRANSPORT_CACHE_MB=0 "$zbrdf" "${common[@]}" --out "$work/killed" --shards 2 "${slurm[@]}" \
  >"$work/killed.json" || fail "submission failed"
array=$(json_get "$work/killed.json" "['array_job']")
merge=$(json_get "$work/killed.json" "['merge_job']")
third=$work/killed/running/ggx-alpha-0.2-F0-0.04-kd-0.3.json
for _ in $(seq 1 1500); do
  [[ -f $third ]] && break
  sleep 0.02
done
[[ -f $third ]] || fail "shard 0 never started its second item"
scancel --signal=KILL "${array}_0"
wait_jobs "$array,$merge" 240
first=$work/killed/items/lambert-0.5.json
[[ -f $first ]] || fail "shard 0's first item has no result"
[[ ! -f $work/killed/items/ggx-alpha-0.2-F0-0.04-kd-0.3.json ]] ||
  fail "the item was finished before the cancel landed; cannot test the resubmission"
[[ ! -f $work/killed/fit-all.csv ]] || fail "the merge ran although a shard was cancelled"
before=$(stat -c '%i %Y.%y' "$first" "$work/killed/items/ggx-alpha-0.4-F0-0.5-kd-0.2.json")
"$zbrdf" batch status "$work/killed" --json >"$work/status.json"
[[ $(json_get "$work/status.json" "['shards_with_missing_items']") == "[0]" ]] ||
  fail "status: $(cat "$work/status.json")"
"$zbrdf" batch resubmit "$work/killed" --json >"$work/resubmit.json" || fail "resubmit failed"
[[ $(json_get "$work/resubmit.json" "['resubmitted_shards']") == "[0]" ]] ||
  fail "resubmitted: $(cat "$work/resubmit.json")"
array=$(json_get "$work/resubmit.json" "['array_job']")
merge=$(json_get "$work/resubmit.json" "['merge_job']")
wait_jobs "$array,$merge" 240
after=$(stat -c '%i %Y.%y' "$first" "$work/killed/items/ggx-alpha-0.4-F0-0.5-kd-0.2.json")
[[ $before == "$after" ]] || fail "finished items were rewritten: $before / $after"
grep -q "fit-all shard 0/2: 2 materials (1 already done, 1 simulated" "$work/killed/slurm/shard-0.out" ||
  fail "the resubmitted shard's log: $(cat "$work/killed/slurm/shard-0.out")"
diff "$work/local/fit-all.csv" "$work/killed/fit-all.csv" || fail "the resubmitted batch's table differs"
echo "PASSED: 4-task array = local; cancelled shard resubmitted, only its missing item redone"
