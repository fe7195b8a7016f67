#!/usr/bin/env bash
# The whole test suite: installs the dependencies, builds, and runs every test with ctest.
# Reference data are read from ../shared/refdata (or $ACRO_REFDATA); with ACRO_REQUIRE_REFDATA=1
# a missing reference file fails its test instead of skipping it.
#
# scripts/test.sh --sanitize: an AddressSanitizer + UndefinedBehaviorSanitizer build in
# ./build-sanitize of only what the readers' and corpus tests need (capture, athlete, vision: no
# reconstruction, no views, no window, no benchmarks, no acrolab), and those tests; any sanitizer
# report fails them.
# scripts/test.sh --sanitize-all: the same plus the skill files' tests and the robustness suite
# against a sanitized acrolab (the whole analysis built again under ASan: about 25 minutes more on
# two cores; opt-in, docs/testing.md).
# ACRO_LONG_TESTS=1: the soak-type tests' full versions (docs/testing.md).
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage's wall time, one "name<TAB>seconds" line per stage, appended to $ACRO_STAGE_LOG when
# it is set (.ci/run prints them as a table).
stage() {
  local name=$1 start=$SECONDS
  shift
  "$@"
  if [ -n "${ACRO_STAGE_LOG:-}" ]; then printf '%s\t%d\n' "$name" $((SECONDS - start)) >> "$ACRO_STAGE_LOG"; fi
}
stage "install the Debian packages" scripts/install-deps.sh
if [ "${1:-}" = --sanitize ] || [ "${1:-}" = --sanitize-all ]; then
  # The readers (capture/), the YAML parser, the corpus replays of the fuzz entry points, the bed
  # detector (a photo or a video frame through OpenCV and our decoder); with --sanitize-all the
  # robustness suite against the sanitized acrolab too.
  # The skill files' tests (analysis/design) and the robustness suite need the whole analysis
  # (Ceres' reconstruction and optimisation) compiled again under ASan: --sanitize-all.
  tests='^(capture/|analysis/athlete/(yaml|athlete_profile|yeadon_measurements)$|analysis/vision/(camera|camera_corpus|bed_detection)$)'
  if [ "$1" = --sanitize-all ]; then
    tests='^(capture/|robustness/|analysis/athlete/(yaml|athlete_profile|yeadon_measurements)$|analysis/design/(yaml_corpus|skill_file)$|analysis/vision/(camera|camera_corpus|bed_detection)$)'
  fi
  # (capture/c3d_allocation counts allocations by interposing malloc itself, as ASan does.)
  exclude='^capture/c3d_allocation$'
  flags="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer"
  launcher=()
  if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  # Line tables only (-g1) for the reports' stack traces: with full debug information the
  # instrumented acrolab was 684 MB, and its compile and link a large part of CI's time. -O1, as
  # ASan's documentation advises: faster to compile than -O2, and the reports keep their frames.
  cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DACRO_BUILD_TESTS=ON -DACRO_BUILD_BENCHMARKS=OFF -DACRO_BUILD_UI=OFF -DACRO_BUILD_STUDIO=OFF \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined,float-cast-overflow"
  # The test names say their targets: capture/trc -> test_capture_trc.
  mapfile -t names < <(cd build-sanitize && ctest -N -R "$tests" -E "$exclude" | sed -n 's/^ *Test *#[0-9]*: //p')
  [ ${#names[@]} -gt 0 ] || { echo "test.sh --sanitize: no test matches $tests" >&2; exit 1; }
  targets=()
  if [ "$1" = --sanitize-all ]; then targets=(--target acrolab); fi
  for n in "${names[@]}"; do targets+=(--target "test_${n//\//_}"); done
  stage "sanitizer build (ASan + UBSan)" cmake --build build-sanitize -j "$(nproc)" "${targets[@]}"
  cd build-sanitize
  # A 4 GB cap on any one allocation: an unbounded one is a report (the video test's own
  # ffmpeg-decoded reference frames take 2 GB).
  export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:max_allocation_size_mb=4096
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  stage "sanitizer tests" ctest --output-on-failure -j "$(nproc)" --timeout 900 -R "$tests" -E "$exclude"
  exit
fi
stage "build (Release, tests, benchmarks, window)" scripts/build.sh -DACRO_BUILD_TESTS=ON \
  -DACRO_BUILD_BENCHMARKS=ON -DACRO_BUILD_UI=ON -DACRO_BUILD_STUDIO=ON
# The pose networks (fetched with npm pack, checked, converted by the converter just built).
stage "pose models (npm pack, convert, check)" scripts/install-models.sh
cd build
# Rendering tests need a display: run under a virtual X server when one is not already there.
runner=()
# A full-HD true-colour screen (the studio's window is 1920 × 1080), and no server reset when the
# last client leaves: a reset refuses the connections of whatever starts at that moment (a test
# run in parallel once failed with "bad X server connection" so).
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null 2>&1; then
  runner=(xvfb-run -a -s "-screen 0 1920x1080x24 -noreset")
fi
stage "tests (ctest -j $(nproc))" "${runner[@]}" ctest --output-on-failure -j "$(nproc)" --timeout 900
