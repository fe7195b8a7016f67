#!/usr/bin/env bash
# The main job on the bundled sample: installs the dependencies, builds, and runs `acrolab analyze`
# on samples/trials/trampoline_routine (a six-skill trampoline routine made by
# tools/make_sample_routine for samples/athletes/sample_athlete.yaml) with its side camera's video.
# The report goes to out/trampoline_routine/report.html, the athlete over the video to
# out/trampoline_routine/overlay.mp4 (linked from the page).
set -euo pipefail
cd "$(dirname "$0")/.."
# Only what the main job needs: the acrolab program with its 3D views (VTK, for the overlay on
# the video), without tests, benchmarks or the Qt window.
scripts/install-deps.sh --main
ACRO_TARGETS="acrolab acrolab-convert-model" scripts/build.sh -DACRO_BUILD_TESTS=OFF -DACRO_BUILD_BENCHMARKS=OFF \
  -DACRO_BUILD_UI=ON -DACRO_BUILD_STUDIO=OFF
# The pose networks `acrolab detect` runs: fetched with npm pack, checked, converted (docs/pose.md).
scripts/install-models.sh
trial=samples/trials/trampoline_routine/trampoline_routine.c3d
out=out/trampoline_routine
echo
echo "== acrolab analyze $trial"
build/bin/acrolab analyze "$trial" --athlete samples/athletes/sample_athlete.yaml -o "$out" \
  --video samples/trials/trampoline_routine/side_camera.mp4 \
  --calib samples/trials/trampoline_routine/side_camera.toml --sync auto
echo
echo "Open $(pwd)/$out/report.html in a browser for the report (plots, per-jump table, verdict)."
