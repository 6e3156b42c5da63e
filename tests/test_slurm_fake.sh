#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# ctest slurm_fake: tools/slurm/sweep_array.sh as four array tasks at once under a faked Slurm
# environment (--array=1-4: SLURM_ARRAY_TASK_ID 1..4, SLURM_ARRAY_TASK_MIN 1). Task 3 is
# sent SIGTERM mid-run: it must exit 143 with an incomplete checkpoint, sweep_merge.sh must
# refuse the shards naming shard 2/4, the task run again must resume (computing only the
# rest), and the merge must be byte-identical to the unsharded, uninterrupted run.
# Usage: test_slurm_fake.sh SMOOTHFORCE REPO
set -euo pipefail
sf=$1
repo=$2
work=$(mktemp -d /tmp/sf_slurm_fake.XXXXXX)
victim=""
cleanup() {
  if [ -n "$victim" ]; then kill -CONT "$victim" 2>/dev/null || true; kill -KILL "$victim" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
# the "done" count of METHOD in DIR/sweep.json (written pretty-printed), -1 without a checkpoint
done_of() {
  local n
  n=$(sed -n '/"done": {/,/}/s/^ *"'"$2"'": \([0-9]*\).*/\1/p' "$1/sweep.json" 2>/dev/null || true)
  echo "${n:--1}"
}

"$sf" generate sphere --radius 0.05 --segments 6 -o "$work/s.obj" >/dev/null
"$sf" cache build "$work/s.obj" --normals file -o "$work/s.sfcache" >/dev/null
# 48,000 samples x 2 depths over 4 shards: 24,000 patch probes a shard, so that its first
# checkpoints (blocks of 1,024, then about 0.02 s of probes each) come well before half of them
# (with 12,000 samples a loaded CI machine once showed 3,099 of 6,000 at the first look)
samples=48000
per=$((samples / 2))
args=(--cache "$work/s.sfcache" --depth 1%,3% --samples $samples --methods patch,direct,shading
      --analytic sphere:0.05 --no-plots)
"$sf" sweep "${args[@]}" --threads 2 -o "$work/whole" >"$work/whole.log" 2>&1 || fail "unsharded run: $(cat "$work/whole.log")"

task() {  # task ID: one array task, as Slurm would start it
  SLURM_ARRAY_JOB_ID=77 SLURM_ARRAY_TASK_ID=$1 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=4 \
    SLURM_ARRAY_TASK_COUNT=4 SLURM_ARRAY_TASK_STEP=1 SLURM_CPUS_PER_TASK=1 SMOOTHFORCE="$sf" \
    SF_CHECKPOINT_EVERY=0.01 SF_PROGRESS_EVERY=0.05 \
    exec bash "$repo/tools/slurm/sweep_array.sh" "$work/out" "${args[@]}"
}

declare -A pid
for id in 1 2 3 4; do
  task "$id" >"$work/task$id.log" 2>&1 &
  pid[$id]=$!
  if [ "$id" = 3 ]; then victim=$!; kill -STOP "$victim"; fi
done
# Let task 3 (shard 2) run 5 ms at a time until its checkpoint shows some of its $per patch
# probes done but at most half; then SIGTERM: the rest of its work is still ahead of it.
shard="$work/out/shard_2"
for _ in $(seq 1 4000); do
  kill -CONT "$victim"
  sleep 0.005
  kill -STOP "$victim"
  d=$(done_of "$shard" patch)
  if [ "$d" -gt 0 ] && [ "$d" -le $((per / 2)) ]; then break; fi
  if [ "$d" -gt $((per / 2)) ]; then fail "shard 2 ran past half of its patch probes between two looks ($d)"; fi
done
[ "$(done_of "$shard" patch)" -gt 0 ] || fail "shard 2 wrote no checkpoint"
kill -TERM "$victim"
kill -CONT "$victim"
set +e
wait "${pid[3]}"
rc3=$?
set -e
victim=""
[ "$rc3" = 143 ] || fail "the task sent SIGTERM exited $rc3, expected 143: $(cat "$work/task3.log")"
grep -q "interrupted by SIGTERM" "$work/task3.log" || fail "no interruption message: $(cat "$work/task3.log")"
for id in 1 2 4; do
  wait "${pid[$id]}" || fail "task $id failed: $(cat "$work/task$id.log")"
done
python3 - "$shard/sweep.json" "$per" <<'EOF' || fail "shard 2's checkpoint is not an interrupted, incomplete one"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["complete"] is False and j["interrupted"] is True, j
assert 0 < j["done"]["patch"] < int(sys.argv[2]), j["done"]
EOF
for k in 0 1 2 3; do [ -d "$work/out/shard_$k" ] || fail "no shard_$k (task index offset by SLURM_ARRAY_TASK_MIN)"; done
grep -q "sweep: progress" "$work/task1.log" || fail "no progress lines in a job log: $(cat "$work/task1.log")"

# the merge refuses the incomplete shard and names it
set +e
SMOOTHFORCE="$sf" bash "$repo/tools/slurm/sweep_merge.sh" "$work/out" >"$work/merge1.log" 2>&1
rc=$?
set -e
[ "$rc" = 1 ] || fail "merge of an incomplete shard exited $rc: $(cat "$work/merge1.log")"
grep -q "incomplete shards.*shard 2/4 ($work/out/shard_2)" "$work/merge1.log" || fail "$(cat "$work/merge1.log")"
! grep -q "shard [013]/4" "$work/merge1.log" || fail "complete shards named: $(cat "$work/merge1.log")"

# task 3 again: it resumes and computes only the rest
before=$(done_of "$shard" patch)
(task 3) >"$work/task3b.log" 2>&1 || fail "resumed task failed: $(cat "$work/task3b.log")"
grep -q "sweep: resuming shard 2/4" "$work/task3b.log" || fail "no resume: $(cat "$work/task3b.log")"
ran=$(sed -n 's/^sweep: patch *\([0-9]*\) HIPs.*/\1/p' "$work/task3b.log")
[ "$ran" = $((per - before)) ] || fail "the resumed task computed $ran patch probes, expected $((per - before))"

SMOOTHFORCE="$sf" bash "$repo/tools/slurm/sweep_merge.sh" "$work/out" >"$work/merge2.log" 2>&1 ||
  fail "merge failed: $(cat "$work/merge2.log")"
n=0
for f in summary.json hips.bin results_patch.bin results_direct.bin results_shading.bin trajectories.json; do
  cmp "$work/whole/$f" "$work/out/merged/$f" || fail "$f differs from the unsharded run"
  n=$((n + 1))
done
[ "$n" = 6 ] || fail "compared $n files"
echo "slurm_fake: 4 concurrent tasks, task 3 SIGTERM after $before of $per patch probes (exit 143), merge refused," \
  "resumed ($ran probes), merged byte-identical to the unsharded run ($n files)"
