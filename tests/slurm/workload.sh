#!/usr/bin/env bash
# What the SLURM test (test_array_job.sh) runs: `prepare` on the submitting machine, `task` as
# each task of an array job (of 4 tasks), `finish` as a job that depends on the array job, and
# `check` on the submitting machine once all jobs are done. SLURM runs a copy of this file from its
# spool folder, so it finds everything through the environment: FMCW_CLI (the fmcw program),
# FMCW_SOURCE_DIR (this repository) and OUT (the folder all jobs write to).
set -euo pipefail

fmcw() { "$FMCW_CLI" "$@"; }

# ===== The workload: change these four functions to change what the cluster runs. ===============
# A generated set of 4 scenarios (fmcw generate), simulated 3 frames each by 4 array tasks (one
# scenario per task, `--task I/N`), then one aggregate evaluation over the folder of datasets.
count=4
frames=3

prepare() {
  fmcw generate --count "$count" --seed 1 -o "$OUT/set" 2>&1 | tail -n 1
}

task() {  # $1: this task's index, $2: the number of tasks
  fmcw simulate "$OUT/set" -o "$OUT/datasets" --task "$1/$2" --frames "$frames" --threads 1 --resume
}

finish() {
  fmcw evaluate "$OUT/datasets" -o "$OUT/report" --no-figures --methods paper,tracked --threads 1
}

check() {
  # A dataset made by a task is byte for byte what one machine writes for its scenario.
  fmcw simulate "$OUT/set/scenarios/gen_00002.yaml" --frames "$frames" -o "$OUT/direct" 2>&1 | tail -n 1
  diff -r "$OUT/direct" "$OUT/datasets/gen_00002"
  python3 - "$OUT" "$count" "$frames" <<'EOF'
import csv, json, os, sys
out, count, frames = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
names = sorted(d for d in os.listdir(os.path.join(out, "datasets")) if not d.endswith(".csv"))
assert names == ["gen_%05d" % k for k in range(count)], f"datasets: {names}"
report = json.load(open(os.path.join(out, "report", "metrics.json")))
assert report["kind"] == "aggregate" and report["complete"], "the aggregate report is not complete"
assert report["datasets_evaluated"] == count, f"{report['datasets_evaluated']} datasets evaluated, expected {count}"
assert report["method_order"] == ["paper", "tracked"], f"methods {report['method_order']}"
for method in ("paper", "tracked"):
    pooled = report["pooled"][method]
    assert pooled["scenarios"] == count and pooled["frames"] == count * frames, \
        f"{method}: {pooled['scenarios']} scenarios, {pooled['frames']} frames"
rows = list(csv.DictReader(open(os.path.join(out, "report", "scenarios.csv"))))
assert len(rows) == 2 * count, f"scenarios.csv: {len(rows)} rows, expected {2 * count}"
assert all(r["layout"] for r in rows), "scenarios.csv: the manifest's layout column is missing"
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
