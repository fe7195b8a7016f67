#!/usr/bin/env bash
# Installs the pose networks `acrolab detect` runs (docs/pose.md, "The models"): Google's BlazePose
# GHUM person detector and landmark networks (Apache-2.0; NOTICE) from the npm package
# @mediapipe/pose at a pinned version, fetched with `npm pack` (one tarball, no install script run),
# its integrity and every file's SHA-256 checked, the TFLite networks converted to ONNX for OpenCV's
# DNN by the project's own converter (build/bin/acrolab-convert-model) and the results checked
# against their pinned SHA-256 (the conversion is deterministic). Nothing is committed to the
# repository and nothing is downloaded at run time.
#
# The cache: $ACRO_MODELS, else $XDG_CACHE_HOME/acrolab/models, else ~/.cache/acrolab/models; the
# networks go to its folder mediapipe-pose-<version>, written whole or not at all. A second run
# checks the files and does nothing.
#
# Usage: scripts/install-models.sh [--check]   (--check: report, never fetch; exit 1 when absent)
set -euo pipefail
cd "$(dirname "$0")/.."

version=0.5.1675469404
package="@mediapipe/pose@$version"
integrity="sha512-DFZsNWTsSphRIZppnUCuunzBiHP2FdJXR9ehc7mMi4KG+oPaOH0Em3d6kr7Py+TSyTXC1doH88KcF28k2sBxsQ=="
root="${ACRO_MODELS:-${XDG_CACHE_HOME:-$HOME/.cache}/acrolab/models}"
dir="$root/mediapipe-pose-$version"
converter="${ACRO_CONVERTER:-build/bin/acrolab-convert-model}"

# The package's files (SHA-256), and the person detector: MediaPipe's packed assets are exactly
# pose_detection.tflite (the loader's table: bytes 0 to 2 962 288).
declare -A source_sha=(
  [pose_landmark_lite.tflite]=f17bfbecadb61c3be1baa8b8d851cc6619c870a87167b32848ad20db306b9d61
  [pose_landmark_full.tflite]=e9a5c5cb17f736fafd4c2ec1da3b3d331d6edbe8a0d32395855aeb2cdfd64b9f
  [pose_landmark_heavy.tflite]=59e42d71bcd44cbdbabc419f0ff76686595fd265419566bd4009ef703ea8e1fe
  [pose_solution_packed_assets.data]=a63c614bef30d35947f13be361820b1e4e3bec9cfeebf4d11216a18373108e85
)
# The converted networks (tools/pose_model_conversion.h).
declare -A onnx_sha=(
  [pose_detection.onnx]=66746923a85a92934a3bc64b372415ba549382b9c626b9f8aa2d0f2a98c4378d
  [pose_landmark_lite.onnx]=56c04b8db4a0490882a0ab364cdcfe8749539fdad5c2e90b566cf351915cd05f
  [pose_landmark_full.onnx]=14bb995cce4c109390c8727830342b0a2db2ad5ecb396841e20c45b9d57c936c
  [pose_landmark_heavy.onnx]=45def5d2b9c736e6253f089470614b8a2a4fbc81624b5ddb1eaa08bd9c372b9e
)
# What the cache keeps: the four TFLite networks (the converter's tests read them) and the ONNX.
declare -A kept_sha=(
  [pose_detection.tflite]=${source_sha[pose_solution_packed_assets.data]}
  [pose_landmark_lite.tflite]=${source_sha[pose_landmark_lite.tflite]}
  [pose_landmark_full.tflite]=${source_sha[pose_landmark_full.tflite]}
  [pose_landmark_heavy.tflite]=${source_sha[pose_landmark_heavy.tflite]}
)
for name in "${!onnx_sha[@]}"; do kept_sha[$name]=${onnx_sha[$name]}; done

sha256() { sha256sum "$1" | cut -c1-64; }

