#!/usr/bin/env bash
# What the SLURM test (test_array_job.sh) runs: `prepare` on the submitting machine, `task` as
# each task of an array job (of 4 tasks), `finish` as a job that depends on the array job, and
# `check` on the submitting machine once all jobs are done. SLURM runs a copy of this file from its
# spool folder, so it finds everything through the environment: FMCW_CLI (the fmcw program),
# FMCW_SOURCE_DIR (this repository) and OUT (the folder all jobs write to).
set -euo pipefail

fmcw() { "$FMCW_CLI" "$@"; }

# ===== The workload: change these four functions to change what the cluster runs. ===============
# One scenario, 8 frames, cut into one shard per task, merged and evaluated (docs/SCALING_OUT.md).
# Planned (issue 17): prepare runs `fmcw generate`, each task simulates its part of the generated
# set (`--task I/N`), and finish evaluates the folder of datasets.
scenario=$FMCW_SOURCE_DIR/scenarios/intersection.yaml
frames=8

prepare() { :; }

task() {  # $1: this task's index, $2: the number of tasks
  fmcw simulate "$scenario" --frames "$frames" --shard "$1/$2" -o "$OUT/shards/$1" --resume \
    --threads 1
}

finish() {
  fmcw merge "$OUT"/shards/* -o "$OUT/merged"
  fmcw evaluate "$OUT/merged" -o "$OUT/report" --no-figures --methods paper,tracked --threads 1
}

check() {
  # The merged shards are byte for byte what one machine writes (no file left out of the diff).
  fmcw simulate "$scenario" --frames "$frames" -o "$OUT/direct" 2>&1 | tail -n 1
  diff -r "$OUT/direct" "$OUT/merged"
  python3 - "$OUT/report/metrics.json" "$frames" <<'EOF'
import json, sys
path, frames = sys.argv[1], int(sys.argv[2])
report = json.load(open(path))
assert report["frames"] == frames, f"{path}: {report['frames']} frames, expected {frames}"
assert report["method_order"] == ["paper", "tracked"], f"{path}: methods {report['method_order']}"
EOF
}
# ===== End of the workload. ======================================================================

case "${1:-}" in
  prepare) prepare ;;
  task)
    # Which SLURM task ran this index: the test checks that each index ran as its own task of
    # one array job.
    mkdir -p "$OUT/tasks"
    echo "array_job=$SLURM_ARRAY_JOB_ID task=$SLURM_ARRAY_TASK_ID job=$SLURM_JOB_ID" \
      > "$OUT/tasks/$SLURM_ARRAY_TASK_ID"
    task "$SLURM_ARRAY_TASK_ID" "$SLURM_ARRAY_TASK_COUNT"
    ;;
  finish) finish ;;
  check) check ;;
  *)
    echo "usage: workload.sh prepare|task|finish|check" >&2
    exit 2
    ;;
esac
