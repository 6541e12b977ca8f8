#!/usr/bin/env bash
# Size of explore's Parquet output, the explore time, and how fast polars reads it back.
# Usage: benches/output_size.sh [SAMPLES] [BINARY...]
# For each binary (default: this build's), alternating over ROUNDS rounds (default 2): one
# `explore --samples SAMPLES --no-report` of the built-in study; prints the chunk files' total
# size per million samples, the explore wall time, and the best of 5 `pl.read_parquet` of all
# chunks (python3 with polars; "skipped" without it).
set -euo pipefail
samples=${1:-1e6}
shift || true
bins=("$@")
[ ${#bins[@]} -gt 0 ] || bins=("${CARGO_TARGET_DIR:-target}/release/polywear")
rounds=${ROUNDS:-2}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
read_time() {
  python3 - "$1" <<'PY' 2>/dev/null || echo "skipped (no polars)"
import sys, time
import polars as pl
best = min(
    (lambda t0: (pl.read_parquet(f"{sys.argv[1]}/chunk-*.parquet"), time.perf_counter() - t0)[1])(time.perf_counter())
    for _ in range(5)
)
print(f"{best:.3f} s")
PY
}
printf "%-34s %6s %12s %16s %12s %14s\n" binary round samples "MB per 1e6" "explore [s]" "polars read"
for r in $(seq 1 "$rounds"); do
  for b in "${bins[@]}"; do
    out="$tmp/run"
    rm -rf "$out"
    start=$(date +%s.%N)
    "$b" explore --quiet --no-report --samples "$samples" --out "$out"
    end=$(date +%s.%N)
    n=$(awk "BEGIN{printf \"%d\", $samples}")
    bytes=$(cat "$out"/chunk-*.parquet | wc -c)
    printf "%-34s %6d %12d %16.1f %12.1f %14s\n" "$(basename "$b") $("$b" --version | awk '{print $2}')" "$r" "$n" \
      "$(awk "BEGIN{print $bytes / 1e6 * 1e6 / $n}")" "$(awk "BEGIN{print $end - $start}")" "$(read_time "$out")"
  done
done
