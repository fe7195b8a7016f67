#!/usr/bin/env bash
# Builds the benchmarks (Release) and runs each with 9 repetitions, printing medians. These figures
# go into docs/performance.md. The machine has 2 cores and is shared: compare ratios, quote medians.
# Usage: scripts/bench.sh [FILTER]   (a --benchmark_filter regular expression)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
filter=${1:-.}
for bench in build/bench/*_bench; do
  [ -x "$bench" ] || continue
  echo "== $(basename "$bench")"
  "$bench" --benchmark_filter="$filter" --benchmark_repetitions=9 --benchmark_report_aggregates_only=true \
    --benchmark_display_aggregates_only=true 2>&1 | grep -E "^(BM_|-|Benchmark|Run on|CPU|Load)" | grep -vE "_(mean|stddev|cv) "
done
