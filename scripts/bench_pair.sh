#!/usr/bin/env bash
# Times this build's benchmarks against another build's (e.g. an earlier commit built in a second
# tree), alternating the two ROUNDS times so that both see the same machine load, and prints the
# median of each side's medians and their ratio. The machine has 2 cores and is shared: only
# ratios measured this way are comparable.
# Usage: scripts/bench_pair.sh OTHER_BUILD_DIR [ROUNDS] [FILTER]
set -euo pipefail
cd "$(dirname "$0")/.."
other=${1:?usage: scripts/bench_pair.sh OTHER_BUILD_DIR [ROUNDS] [FILTER]}
rounds=${2:-3}
filter=${3:-.}
runner=()
# A full-HD true-colour screen (the studio's window is 1920 × 1080), and no server reset when the
# last client leaves: a reset refuses the connections of whatever starts at that moment (a test
# run in parallel once failed with "bad X server connection" so).
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null 2>&1; then
  runner=(xvfb-run -a -s "-screen 0 1920x1080x24 -noreset")
fi
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for ((i = 0; i < rounds; i++)); do
  for side in "$other" build; do
    for bench in "$side"/bench/*_bench; do
      "${runner[@]}" "$bench" --benchmark_filter="$filter" --benchmark_repetitions=5 \
        --benchmark_report_aggregates_only=true 2>/dev/null |
        awk -v s="$side" '/_median/ {print s, $1, $2, $3}' >> "$out"
    done
  done
done
python3 - "$out" "$other" <<'PY'
import collections, statistics, sys
values = collections.defaultdict(list)
for line in open(sys.argv[1]):
    side, name, value, unit = line.split()
    values[(name, side)].append(float(value))
names = sorted({n for n, _ in values})
print(f"{'benchmark':52s} {'other':>10s} {'this':>10s}  ratio")
for n in names:
    if (n, sys.argv[2]) in values and (n, "build") in values:
        a = statistics.median(values[(n, sys.argv[2])])
        b = statistics.median(values[(n, "build")])
        print(f"{n:52s} {a:10.3f} {b:10.3f}  {b / a:.3f}")
PY
