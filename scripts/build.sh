#!/usr/bin/env bash
# Configures and builds into build/ (Release, with link-time optimisation, without precompiled
# headers). Extra arguments go to CMake's configure step after these defaults, so that they win
# (scripts/test_all.sh passes -DFMCW_LTO=OFF -DFMCW_PCH=ON); the defaults are given every time, so
# that a build/ the test script configured goes back to them. FMCW_TARGET=fmcw builds only the
# command-line tool (what the main job runs).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DFMCW_LTO=ON -DFMCW_PCH=OFF "$@" > build.log 2>&1 || { cat build.log; exit 1; }
cmake --build build -j"$(nproc)" ${FMCW_TARGET:+--target "$FMCW_TARGET"} >> build.log 2>&1 || { tail -50 build.log; exit 1; }
echo "build: ok (CLI at build/bin/fmcw)"
