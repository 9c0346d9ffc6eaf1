#!/usr/bin/env bash
# The timing table of docs/cluster.md: a small fit-all as one process, and as Slurm arrays of 1 and
# 2 shards (cold cache, then warm) on a single-node cluster started here (scripts/slurm_local.sh;
# root, Debian's slurmctld/slurmd/munge). Checks that every run wrote the same fit-all.csv.
#   bash scripts/cluster_timing.sh [ZBRDF]      (default: build/zbrdf)
set -euo pipefail
cd "$(dirname "$0")/.."
zbrdf=$(realpath "${1:-build/zbrdf}")
work=$(mktemp -d /tmp/zbrdf-cluster-timing.XXXXXX)
chmod 755 "$work"
started=$(bash scripts/slurm_local.sh start "$work/cluster")  # exits here if the daemons fail
eval "$started"
export SLURM_CONF
trap 'bash scripts/slurm_local.sh stop "$work/cluster"' EXIT
materials='merl:blue-acrylic,merl:gold-metallic-paint,merl:white-diffuse-bball,merl:chrome,merl:red-plastic,merl:alum-bronze'
command=(fit-all --rig rig/rigs/thesis.yaml --materials "$materials" --order 4 --models ggx --preset fast)
wait_queue() { while [[ -n $(squeue -h -o %i) ]]; do sleep 0.2; done; }
run() {  # name, cache, extra flags...
  local name=$1 cache=$2
  shift 2
  export ZBRDF_CACHE_DIR=$work/$cache
  local t0 t1
  t0=$(date +%s.%N)
  "$zbrdf" "${command[@]}" --out "$work/$name" "$@" >/dev/null 2>&1
  wait_queue
  t1=$(date +%s.%N)
  printf '%-40s %6.1f s  ' "$name" "$(echo "$t1 - $t0" | bc)"
  if [[ $name == local ]] || diff -q "$work/local/fit-all.csv" "$work/$name/fit-all.csv" >/dev/null; then
    echo "same table"
  else
    echo "DIFFERENT TABLE"
  fi
}
run local cache-local --jobs 2
run slurm-1-shard-2-cpus cache-s1 --executor slurm --shards 1 --cpus-per-task 2
run slurm-2-shards-1-cpu cache-s2 --executor slurm --shards 2 --cpus-per-task 1
run slurm-2-shards-1-cpu-warm cache-s2 --executor slurm --shards 2 --cpus-per-task 1
echo "work folder: $work"
