#!/usr/bin/env bash
# Memory and time of `polywear analyze` against the study size: runs analyze on the explore
# output of 1e6 and of 4e6 samples and prints wall time and peak resident memory (RSS) of each,
# and their ratios. The goal: peak RSS <= 400 MB for both, 4e6 at most 1.2 x 1e6.
#
# The data is real explore output, made cheap: the default study's tire-structure spread with
# speeds of 40-100 km/h, so most points are stable (decided from the eigenvalues alone) and
# about one in ten is a limit cycle (found by shooting). Outputs are kept in data/bench_analyze/
# and reused by later runs (about 1 GB; the 4e6 run takes a while on 2 cores).
# Usage: benches/analyze_scaling.sh [SAMPLES...]   (default: 1e6 4e6)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${CARGO_TARGET_DIR:-target}/release/polywear
[ -x "$bin" ] || cargo build --release --quiet
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(1e6 4e6)
base=data/bench_analyze
mkdir -p "$base"
cat > "$base/study.toml" <<'TOML'
name = "bench_analyze"
description = "analyze benchmark: the default study's structure spread at 40-100 km/h (few limit cycles)"
seed = 12
samples = 1000000
design = "random"
variants = ["paper"]
chunk_size = 16384
[params]
speed_kmh    = { dist = "uniform", min = 40, max = 100 }
toe_deg      = { dist = "truncated_normal", mean = 0.25, sd = 0.12, min = 0.02, max = 0.8 }
load_n       = { dist = "truncated_normal", mean = 4000, sd = 600, min = 2500, max = 6500 }
pressure_kpa = { dist = "truncated_normal", mean = 240, sd = 20, min = 180, max = 320 }
g_mod        = { dist = "lognormal", median = 0.8645e6, sigma = 0.05 }
c_brush      = { dist = "lognormal", median = 3.6e7, sigma = 0.05 }
tread_height = { dist = "truncated_normal", mean = 0.015, sd = 0.0005, min = 0.0135, max = 0.0165 }
rho          = { dist = "truncated_normal", mean = 1250, sd = 25, min = 1175, max = 1325 }
TOML
runs=${RUNS:-3}
echo "analyze, median of $runs runs per size (peak RSS varies by a few MB with thread timing)"
printf "%10s %10s %12s %14s %s\n" samples rows "wall [s]" "peak RSS [MB]" "(each run: s, MB)"
first_rss=""; first_s=""
for n in "${sizes[@]}"; do
  dir="$base/samples_$n"
  # --resume finishes (or reuses) an earlier run of the same size.
  nice "$bin" explore "$base/study.toml" --samples "$n" --out "$dir" --resume --quiet --no-report
  secs_all=(); kb_all=(); each=""
  for _ in $(seq "$runs"); do
    rm -rf "$dir/_bench_report"
    out=$( { /usr/bin/time -f "%e s %M KB" "$bin" analyze "$dir" --out "$dir/_bench_report" >/dev/null; } 2>&1 | tail -1)
    secs_all+=("${out%% s *}"); kb_all+=("$(echo "$out" | awk '{print $3}')")
    each="$each ${out%% s *}/$(awk "BEGIN{printf \"%.0f\", $(echo "$out" | awk '{print $3}') / 1024}")"
  done
  secs=$(printf "%s\n" "${secs_all[@]}" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}')
  kb=$(printf "%s\n" "${kb_all[@]}" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}')
  rows=$(grep -o "([0-9]* rows" "$dir/_bench_report/report.md" | head -1 | tr -d '( rows')
  printf "%10s %10s %12.2f %14.1f  (%s )\n" "$n" "$rows" "$secs" "$(awk "BEGIN{print $kb / 1024}")" "$each"
  [ -n "$first_rss" ] || { first_rss=$kb; first_s=$secs; }
  last_rss=$kb; last_s=$secs
done
if [ ${#sizes[@]} -gt 1 ]; then
  echo "ratio last/first (medians): peak RSS $(awk "BEGIN{printf \"%.2f\", $last_rss / $first_rss}"), wall time $(awk "BEGIN{printf \"%.2f\", $last_s / $first_s}")"
fi
