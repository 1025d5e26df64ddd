#!/usr/bin/env bash
# Digests of what every method writes on a set of datasets, timing columns aside, to show that a
# refactor or a speed-up leaves the results byte-identical.
#   tests/reliability/same_outputs.sh FMCW_BINARY DATASETS_FOLDER OUTPUT_FOLDER
# DATASETS_FOLDER holds one dataset per scenario (`fmcw simulate scenarios/X.yaml -o D/X`).
# Prints one sha256 per dataset and file; run it with the old and the new binary and diff.
set -euo pipefail
bin=$1 datasets=$2 out=$3
mkdir -p "$out"
for d in "$datasets"/*/; do
  name=$(basename "$d")
  rm -rf "$out/$name"
  "$bin" evaluate "$d" -o "$out/$name" --threads 1 --no-figures > "$out/$name.log" 2>&1
  # frames.csv without its timing columns (clustering_ms, ego_ms, objects_ms, total_ms: the last four).
  awk -F, 'BEGIN{OFS=","} {NF-=4; print}' "$out/$name/frames.csv" > "$out/$name/frames_untimed.csv"
  for f in objects.csv frames_untimed.csv snapshot_clusters.csv snapshot_pixels.csv; do
    printf '%s  %s/%s\n' "$(sha256sum < "$out/$name/$f" | cut -d' ' -f1)" "$name" "$f"
  done
done
