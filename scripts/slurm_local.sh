#!/usr/bin/env bash
# Start and stop a private, single-node Slurm cluster on this machine, for tests.
#
#   bash scripts/slurm_local.sh check        exit 0 if a local cluster can be started here
#                                             (binaries present, running as root); otherwise
#                                             print why on stderr and exit 1 (callers skip).
#   bash scripts/slurm_local.sh start DIR    create DIR, generate a munge key and slurm.conf in
#                                             it, start munged, slurmctld and slurmd, wait until
#                                             the node is idle, then print ONE line on stdout:
#                                                 export SLURM_CONF=DIR/slurm.conf
#                                             so that callers can evaluate it:
#                                               out=$(bash scripts/slurm_local.sh start "$d") && eval "$out"
#                                             (a bare `eval "$(...)"` would hide a failed start).
#   bash scripts/slurm_local.sh stop DIR     cancel the cluster's jobs (so their processes end),
#                                             then stop exactly the daemons whose PIDs start
#                                             recorded in DIR/pids (TERM, wait, then KILL).
#                                             Idempotent; never signals any other process.
#
# SLURM_LOCAL_START_TIMEOUT (seconds, default 30) bounds start's wait for the idle node.
#
# DIR must be an absolute or relative path without whitespace, at most 80 characters (munge's
# socket path must fit a Unix socket address); folders above it must be searchable by all.
# Everything lives under DIR: munge key, socket, pid, log and seed files; slurm.conf; state,
# spool, pid and log files of slurmctld and slurmd. Nothing under /etc, /run or /var is used or
# changed, so the cluster never clashes with a system Slurm or munge, and several clusters (in
# different DIRs) can run side by side: each start picks its own free TCP ports on loopback.
#
# Written for and tested with Debian 12's slurm-wlm 22.05.8 and munge 0.5.15, run as root.
set -euo pipefail

# The programs a cluster needs: the three daemons, munge's key generator (a dd fallback exists,
# so it is not required) and the client commands tests use.
REQUIRED_BINS=(munged slurmctld slurmd sinfo sbatch squeue scontrol scancel)
# How long start waits for the node to become idle.
START_TIMEOUT_S=${SLURM_LOCAL_START_TIMEOUT:-30}
# How long stop waits after SIGTERM before it sends SIGKILL.
STOP_GRACE_S=5
# start launches munged, slurmctld, slurmd in that order; stop goes in reverse.

die() {
  echo "slurm_local.sh: error: $*" >&2
  exit 1
}

usage() {
  echo "usage: bash $0 check | start DIR | stop DIR" >&2
  exit 2
}

