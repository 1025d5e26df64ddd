#!/usr/bin/env bash
# The whole test suite: set up, build, run every test with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
cd build
# setup.sh installed Open3D and PCL's tools: the export checks must run, not skip.
FMCW_REQUIRE_EXTERNAL_TOOLS=1 ctest --output-on-failure -j"$(nproc)"

# The core on its own: Eigen, Ceres and OpenMP only, as a user embedding it would build it.
cd ..
cmake -S . -B build-core -DCMAKE_BUILD_TYPE=Release -DFMCW_CORE_ONLY=ON > build-core.log 2>&1 || { cat build-core.log; exit 1; }
cmake --build build-core -j"$(nproc)" >> build-core.log 2>&1 || { tail -50 build-core.log; exit 1; }
cd build-core
ctest --output-on-failure -j"$(nproc)"
