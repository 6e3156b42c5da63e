#!/bin/bash
# SPDX-License-Identifier: Apache-2.0
# One shard of a `smoothforce sweep` per Slurm array task, resumable (docs/sweeps.md):
#
#   sbatch --array=1-32 tools/slurm/sweep_array.sh OUTDIR SWEEP_OPTIONS...
#
# Task SLURM_ARRAY_TASK_ID of --array=A-B[:S] computes shard K = (ID - A) / S of
# N = SLURM_ARRAY_TASK_COUNT into OUTDIR/shard_K, so any start index works. SWEEP_OPTIONS are
# the sweep's (--cache C --depth 2%,4% --samples ...), the same for every task; the script
# adds --shard K/N --threads SLURM_CPUS_PER_TASK --resume --checkpoint-every -o. Every task
# resumes: resubmitting the array after a time limit, scancel or node failure continues each
# shard from its last checkpoint (complete shards exit 0 at once). A shard stopped by SIGTERM
# (time limit, scancel) saves a checkpoint and exits 143, so an afterok merge does not run on
# partial data. Environment: SMOOTHFORCE (the binary; default build/tools/smoothforce under
# the submit directory, else smoothforce on PATH), SF_CHECKPOINT_EVERY (s, default 60),
# SF_PROGRESS_EVERY (s between progress lines in the job log, default 30).
#SBATCH --job-name=sf-sweep
#SBATCH --cpus-per-task=2
#SBATCH --open-mode=append
set -euo pipefail

die() { echo "sweep_array.sh: $1" >&2; exit 2; }
[ $# -ge 1 ] || die "usage: sbatch --array=A-B sweep_array.sh OUTDIR SWEEP_OPTIONS..."
out=$1
shift
for v in SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_MIN SLURM_ARRAY_TASK_COUNT; do
  [ -n "${!v:-}" ] || die "$v is not set: submit with sbatch --array (or set the SLURM_ARRAY_* variables)"
done
step=${SLURM_ARRAY_TASK_STEP:-1}
n=$SLURM_ARRAY_TASK_COUNT
k=$(((SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN) / step))
if ((k < 0 || k >= n || (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN) % step != 0)); then
  die "task ${SLURM_ARRAY_TASK_ID} is not in an array from ${SLURM_ARRAY_TASK_MIN} of ${n} tasks every ${step}"
fi

sf=${SMOOTHFORCE:-}
if [ -z "$sf" ]; then
  sf="${SLURM_SUBMIT_DIR:-.}/build/tools/smoothforce"
  [ -x "$sf" ] || sf=$(command -v smoothforce) || die "no smoothforce binary: set SMOOTHFORCE"
fi
mkdir -p "$out"
echo "sweep_array.sh: task ${SLURM_ARRAY_TASK_ID} -> shard ${k}/${n} in ${out}/shard_${k} on $(hostname)" >&2
exec "$sf" sweep "$@" --shard "${k}/${n}" --threads "${SLURM_CPUS_PER_TASK:-0}" --resume \
  --checkpoint-every "${SF_CHECKPOINT_EVERY:-60}" --progress-every "${SF_PROGRESS_EVERY:-30}" -o "${out}/shard_${k}"
