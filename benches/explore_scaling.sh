#!/usr/bin/env bash
# Throughput of `polywear explore` on the default study, and its scaling with threads.
# Usage: benches/explore_scaling.sh [SAMPLES] [BINARY]
# Prints one line per thread count: threads, samples, seconds, samples/s, speed-up over 1 thread.
set -euo pipefail
samples=${1:-20000}
bin=${2:-${CARGO_TARGET_DIR:-target}/release/polywear}
[ -x "$bin" ] || cargo build --release --quiet
cores=$(nproc)
counts="1"; t=2
while [ "$t" -le "$cores" ]; do counts="$counts $t"; t=$((t * 2)); done
case " $counts " in *" $cores "*) ;; *) counts="$counts $cores";; esac
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf "%8s %10s %10s %12s %9s\n" threads samples seconds samples/s speedup
base=""
for t in $counts; do
  start=$(date +%s.%N)
  "$bin" explore --quiet --samples "$samples" --threads "$t" --out "$tmp/t$t"
  end=$(date +%s.%N)
  secs=$(awk "BEGIN{print $end - $start}")
  rate=$(awk "BEGIN{print $samples / $secs}")
  [ -n "$base" ] || base=$rate
  printf "%8d %10d %10.2f %12.0f %9.2f\n" "$t" "$samples" "$secs" "$rate" "$(awk "BEGIN{print $rate / $base}")"
done
