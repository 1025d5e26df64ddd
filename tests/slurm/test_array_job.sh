#!/usr/bin/env bash
# The SLURM jobs of docs/SCALING_OUT.md on a real SLURM: starts a one-node cluster on this
# machine (cluster.sh), submits workload.sh as an array job of 4 tasks and a job that depends on
# it, waits, checks that each index ran as its own task of the array and that the results are
# right (workload.sh check), and stops the daemons it started, on failure too.
# Usage: test_array_job.sh WORK_DIR, with FMCW_CLI and FMCW_SOURCE_DIR set (CTest sets them:
# tests/slurm/CMakeLists.txt). Exits 77 (skipped) without root or SLURM, unless
# FMCW_REQUIRE_EXTERNAL_TOOLS=1 (scripts/test_all.sh): then that is a failure.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source-path=SCRIPTDIR source=cluster.sh
source "$here/cluster.sh"

missing() {
  if [ "${FMCW_REQUIRE_EXTERNAL_TOOLS:-0}" = 1 ]; then
    echo "$1, and FMCW_REQUIRE_EXTERNAL_TOOLS=1 requires it" >&2
    exit 1
  fi
  echo "skipped: $1" >&2
  exit 77
}
for program in "${cluster_programs[@]}"; do
  command -v "$program" > /dev/null ||
    missing "$program is not installed (Debian: slurm-wlm, munge; scripts/setup.sh installs them)"
done
[ "$(id -u)" = 0 ] ||
  missing "a SLURM cluster on this machine needs root (slurmd starts jobs); this is uid $(id -u)"

# A SLURM around this test (CI inside a job) must not leak its job or options into ours.
for v in $(compgen -e); do
  case $v in SLURM_* | SBATCH_* | SQUEUE_* | SINFO_* | SCONTROL_*) unset "$v" ;; esac
done

work=${1:?usage: test_array_job.sh WORK_DIR}
mkdir -p "$work"
work=$(cd "$work" && pwd)
cluster=$work/cluster
tasks=4
export OUT=$work/out
export SLURM_CONF=$cluster/slurm.conf
export FMCW_CLI FMCW_SOURCE_DIR

fail() {
  echo "$1" >&2
  exit 1
}

# On any exit: on failure the jobs, their output and the daemons' logs; then the cluster stops.
finished=0
cleanup() {
  local status=$? log
  if [ "$finished" != 1 ]; then
    echo "FAILED; the jobs:" >&2
    scontrol -o show job 2> /dev/null |
      sed -E 's/^(JobId=[^ ]*).*(JobState=[^ ]*).*(ExitCode=[^ ]*).*/\1 \2 \3/' >&2 || true
    for log in "$work"/jobs/*.log; do
      [ -f "$log" ] && { echo "----- $log"; tail -n 30 "$log"; } >&2
    done
    cluster_logs "$cluster" >&2
  fi
  cluster_stop "$cluster"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# A run that was killed may have left its cluster running, and its jobs writing to OUT.
cluster_stop "$cluster"
rm -rf "$OUT" "$work/jobs"
mkdir -p "$OUT" "$work/jobs"
start=$SECONDS
cluster_start "$cluster"
echo "cluster up in $((SECONDS - start)) s:" \
  "$(grep -E '^(NodeName|SlurmctldPort|SlurmdPort)' "$SLURM_CONF" | tr '\n' ' ')"

bash "$here/workload.sh" prepare
array=$(sbatch --parsable --job-name=fmcw-task --array=0-$((tasks - 1)) --cpus-per-task=1 \
  --output="$work/jobs/task_%A_%a.log" --chdir="$work" "$here/workload.sh" task)
finish=$(sbatch --parsable --job-name=fmcw-finish --dependency=afterok:"$array" \
  --kill-on-invalid-dep=yes --output="$work/jobs/finish_%j.log" --chdir="$work" \
  "$here/workload.sh" finish)
echo "submitted array job $array (tasks 0-$((tasks - 1))) and job $finish after it"

# The jobs leave the queue when done, failed or cancelled; at most 120 s.
for _ in $(seq 600); do
  [ -z "$(squeue -h -o %i)" ] && break
  sleep 0.2
done
[ -z "$(squeue -h -o %i)" ] || fail "jobs still queued after 120 s"
echo "jobs done $((SECONDS - start)) s after the start"

# Every task and the finishing job completed (exit 0).
states=$(scontrol -o show job | grep -oE '^JobId=[0-9]+|JobState=[A-Z_]+' | paste -d ' ' - -)
echo "$states"
[ "$(grep -c 'JobState=COMPLETED' <<< "$states")" = $((tasks + 1)) ] || fail "a job failed"

# Each index ran as its own SLURM job, a task of the one array job.
for ((i = 0; i < tasks; i++)); do
  record=$(cat "$OUT/tasks/$i" 2> /dev/null) || fail "task $i left no record"
  [[ $record =~ ^array_job=$array\ task=$i\ job=[0-9]+$ ]] || fail "task $i: $record"
done
[ "$(cat "$OUT"/tasks/* | sed 's/.*job=//' | sort -u | wc -l)" = "$tasks" ] ||
  fail "the $tasks tasks did not run as $tasks SLURM jobs: $(cat "$OUT"/tasks/*)"

bash "$here/workload.sh" check
finished=1
echo "ok: $tasks array tasks and the finishing job ran on SLURM; results checked" \
  "($((SECONDS - start)) s)"
