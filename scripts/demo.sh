#!/usr/bin/env bash
# The main job on the bundled sample: installs the dependencies, builds, and runs acrolab on
# samples/trials/straight_jump/straight_jump.c3d (a trampoline jump made by tools/make_sample_trial).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
sample=samples/trials/straight_jump/straight_jump.c3d
echo
echo "== acrolab info $sample"
build/bin/acrolab info "$sample"
