#!/usr/bin/env bash
# The independent MCAP reader test: simulates a short dataset, exports it with
# `fmcw export --to mcap`, and reads the file with read_export.mjs (Foxglove's libraries, from
# npm_install.sh). Skipped (77) when they are not installed, unless FMCW_REQUIRE_EXTERNAL_TOOLS=1.
#   run_reader.sh FMCW_CLI SOURCE_DIR NODE_DIR
set -euo pipefail
cli=$1
src=$2
node_dir=$3
here=$(cd "$(dirname "$0")" && pwd)
if [ ! -f "$node_dir/node_modules/.fmcw_installed" ]; then
  if [ "${FMCW_REQUIRE_EXTERNAL_TOOLS:-0}" = 1 ]; then
    echo "Foxglove's npm packages are not installed in $node_dir (npm_install.sh failed)" >&2
    exit 1
  fi
  echo "skipped: Foxglove's npm packages are not installed in $node_dir" >&2
  exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/fmcw_mcap_js.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$cli" simulate "$src/scenarios/intersection.yaml" -o "$work/data" --frames 3 --seed 4 > "$work/simulate.log" 2>&1 ||
  { cat "$work/simulate.log"; exit 1; }
"$cli" export "$work/data" -o "$work/seq.mcap" --to mcap
# The script resolves its imports from the folder it lies in: run a copy beside node_modules.
cp "$here/read_export.mjs" "$node_dir/read_export.mjs"
node "$node_dir/read_export.mjs" "$work/seq.mcap" "$work/data/frames/000001.pcd" 3 1
