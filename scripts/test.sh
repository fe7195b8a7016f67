#!/usr/bin/env bash
# The whole test suite: installs the dependencies, builds, and runs every test with ctest.
# Reference data are read from ../shared/refdata (or $ACRO_REFDATA); with ACRO_REQUIRE_REFDATA=1
# a missing reference file fails its test instead of skipping it.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh -DACRO_BUILD_TESTS=ON -DACRO_BUILD_BENCHMARKS=ON -DACRO_BUILD_UI=ON \
  -DACRO_BUILD_STUDIO=ON
cd build
# Rendering tests need a display: run under a virtual X server when one is not already there.
runner=()
# A full-HD true-colour screen (the studio's window is 1920 × 1080), and no server reset when the
# last client leaves: a reset refuses the connections of whatever starts at that moment (a test
# run in parallel once failed with "bad X server connection" so).
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null 2>&1; then
  runner=(xvfb-run -a -s "-screen 0 1920x1080x24 -noreset")
fi
"${runner[@]}" ctest --output-on-failure -j "$(nproc)" --timeout 900
