#!/usr/bin/env bash
# Opt-in fuzzing of every file reader with libFuzzer (clang, ASan, UBSan), one target per family:
#   readers  C3D, TRC, marker CSV, OpenSim storage      seeds: ../shared/refdata's mocap files
#   yaml     athlete, Yeadon, skill, routine, markers   seeds: samples/ and docs/formats' examples
#   camera   calibrations and 2D detections             seeds: refdata's calibrations, OpenPose JSON
#   video    the video reader (FFmpeg)                  seeds: small videos of seven codecs (ffmpeg)
# Usage: scripts/fuzz.sh [SECONDS [TARGET...]]   (default 300 s each, every target in turn).
# Crashes land in build-fuzz/crashes/<target>/, the grown corpus in build-fuzz/corpus/<target>/,
# each run's statistics in build-fuzz/<target>.log.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-300}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(readers yaml camera video)
refdata=${ACRO_REFDATA:-../shared/refdata}
scripts/install-deps.sh --fuzz
sanitize="-fsanitize=address,undefined,fuzzer-no-link"
mkdir -p build-fuzz
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DACRO_BUILD_FUZZERS=ON \
  -DACRO_BUILD_TESTS=ON -DACRO_BUILD_UI=OFF -DACRO_BUILD_BENCHMARKS=OFF \
  -DCMAKE_CXX_FLAGS="$sanitize" -DCMAKE_C_FLAGS="$sanitize" > build-fuzz/configure.log
build_targets=()
for t in "${targets[@]}"; do build_targets+=(--target "${t}_fuzz"); done
cmake --build build-fuzz -j "$(nproc)" "${build_targets[@]}"

# Seed corpora, copied into the build tree (never into the repository).
seed() {  # seed TARGET: fills build-fuzz/seeds/TARGET
  local dir=build-fuzz/seeds/$1
  rm -rf "$dir" && mkdir -p "$dir"
  case $1 in
    readers)
      find "$refdata" \( -iname '*.c3d' -o -iname '*.trc' -o -iname '*.mot' -o -iname '*.sto' \) \
        -size -2M -exec cp -t "$dir" {} + 2>/dev/null || true ;;
    yaml)
      cp samples/athletes/*.yaml samples/skills/*.yaml "$dir"
      for md in docs/formats/*.md; do
        awk -v out="$dir/$(basename "$md" .md)" '/^```yaml$/{n++; f=out "_" n ".yaml"; next}
          /^```/{f=""} f{print > f}' "$md"
      done ;;
    camera)
      cp "$refdata"/pose2sim-demo/calibration/Calib.qca.txt \
        "$refdata"/pose2sim-demo/calibration/Calib_qualisys.toml \
        "$refdata"/sports2d-demo/Calib_demo.toml samples/trials/trampoline_routine/side_camera.toml "$dir"
      cp "$refdata"/s2mLab-EKF_multicamera-trampoline/inputs/calibration/Calib.toml "$dir/ekf.toml"
      cp "$refdata"/pose2sim-demo/balancing-trial/pose/cam01_json/cam01.000{1,2,3}.json "$dir"
      printf '%s\n' '%YAML:1.0' '---' 'image_width: 1920' 'image_height: 1080' \
        'camera_matrix: !!opencv-matrix' '   rows: 3' '   cols: 3' '   dt: d' \
        '   data: [ 1500., 0., 960., 0., 1500., 540., 0., 0., 1. ]' \
        'distortion_coefficients: !!opencv-matrix' '   rows: 1' '   cols: 5' '   dt: d' \
        '   data: [ -0.1, 0.01, 0., 0., 0. ]' 'rvec: [ 0.1, -0.2, 0.3 ]' 'tvec: [ 0.5, 1.0, 4.0 ]' \
        > "$dir/opencv.yml"
      printf '%s\n' camera,frame,time_s,marker,u_px,v_px cam1,0,0,LHEE,512.25,700.5 \
        cam1,1,0.0167,LHEE,513.5,699.25 > "$dir/detections.csv" ;;
    video)
      local src="-f lavfi -i testsrc=size=64x48:rate=25 -frames:v 16"
      ffmpeg -v error -y $src -c:v libx264 -bf 2 -g 6 -pix_fmt yuv420p -movflags +faststart "$dir/h264.mp4"
      ffmpeg -v error -y $src -c:v libx265 -x265-params log-level=none -g 6 -pix_fmt yuv420p "$dir/hevc.mkv"
      ffmpeg -v error -y $src -c:v libvpx-vp9 -g 6 -deadline realtime "$dir/vp9.webm"
      ffmpeg -v error -y $src -c:v libaom-av1 -cpu-used 8 -g 6 "$dir/av1.mkv"
      ffmpeg -v error -y $src -c:v mpeg4 -g 6 "$dir/mpeg4.avi"
      ffmpeg -v error -y $src -c:v mjpeg -q:v 5 "$dir/mjpeg.avi"
      ffmpeg -v error -y $src -c:v libx264 -g 6 -pix_fmt yuv420p -metadata:s:v rotate=90 "$dir/rotated.mp4" ;;
  esac
}

status=0
for t in "${targets[@]}"; do
  seed "$t"
  mkdir -p "build-fuzz/corpus/$t" "build-fuzz/crashes/$t"
  echo "== $t: ${seconds} s"
  # A video input can be decoded for up to 64 frames: larger inputs only slow the search.
  max_len=$([ "$t" = video ] && echo 65536 || echo 1048576)
  if ! "build-fuzz/fuzz/${t}_fuzz" "build-fuzz/corpus/$t" "build-fuzz/seeds/$t" \
      -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 \
      -max_len="$max_len" -artifact_prefix="build-fuzz/crashes/$t/" -print_final_stats=1 \
      > "build-fuzz/$t.log" 2>&1; then
    echo "$t: a finding (build-fuzz/crashes/$t/, log build-fuzz/$t.log)" >&2
    status=1
  fi
  grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)" \
    "build-fuzz/$t.log" || true
  grep -E "cov: [0-9]+" "build-fuzz/$t.log" | tail -1 || true
done
exit $status
