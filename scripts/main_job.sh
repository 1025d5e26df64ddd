#!/usr/bin/env bash
# The main job: set up, build, simulate the paper's intersection scenario (135 scans), run every
# motion method on it, compare with the ground truth, and write the report to out/main/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
FMCW_TARGET=fmcw bash scripts/build.sh  # the CLI alone, with link-time optimisation
out=${1:-out/main}
scenario=${2:-scenarios/intersection.yaml}
mkdir -p "$out"
build/bin/fmcw run "$scenario" -o "$out" --overwrite
echo "main job: report in $out/report.html (metrics.json, frames.csv, objects.csv, figures; dataset in $out/dataset)"
