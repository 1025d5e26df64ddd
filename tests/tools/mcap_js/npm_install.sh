#!/usr/bin/env bash
# CTest fixture of the independent MCAP reader test: installs Foxglove's MCAP and ROS 2 message
# libraries from the npm registry into DIR (in the build tree), from package.json beside this
# script. Without node/npm or the registry the test is skipped (exit 77), unless
# FMCW_REQUIRE_EXTERNAL_TOOLS=1: then it fails.
#   npm_install.sh DIR
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dir=$1
missing() {
  if [ "${FMCW_REQUIRE_EXTERNAL_TOOLS:-0}" = 1 ]; then
    echo "$1, and FMCW_REQUIRE_EXTERNAL_TOOLS=1 requires it" >&2
    exit 1
  fi
  echo "skipped: $1" >&2
  exit 77
}
command -v node > /dev/null || missing "node is not installed (Debian: nodejs; scripts/setup.sh installs it)"
command -v npm > /dev/null || missing "npm is not installed (Debian: npm; scripts/setup.sh installs it)"
mkdir -p "$dir"
cp "$here/package.json" "$dir/package.json"
if [ -f "$dir/node_modules/.fmcw_installed" ] && cmp -s "$here/package.json" "$dir/node_modules/.fmcw_installed"; then
  echo "npm packages already installed in $dir"
  exit 0
fi
npm install --prefix "$dir" --no-audit --no-fund --loglevel=error > "$dir/npm.log" 2>&1 ||
  { cat "$dir/npm.log" >&2; missing "npm install of $(tr -d '\n ' < "$here/package.json" | grep -o '"dependencies":{[^}]*}') failed"; }
cp "$here/package.json" "$dir/node_modules/.fmcw_installed"
echo "installed into $dir/node_modules"
