#!/bin/bash
# SPDX-License-Identifier: Apache-2.0
# Submits a sharded sweep: N array tasks (sweep_array.sh) and the merge (sweep_merge.sh) that
# runs only when every task succeeded (afterok). Prints the two job ids.
#
#   tools/slurm/submit.sh N OUTDIR SWEEP_OPTIONS...
#
# sbatch options come from the environment (SBATCH_PARTITION, SBATCH_TIMELIMIT, ...; man
# sbatch, "INPUT ENVIRONMENT VARIABLES"). After a failure (a time limit, scancel), cancel the
# merge that can no longer run (scancel MERGE_ID) and run this again: the shards resume.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
[ $# -ge 2 ] || { echo "usage: submit.sh N OUTDIR SWEEP_OPTIONS..." >&2; exit 2; }
n=$1
out=$2
shift 2
[[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: N must be a positive integer, got '$n'" >&2; exit 2; }
array=$(sbatch --parsable --array="1-${n}" "$here/sweep_array.sh" "$out" "$@")
merge=$(sbatch --parsable --dependency="afterok:${array%%;*}" "$here/sweep_merge.sh" "$out")
echo "array job ${array%%;*} (${n} shards), merge job ${merge%%;*} -> ${out}/merged"
