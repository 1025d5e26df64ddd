#!/usr/bin/env bash
# The main job: set up, build, make a scan, run the motion core on it, write the report.
# Until the simulator lands, the scan is the analytic street scene of `fmcw synth`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
out=${1:-out/main}
mkdir -p "$out"
build/bin/fmcw synth -o "$out/frame.pcd" --objects 20 --seed 1
for method in paper fast; do
  build/bin/fmcw process "$out/frame.pcd" -o "$out/$method" --method "$method"
done
build/bin/fmcw bench --json > "$out/bench.json"
echo "main job: report in $out/ (paper/ and fast/: ego.csv, objects.csv, results.json; bench.json)"