# check: can a local cluster run here? Prints the reason on stderr when it cannot.
cmd_check() {
  local missing=() b
  for b in "${REQUIRED_BINS[@]}"; do
    # The daemons are in /usr/sbin, which is not on every PATH.
    command -v "$b" >/dev/null 2>&1 || [[ -x /usr/sbin/$b ]] || missing+=("$b")
  done
  if ((${#missing[@]})); then
    echo "slurm_local.sh: Slurm/munge not installed (missing: ${missing[*]});" \
      "install the Debian packages slurmctld slurmd slurm-client munge" >&2
    return 1
  fi
  if [[ $(id -u) -ne 0 ]]; then
    # slurmd must be root to launch jobs (it setuid()s to the job's user), and munged must run as
    # the owner of its key; this script runs everything as root (SlurmUser=root).
    echo "slurm_local.sh: a local Slurm cluster needs root (slurmd runs as root); running as uid $(id -u)" >&2
    return 1
  fi
  return 0
}

# Absolute path of DIR without requiring it to exist (realpath -m), refusing paths Slurm and
# munge cannot take.
abs_dir() {
  local d
  d=$(realpath -m -- "$1")
  # slurm.conf values cannot hold whitespace (no quoting in its parser) nor '#'.
  [[ $d != *[[:space:]#]* ]] || die "DIR '$d' contains whitespace or '#', which slurm.conf cannot hold; use a path like /tmp/slurm.XXXXXX"
  # A Unix socket path is limited to 108 bytes (sun_path); munge's socket is DIR/munge/munge.socket.
  ((${#d} <= 80)) || die "DIR '$d' is too long (${#d} chars) for munge's Unix socket path; use a shorter path under /tmp"
  [[ $d != / ]] || die "DIR must not be /"
  printf '%s\n' "$d"
}

# Is PID alive and one that this DIR started? Guards against PID reuse: the process must be the
# named program and its command line must mention DIR (all daemons get DIR paths as arguments).
# A zombie (exited, not yet reaped by init, which some container inits do late) counts as gone.
is_ours() {
  local pid=$1 name=$2 dir=$3 comm cmdline stat
  [[ $pid =~ ^[0-9]+$ ]] || return 1
  [[ -r /proc/$pid/comm ]] || return 1
  stat=$(cat "/proc/$pid/stat" 2>/dev/null) || return 1
  # Field 3 of /proc/PID/stat, after the ")" that ends the command name, is the state.
  stat=${stat##*) }
  [[ ${stat:0:1} != Z ]] || return 1
  comm=$(cat "/proc/$pid/comm" 2>/dev/null) || return 1
  [[ $comm == "$name" ]] || return 1
  cmdline=$(tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null) || return 1
  [[ $cmdline == *"$dir/"* ]]
}

# Record "name pid" in DIR/pids (one line per daemon; stop reads it back).
record_pid() {
  echo "$2 $3" >>"$1/pids"
}

# Stop the daemons recorded in DIR/pids, newest first. Only PIDs that still pass is_ours are
# signalled; the rest have already exited (or the PID was reused by someone else: left alone).
stop_dir() {
  local dir=$1 pids_file=$1/pids name pid i
  [[ -f $pids_file ]] || return 0
  local names=() pidl=()
  while read -r name pid; do
    [[ -n ${name:-} ]] || continue
    names+=("$name")
    pidl+=("$pid")
  done <"$pids_file"

  # Cancel the jobs of this cluster first, while slurmctld still runs, so their job processes
  # (children of slurmstepd, which slurmd does not take down with it) end too.
  local ctl_alive=0
  for i in "${!names[@]}"; do
    if [[ ${names[$i]} == slurmctld ]] && is_ours "${pidl[$i]}" slurmctld "$dir"; then ctl_alive=1; fi
  done
  if ((ctl_alive)) && [[ -f $dir/slurm.conf ]]; then
    local jobs
    # %F: the array's job id for array tasks (cancelling it cancels every task), else the job id.
    jobs=$(SLURM_CONF=$dir/slurm.conf timeout 10 squeue -h -o %F 2>/dev/null | sort -u || true)
    if [[ -n $jobs ]]; then
      # shellcheck disable=SC2086  # word splitting of the job id list is intended
      SLURM_CONF=$dir/slurm.conf timeout 10 scancel $jobs 2>/dev/null || true
      for _ in $(seq 1 20); do
        [[ -z $(SLURM_CONF=$dir/slurm.conf timeout 5 squeue -h -t R,CG -o %A 2>/dev/null || true) ]] && break
        sleep 0.25
      done
    fi
  fi

  for ((i = ${#names[@]} - 1; i >= 0; i--)); do
    name=${names[$i]}
    pid=${pidl[$i]}
    is_ours "$pid" "$name" "$dir" || continue
    kill -TERM "$pid" 2>/dev/null || true
    local waited=0
    while is_ours "$pid" "$name" "$dir" && ((waited < STOP_GRACE_S * 10)); do
      sleep 0.1
      waited=$((waited + 1))
    done
    if is_ours "$pid" "$name" "$dir"; then
      echo "slurm_local.sh: $name (pid $pid) ignored SIGTERM for ${STOP_GRACE_S}s; sending SIGKILL" >&2
      kill -KILL "$pid" 2>/dev/null || true
      for _ in $(seq 1 50); do is_ours "$pid" "$name" "$dir" || break; sleep 0.1; done
    fi
    # A daemon started by this script is our child only while start runs; afterwards it has been
    # re-parented, so there is nothing to reap. Report if it somehow survives SIGKILL.
    if is_ours "$pid" "$name" "$dir"; then
      echo "slurm_local.sh: $name (pid $pid) is still running after SIGKILL" >&2
    fi
  done
  rm -f "$pids_file"
}

# A TCP port on which nothing listens on loopback and that no other cluster of ours uses.
# Python binds port 0 to let the kernel choose; without python, try random ports with bash's
# /dev/tcp (a refused connect means nothing listens there).
free_port() {
  local p
  if command -v python3 >/dev/null 2>&1 &&
    p=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])' 2>/dev/null) &&
    [[ $p =~ ^[0-9]+$ ]]; then
    printf '%s\n' "$p"
    return 0
  fi
  for _ in $(seq 1 100); do
    p=$((20000 + RANDOM % 40000))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null; then
      printf '%s\n' "$p"
      return 0
    fi
  done
  die "could not find a free TCP port on 127.0.0.1"
}

# Launch a daemon in the foreground mode of its own, in the background of this script, in a new
# session (so that a Ctrl-C or SIGHUP aimed at the caller's terminal does not reach it), with all
# stdio on files (so that `$(... start DIR)` does not wait for the daemons to close its pipe).
# Prints the PID. `setsid` execs in place here (a background job of a non-interactive shell is
# not a process-group leader), so $! is the daemon's own PID; launch checks that.
launch() {
  local dir=$1 name=$2
  shift 2
  setsid "$@" </dev/null >>"$dir/log/$name.stdio" 2>&1 &
  local pid=$!
  record_pid "$dir" "$name" "$pid"
  printf '%s\n' "$pid"
}

# Print the last lines of a daemon log on stderr, for failure messages, without the harmless
# PMIx noise (see cmd_start).
show_log() {
  local f=$1
  [[ -s $f ]] || return 0
  echo "---- last lines of $f ----" >&2
  grep -v -E 'pmix|PMIx|MPI: Cannot create context' "$f" | tail -n 15 >&2 || true
}

# start failed: say why and what to read, stop what this run started, exit 1.
fail_start() {
  local dir=$1 msg=$2
  shift 2
  echo "slurm_local.sh: error: $msg" >&2
  local f
  for f in "$@"; do show_log "$f"; done
  stop_dir "$dir"
  exit 1
}

cmd_start() {
  cmd_check || exit 1
  local dir
  dir=$(abs_dir "$1")
  PATH=$PATH:/usr/sbin:/sbin

  # Refuse to start a second cluster on top of a running one in the same DIR: its ports, socket
  # and state would clash. (Another DIR is fine: fresh ports, own socket and state.)
  if [[ -f $dir/pids ]]; then
    local name pid
    while read -r name pid; do
      if [[ -n ${name:-} ]] && is_ours "$pid" "$name" "$dir"; then
        die "a cluster started in $dir is still running ($name pid $pid); run 'bash $0 stop $dir' first, or use another DIR"
      fi
    done <"$dir/pids"
    rm -f "$dir/pids"
  fi

  # From here on, whatever ends start early (an error, Ctrl-C, SIGTERM from a test runner's
  # timeout) stops the daemons this start launched; success clears the trap.
  # shellcheck disable=SC2064  # expand DIR now, not when the trap runs
  trap "if ((\$? != 0)); then stop_dir $(printf %q "$dir"); fi" EXIT
  trap 'exit 130' INT
  trap 'exit 143' TERM
  trap 'exit 129' HUP

  # Fresh generated content each time; only the subfolders this script owns are wiped.
  mkdir -p "$dir"
  # munged wants every folder above its socket searchable by all ("Socket is inaccessible:
  # execute permissions for all required"); `mktemp -d` makes DIR 0700. Add search (x) only,
  # not read: others still cannot list DIR.
  chmod go+x "$dir"
  rm -rf "$dir/munge" "$dir/state" "$dir/spool" "$dir/log" "$dir/run"
  mkdir -p "$dir/state" "$dir/spool" "$dir/log" "$dir/run"
  # munged refuses a key, socket or log folder that group/other can write, a key that others can
  # read or that is not owned by the user it runs as (root here), and a socket folder that not
  # everyone can search ("Socket is inaccessible: execute permissions for all required"): so a
  # 0755 folder owned by root holds its files, with the key 0600.
  mkdir -p "$dir/munge"
  chmod 0755 "$dir/munge"

  # --- munged: private key, socket, pid, log and seed files ---------------------------------
  local key=$dir/munge/munge.key sock=$dir/munge/munge.socket
  if command -v mungekey >/dev/null 2>&1; then
    mungekey --create --keyfile="$key" >/dev/null 2>&1 || true
  fi
  if [[ ! -s $key ]]; then
    (umask 077 && dd if=/dev/urandom of="$key" bs=1024 count=1 status=none)
  fi
  chmod 0600 "$key"
  local munged_pid
  # --foreground: this script keeps its PID; it then logs to stderr (DIR/log/munged.stdio), so
  # --log-file only keeps it off /var/log/munge. Harmless there: "Unauthorized credential for
  # client UID=0 GID=0" at daemon starts and once per job (Slurm's NEWS: "not a cause for concern").
  munged_pid=$(launch "$dir" munged munged --foreground \
    --socket="$sock" --key-file="$key" --pid-file="$dir/munge/munged.pid" \
    --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed")
  for _ in $(seq 1 100); do
    [[ -S $sock ]] && break
    kill -0 "$munged_pid" 2>/dev/null ||
      fail_start "$dir" "munged exited at startup; read $dir/log/munged.stdio" "$dir/log/munged.stdio"
    sleep 0.1
  done
  [[ -S $sock ]] || fail_start "$dir" "munged did not create $sock within 10 s; read $dir/log/munged.stdio" "$dir/log/munged.stdio"

  # --- slurm.conf ------------------------------------------------------------------------------
  local host cpus mem node_line ctl_port d_port
  host=$(hostname -s 2>/dev/null || hostname)
  # slurmd -C reports this machine's hardware as a NodeName line. Only CPUs and RealMemory are
  # kept: with Sockets/Cores/Threads given, select/cons_tres never puts two jobs on one core, and
  # tests want one job per CPU.
  node_line=$(slurmd -C 2>/dev/null | head -n 1) || true
  cpus=$(sed -n 's/.*\bCPUs=\([0-9]*\).*/\1/p' <<<"$node_line")
  mem=$(sed -n 's/.*\bRealMemory=\([0-9]*\).*/\1/p' <<<"$node_line")
  [[ -n $cpus ]] || cpus=$(nproc)
  [[ -n $mem ]] || mem=1000
  ctl_port=$(free_port)
  d_port=$(free_port)
  while [[ $d_port == "$ctl_port" ]]; do d_port=$(free_port); done

  cat >"$dir/slurm.conf" <<EOF
# Generated by scripts/slurm_local.sh for a private, single-node test cluster; regenerated by
# every start. All paths are under $dir.
ClusterName=localtest
# The controller runs here and is reached on loopback, whatever the machine's network is.
SlurmctldHost=$host(127.0.0.1)
# Fresh free ports per start, so clusters in other DIRs (or a system Slurm) do not clash.
SlurmctldPort=$ctl_port
SlurmdPort=$d_port
# Everything runs as root: no slurm user or file ownership to set up.
SlurmUser=root
SlurmdUser=root
# Our own munged, not the system one in /run/munge (honoured by auth/munge and cred/munge).
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock
# State, spool, pid and log files under DIR; nothing under /var or /run.
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/%n
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups (containers often lack them): track job processes through /proc, no task binding.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
# No slurmdbd and no accounting.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
# Schedule each CPU separately (CR_CPU; no memory tracking, so a job without --mem does not take
# the whole node's memory), so that N single-CPU jobs or array tasks run at once on N CPUs.
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
# Try to start jobs right at submission and at each job end (no batching delay, no minimum
# interval between scheduler runs). Measured: a job waits ~1 s after the event that frees it
# (slurmctld's background loop), and the first scheduler run is ~3 s after slurmctld starts.
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
# A node that was down comes back by itself when its slurmd registers again.
ReturnToService=2
# Job end and node checks: short timeouts suit a local test cluster.
SlurmdTimeout=60
InactiveLimit=0
KillWait=5
MinJobAge=300
# No mail from a test cluster.
MailProg=/bin/true
NodeName=$host NodeAddr=127.0.0.1 NodeHostname=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF=$dir/slurm.conf
  # slurmd logs an error at startup if its spool folder (SlurmdSpoolDir, %n = node name) is missing.
  mkdir -p "$dir/spool/$host"

  # --- slurmctld and slurmd --------------------------------------------------------------------
  # -D: foreground (this script keeps the PID); -c: clear any previous state; -i: ignore errors in
  # state files. -N: the node name, in case `hostname` and NodeName ever differ.
  # Harmless in their logs: "mpi/pmix_v4 ... can not load PMIx library" (Debian's slurm loads
  # every MPI plugin even with MpiDefault=none), "Could not open job state file" (fresh state),
  # "xcpuinfo_hwloc_topo_load: failed" and "Node reconfigured socket/core boundaries" (the node is
  # described by CPUs only, see above).
  local ctl_pid d_pid
  ctl_pid=$(launch "$dir" slurmctld slurmctld -D -c -i -f "$SLURM_CONF")
  d_pid=$(launch "$dir" slurmd slurmd -D -N "$host" -f "$SLURM_CONF")

  # --- wait until the node is idle --------------------------------------------------------------
  local deadline=$((SECONDS + START_TIMEOUT_S)) state=""
  while ((SECONDS < deadline)); do
    kill -0 "$munged_pid" 2>/dev/null ||
      fail_start "$dir" "munged exited; read $dir/log/munged.stdio" "$dir/log/munged.stdio"
    kill -0 "$ctl_pid" 2>/dev/null ||
      fail_start "$dir" "slurmctld exited at startup; read $dir/log/slurmctld.log and $dir/log/slurmctld.stdio" \
        "$dir/log/slurmctld.log" "$dir/log/slurmctld.stdio"
    kill -0 "$d_pid" 2>/dev/null ||
      fail_start "$dir" "slurmd exited at startup; read $dir/log/slurmd.log and $dir/log/slurmd.stdio" \
        "$dir/log/slurmd.log" "$dir/log/slurmd.stdio"
    state=$(timeout 5 sinfo -h -N -n "$host" -o %T 2>/dev/null | head -n 1 || true)
    if [[ $state == idle ]]; then
      # The PIDs recorded are the daemons themselves (not a wrapper): check once.
      if ! { is_ours "$ctl_pid" slurmctld "$dir" && is_ours "$d_pid" slurmd "$dir" && is_ours "$munged_pid" munged "$dir"; }; then
        fail_start "$dir" "the PIDs recorded in $dir/pids are not the daemons' own; see $dir/log"
      fi
      trap - EXIT INT TERM HUP
      printf 'export SLURM_CONF=%s\n' "$SLURM_CONF"
      return 0
    fi
    sleep 0.5
  done
  local reason
  reason=$(timeout 5 sinfo -h -R -o '%E' 2>/dev/null || true)
  fail_start "$dir" "node '$host' not idle after ${START_TIMEOUT_S}s (state: '${state:-no answer from slurmctld}'${reason:+, reason: $reason}); read $dir/log/slurmctld.log and $dir/log/slurmd.log" \
    "$dir/log/slurmctld.log" "$dir/log/slurmd.log"
}

cmd_stop() {
  local dir
  dir=$(abs_dir "$1")
  stop_dir "$dir"
}

case ${1:-} in
check)
  (($# == 1)) || usage
  cmd_check
  ;;
start)
  (($# == 2)) || usage
  cmd_start "$2"
  ;;
stop)
  (($# == 2)) || usage
  cmd_stop "$2"
  ;;
*) usage ;;
esac
