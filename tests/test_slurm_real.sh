#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# ctest slurm_real: a real single-node Slurm (Debian slurm-wlm + munge) started on localhost
# in a scratch directory (its own munge key and socket, its own ports and slurm.conf through
# SLURM_CONF: nothing under /etc is touched), which runs tools/slurm/sweep_array.sh as an
# --array=1-4 job (sbatch --wait) and tools/slurm/sweep_merge.sh as an afterok dependent job
# (polled); the merge must be byte-identical to the unsharded run. A failing array must
# leave its afterok merge unrun. Skips (exit 77) only when not root or when the packages
# cannot be installed. Usage: test_slurm_real.sh SMOOTHFORCE REPO
set -euo pipefail
sf=$1
repo=$2
skip() { echo "SKIP: $*"; exit 77; }
fail() {
  echo "FAIL: $*" >&2
  [ -n "${work:-}" ] && for f in "$work"/*.log "$work/munge/munged.log"; do
    [ -e "$f" ] && { echo "--- $f" >&2; tail -20 "$f" >&2; }
  done
  exit 1
}

[ "$(id -u)" = 0 ] || skip "not root: a single-node Slurm needs root (munged, slurmd)"
need=(slurmctld slurmd sbatch sinfo scancel munged munge)
missing() { for c in "${need[@]}"; do command -v "$c" >/dev/null || [ -x "/usr/sbin/$c" ] || return 0; done; return 1; }
if missing; then
  echo "slurm_real: installing slurm-wlm munge"
  DEBIAN_FRONTEND=noninteractive timeout 600 apt-get install -y -q --no-install-recommends slurm-wlm munge \
    >/tmp/sf_slurm_apt.log 2>&1 || skip "apt-get install slurm-wlm munge failed: $(tail -3 /tmp/sf_slurm_apt.log)"
  missing && skip "slurm-wlm/munge installed but a command is missing"
fi
export PATH="$PATH:/usr/sbin"

work=$(mktemp -d /tmp/sf_slurm_real.XXXXXX)
chmod 755 "$work"
export SLURM_CONF="$work/slurm.conf"
array_pid=""
cleanup() {
  set +e
  [ -n "$array_pid" ] && kill "$array_pid" 2>/dev/null
  scancel --quiet --user=root >/dev/null 2>&1  # the jobs of this scratch cluster (SLURM_CONF)
  for p in "$work/slurmd.pid" "$work/slurmctld.pid" "$work/munge/munged.pid"; do
    [ -s "$p" ] && kill "$(cat "$p")" 2>/dev/null
  done
  sleep 1
  for p in "$work/slurmd.pid" "$work/slurmctld.pid" "$work/munge/munged.pid"; do
    [ -s "$p" ] && kill -9 "$(cat "$p")" 2>/dev/null
  done
  rm -rf "$work"
}
trap cleanup EXIT

# munge: a key and a socket of our own
mkdir -p "$work/munge" && chmod 755 "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --force --socket="$work/munge/socket" --key-file="$work/munge/munge.key" --log-file="$work/munge/munged.log" \
  --pid-file="$work/munge/munged.pid" --seed-file="$work/munge/munged.seed" || fail "munged did not start"
munge -S "$work/munge/socket" -n | unmunge -S "$work/munge/socket" >/dev/null || fail "munge does not work"

# slurm.conf on two free localhost ports
read -r ctld_port d_port < <(python3 -c 'import socket
s=[socket.socket() for _ in range(2)]
[x.bind(("127.0.0.1",0)) for x in s]
print(*[x.getsockname()[1] for x in s])')
host=$(hostname -s)
mkdir -p "$work/state" "$work/spool"
cat >"$SLURM_CONF" <<EOF
ClusterName=sftest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
CommunicationParameters=NoInAddrAny
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start"
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
for _ in $(seq 1 60); do
  [ "$(sinfo -h -o %T 2>/dev/null)" = idle ] && break
  sleep 1
done
[ "$(sinfo -h -o %T)" = idle ] || fail "the node is not idle: $(sinfo 2>&1)"

# the sweep: unsharded here, sharded through Slurm
"$sf" generate sphere --radius 0.05 --segments 5 -o "$work/s.obj" >/dev/null
"$sf" cache build "$work/s.obj" --normals file -o "$work/s.sfcache" >/dev/null
args=(--cache "$work/s.sfcache" --depth 1%,3% --samples 4000 --methods patch,direct,shading
      --analytic sphere:0.05 --no-plots)
"$sf" sweep "${args[@]}" -o "$work/whole" >"$work/whole.log" 2>&1 || fail "unsharded run"

submit=(--chdir="$work" --cpus-per-task=1 --export="ALL,SMOOTHFORCE=$sf,SF_CHECKPOINT_EVERY=1,SF_PROGRESS_EVERY=1")
timeout 600 sbatch --parsable --wait --array=1-4 "${submit[@]}" -o "$work/task_%a.log" \
  "$repo/tools/slurm/sweep_array.sh" "$work/out" "${args[@]}" >"$work/array.id" 2>"$work/array.err" &
array_pid=$!
for _ in $(seq 1 100); do [ -s "$work/array.id" ] && break; sleep 0.1; done
jid=$(head -1 "$work/array.id" | cut -d';' -f1)
[[ "$jid" =~ ^[0-9]+$ ]] || fail "no array job id: $(cat "$work/array.id" "$work/array.err")"
# the merge: submitted as users do, then polled (sbatch --wait's polls back off: it saw the
# merge's end up to 24 s late)
merge=$(sbatch --parsable --dependency="afterok:$jid" "${submit[@]}" -o "$work/merge.log" \
  "$repo/tools/slurm/sweep_merge.sh" "$work/out" --no-plots | cut -d';' -f1)
[[ "$merge" =~ ^[0-9]+$ ]] || fail "no merge job id: $merge"
state=""
for _ in $(seq 1 1200); do
  state=$(scontrol show job "$merge" -o 2>/dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2 || true)
  case "$state" in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY) break ;; esac
  sleep 0.5
done
[ "$state" = COMPLETED ] || fail "the merge job: ${state:-no state} after up to 600 s (COMPLETED expected)"
wait "$array_pid" || fail "the array job failed: $(cat "$work/array.err")"
array_pid=""
for k in 1 2 3 4; do
  grep -q "task $k -> shard $((k - 1))/4" "$work/task_$k.log" || fail "task $k: $(cat "$work/task_$k.log")"
done
n=0
for f in summary.json hips.bin results_patch.bin results_direct.bin results_shading.bin trajectories.json; do
  cmp "$work/whole/$f" "$work/out/merged/$f" || fail "$f differs from the unsharded run"
  n=$((n + 1))
done

# a failing array (a usage error: exit 2 in every task): its afterok merge must never start;
# Slurm keeps it pending (DependencyNeverSatisfied) until it is cancelled
bad=$(sbatch --parsable --array=1-2 "${submit[@]}" -o "$work/bad_%a.log" "$repo/tools/slurm/sweep_array.sh" \
  "$work/bad" --cache "$work/s.sfcache" --depth 2%x | cut -d';' -f1)
badmerge=$(sbatch --parsable --dependency="afterok:$bad" "${submit[@]}" -o "$work/badmerge.log" \
  "$repo/tools/slurm/sweep_merge.sh" "$work/bad" | cut -d';' -f1)
reason=""
for _ in $(seq 1 120); do
  reason=$(squeue -h -j "$badmerge" -o "%T %r" 2>/dev/null || true)
  [ "$reason" = "PENDING DependencyNeverSatisfied" ] && break
  sleep 1
done
[ "$reason" = "PENDING DependencyNeverSatisfied" ] || fail "the merge after a failed array is '$reason'"
grep -q "2%x" "$work/bad_1.log" || fail "the failing task: $(cat "$work/bad_1.log")"
[ ! -e "$work/badmerge.log" ] || fail "the merge after a failed array ran: $(cat "$work/badmerge.log")"
scancel "$badmerge"
echo "slurm_real: array job $jid (4 tasks) and afterok merge via sbatch --wait, merged byte-identical ($n files);" \
  "a failed array ($bad) left its merge ($badmerge) pending: $reason"
