#!/usr/bin/env bash
# Opt-in fuzzing of every file reader with libFuzzer (clang, ASan, UBSan), seeded with the public
# reference files. Usage: scripts/fuzz.sh [SECONDS]   (default 300). Crashes land in build-fuzz/crashes/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-300}
refdata=${ACRO_REFDATA:-../shared/refdata}
command -v clang++ >/dev/null || { echo "fuzz.sh: needs clang (apt-get install clang libclang-rt-14-dev)" >&2; exit 1; }
sanitize="-fsanitize=address,undefined,fuzzer-no-link"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DACRO_BUILD_FUZZERS=ON \
  -DACRO_BUILD_UI=OFF -DACRO_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS="$sanitize" -DCMAKE_C_FLAGS="$sanitize"
cmake --build build-fuzz -j "$(nproc)" --target readers_fuzz
seeds=build-fuzz/seeds
mkdir -p "$seeds" build-fuzz/corpus build-fuzz/crashes
# Seed corpus: the reference files themselves (copied into the build tree, never into the repository).
find "$refdata" \( -iname '*.c3d' -o -iname '*.trc' -o -iname '*.mot' -o -iname '*.sto' \) -size -2M \
  -exec cp -t "$seeds" {} + 2>/dev/null || true
build-fuzz/fuzz/readers_fuzz build-fuzz/corpus "$seeds" -max_total_time="$seconds" -rss_limit_mb=2048 \
  -malloc_limit_mb=1024 -timeout=10 -artifact_prefix=build-fuzz/crashes/ -print_final_stats=1
