#!/bin/bash
# SPDX-License-Identifier: Apache-2.0
# Joins the shards of tools/slurm/sweep_array.sh into OUTDIR/merged (summary, plots, index.html):
#
#   sbatch --dependency=afterok:ARRAY_JOB_ID tools/slurm/sweep_merge.sh OUTDIR [--no-plots]
#
# sweep-merge refuses (exit 1, naming them) shards that are incomplete, and a set of shards
# with a gap or of different runs. Environment: SMOOTHFORCE as in sweep_array.sh.
#SBATCH --job-name=sf-sweep-merge
#SBATCH --cpus-per-task=2
set -euo pipefail

die() { echo "sweep_merge.sh: $1" >&2; exit 2; }
[ $# -ge 1 ] || die "usage: sbatch --dependency=afterok:JOB sweep_merge.sh OUTDIR [sweep-merge options]"
out=$1
shift
sf=${SMOOTHFORCE:-}
if [ -z "$sf" ]; then
  sf="${SLURM_SUBMIT_DIR:-.}/build/tools/smoothforce"
  [ -x "$sf" ] || sf=$(command -v smoothforce) || die "no smoothforce binary: set SMOOTHFORCE"
fi
shopt -s nullglob
shards=("$out"/shard_*)
((${#shards[@]} > 0)) || { echo "sweep_merge.sh: no shard_* directories in $out" >&2; exit 1; }
exec "$sf" sweep-merge "${shards[@]}" -o "$out/merged" "$@"