# The cache is complete when every file is there with its pinned hash, and MANIFEST lists them.
present() {
  [ -f "$dir/MANIFEST" ] || return 1
  local name
  for name in "${!kept_sha[@]}"; do
    [ -f "$dir/$name" ] && [ "$(sha256 "$dir/$name")" = "${kept_sha[$name]}" ] || return 1
  done
}

if present; then
  echo "install-models: the pose models are present in $dir"
  exit 0
fi
if [ "${1:-}" = --check ]; then
  echo "install-models: the pose models are not installed in $dir: run scripts/install-models.sh" >&2
  exit 1
fi
command -v npm >/dev/null 2>&1 || { echo "install-models: npm is missing: run scripts/install-deps.sh" >&2; exit 1; }
command -v node >/dev/null 2>&1 || { echo "install-models: node is missing: run scripts/install-deps.sh" >&2; exit 1; }
[ -x "$converter" ] || { echo "install-models: $converter is missing: build it first (scripts/build.sh)" >&2; exit 1; }

mkdir -p "$root"
work=$(mktemp -d "$root/.install-XXXXXX")
trap 'rm -rf "$work"' EXIT

echo "install-models: fetching $package with npm pack"
(cd "$work" && npm pack "$package" --silent >/dev/null)
tarball="$work/mediapipe-pose-$version.tgz"
[ -f "$tarball" ] || { echo "install-models: npm pack wrote no $tarball" >&2; exit 1; }
# The registry's integrity string is sha512 of the tarball, base64: computed here, not taken from npm.
got="sha512-$(node -e 'const c=require("crypto"),f=require("fs");process.stdout.write(c.createHash("sha512").update(f.readFileSync(process.argv[1])).digest("base64"))' "$tarball")"
if [ "$got" != "$integrity" ]; then
  echo "install-models: $package: integrity $got, expected $integrity" >&2
  exit 1
fi
tar -xzf "$tarball" -C "$work" package/pose_landmark_lite.tflite package/pose_landmark_full.tflite \
  package/pose_landmark_heavy.tflite package/pose_solution_packed_assets.data
for name in "${!source_sha[@]}"; do
  if [ "$(sha256 "$work/package/$name")" != "${source_sha[$name]}" ]; then
    echo "install-models: $package: $name has SHA-256 $(sha256 "$work/package/$name"), expected ${source_sha[$name]}" >&2
    exit 1
  fi
done

out="$work/models"
mkdir "$out"
mv "$work/package/pose_solution_packed_assets.data" "$out/pose_detection.tflite"
for model in lite full heavy; do mv "$work/package/pose_landmark_$model.tflite" "$out/"; done
# The landmark networks without their segmentation head (12–15 % of their time; Acrolab makes
# silhouettes its own way): landmarks, pose flag, heatmap, world landmarks.
"$converter" "$out/pose_detection.tflite" "$out/pose_detection.onnx" >/dev/null
for name in pose_landmark_lite pose_landmark_full pose_landmark_heavy; do
  "$converter" "$out/$name.tflite" "$out/$name.onnx" --outputs Identity,Identity_1,Identity_3,Identity_4 >/dev/null
done
chmod 644 "$out"/*
for name in "${!kept_sha[@]}"; do
  if [ "$(sha256 "$out/$name")" != "${kept_sha[$name]}" ]; then
    echo "install-models: $name has SHA-256 $(sha256 "$out/$name"), expected ${kept_sha[$name]} (the converter changed?)" >&2
    exit 1
  fi
done
for name in $(printf '%s\n' "${!kept_sha[@]}" | sort); do
  printf '%s  %s  %s\n' "${kept_sha[$name]}" "$(stat -c %s "$out/$name")" "$name"
done > "$out/MANIFEST"
cp NOTICE "$out/NOTICE"

# Into place in one rename (a previous, incomplete copy is moved aside first).
if [ -e "$dir" ]; then mv "$dir" "$work/old"; fi
mv "$out" "$dir"
echo "install-models: the pose models are installed in $dir ($(du -sh "$dir" | cut -f1))"
