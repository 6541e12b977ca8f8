#!/usr/bin/env bash
# Regenerates every table of docs/book/src/maintainers/benchmarks.md, in one run, into data/benchmarks/report.md (and
# prints it). Each section names the exact command behind its figures, so any one of them can
# be rerun alone. Timings depend on the machine and its load: the report starts with both.
#
# Usage: benches/regenerate.sh [--quick] [--out DIR] [--only SECTION,...]
#   default: the sizes the benchmarks page quotes, about 15 minutes on 2 quiet cores
#   --quick: tiny sizes and criterion's test mode, a smoke run (under a minute once built) that
#            checks every benchmark still runs; its figures mean nothing
#   --only:  just these sections (e.g. --only hot-paths,sampling), the report holding only them
# The peers (SciPy, numba) run only where python3 imports scipy and numba
# (benches/peers/compare.sh installs them); otherwise their sections say they were skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
only=""
out=data/benchmarks
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --out) out=$2; shift ;;
    --only) only=$2; shift ;;
    *) echo "usage: benches/regenerate.sh [--quick] [--out DIR] [--only SECTION,...]" >&2; exit 2 ;;
  esac
  shift
done
if [ "$quick" = 1 ]; then
  EXPLORE_N=2000; OUTPUT_N=2000; SCALING_N=1000; FSYNC_N=400; VALIDATE_N=4; THROUGHPUT_N=500; LIFE_N=200
  ANALYZE_SIZES="2e4 4e4"; ANALYZE_RUNS=1; REPRODUCE="--steps 11 --paired-samples 200"
  DECODING_N=2560; PEERS_N=20; PEERS_SCIPY=2; CRITERION="--test"; CYCLE_REPEATS=1
  SCENARIOS_N=1000; OPTIMIZE_N=300; WEAR_KM=300; CYCLE_STRUCTURES=2
else
  EXPLORE_N=1e6; OUTPUT_N=1e6; SCALING_N=20000; FSYNC_N=4000; VALIDATE_N=340; THROUGHPUT_N=20000; LIFE_N=4000
  ANALYZE_SIZES="1e6 4e6"; ANALYZE_RUNS=3; REPRODUCE=""
  DECODING_N=51200; PEERS_N=1000; PEERS_SCIPY=50; CRITERION="--warm-up-time 1 --measurement-time 3"; CYCLE_REPEATS=9
  SCENARIOS_N=20000; OPTIMIZE_N=10000; WEAR_KM=60000; CYCLE_STRUCTURES=20
fi

cargo build --release --quiet --bin polywear
bin=${CARGO_TARGET_DIR:-target}/release/polywear
mkdir -p "$out"
work=$(mktemp -d "$out/run.XXXXXX")
trap 'rm -rf "$work"' EXIT
report="$out/report.md"
: > "$report"
say() { printf '%s\n' "$*" | tee -a "$report"; }
block() { say '```'; tee -a "$report"; say '```'; say ""; }
section() { say ""; say "## $1"; say ""; }
timed() { /usr/bin/time -f "%e s %M KB" "$@"; }
# Wall, CPU (user + system) and peak memory: README quotes the explore run's three.
timed_cpu() { /usr/bin/time -f "%e s wall, %U s user + %S s system CPU, %M KB peak" "$@"; }
want() { [ -z "$only" ] || [[ ",$only," == *",$1,"* ]]; }
peers_ok() { python3 -c "import scipy, numba, pandas" >/dev/null 2>&1; }
# Criterion's result lines, one per benchmark: a long name stands on a line of its own, with
# `time:` on the next; test mode (--quick) prints "Testing NAME" and "Success".
criterion_lines() {
  awk '/^Testing|^Success/ {print; next}
       / time: +\[/ { n = $1; if (n == "time:") n = prev; sub(/.*time: +/, ""); printf "%-58s %s\n", n, $0; next }
       NF == 1 { prev = $1 }'
}

say "# polywear benchmarks ($(date -u +%Y-%m-%d), $([ "$quick" = 1 ] && echo quick || echo full) run)"
say ""
say "- polywear $("$bin" --version | awk '{print $2}'), commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with local changes)')"
say "- $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(awk '{printf "%.1f GB", $2/1048576}' <(grep MemTotal /proc/meminfo)) memory"
say "- load average at the start: $(cut -d' ' -f1-3 /proc/loadavg)"
say "- binary: $(stat -c %s "$bin" | awk '{printf "%.1f MB (%.1f MiB)", $1/1e6, $1/1048576}')"

if want explore; then
  section "explore"
  say "Command: \`polywear explore --samples $EXPLORE_N\` (the built-in study, with the closing report)."
  say ""
  timed_cpu "$bin" explore --samples "$EXPLORE_N" --out "$work/explore" > "$work/explore.out" 2> "$work/explore.err"
  { grep -E "samples evaluated|analysed" "$work/explore.out" || true; echo "the whole command: $(tail -1 "$work/explore.err")"; } | block
  { grep -E "^P\(|within +[0-9,]+ km:|paired|classified" "$work/explore.out" || true; } | block
fi

if want output-size; then
  section "output-size"
  say "Command: \`benches/output_size.sh $OUTPUT_N\` (the built-in study's chunk files: size, explore time, polars read time)."
  say ""
  ROUNDS=1 benches/output_size.sh "$OUTPUT_N" "$bin" | block
fi

if want explore-threads; then
  section "explore-threads"
  say "Command: \`benches/explore_scaling.sh $SCALING_N\` (the default study at 1, 2, 4, ... threads)."
  say ""
  benches/explore_scaling.sh "$SCALING_N" "$bin" | block
fi

if want fsync; then
  section "fsync"
  say "Command: the default study's axes in $((FSYNC_N / 16)) chunks of 16 samples, written to disk (\`data/\`) and to"
  say "tmpfs (\`/dev/shm\`, where fsync costs nothing): the difference is the price of three fsyncs per chunk."
  say ""
  sed 's/^samples = .*/chunk_size = 16/' studies/default.toml > "$work/fsync.toml"
  fsync_run() {
    local dir=$1
    rm -rf "$dir"
    local t0 t1
    t0=$(date +%s.%N)
    "$bin" explore "$work/fsync.toml" --samples "$FSYNC_N" --out "$dir" --quiet --no-report > /dev/null
    t1=$(date +%s.%N)
    awk "BEGIN{printf \"%.2f\", $t1 - $t0}"
  }
  shm=/dev/shm/polywear-fsync-$$
  {
    for round in 1 2 3; do
      echo "round $round: disk $(fsync_run "$work/fsync_disk") s, tmpfs $(fsync_run "$shm") s"
    done
    echo "($((FSYNC_N / 16)) chunks of 16 samples each)"
  } | block
  rm -rf "$shm"
fi

if want validate; then
  section "validate"
  say "Command: \`polywear validate --points $VALIDATE_N --seed 1\` (fast classifier against brute force, 2 wheels × 3 variants per point)."
  say ""
  timed "$bin" validate --points "$VALIDATE_N" --seed 1 --out "$work/validate.csv" > "$work/validate.out" 2> "$work/validate.err"
  { cat "$work/validate.out"; echo "wall: $(tail -1 "$work/validate.err")"; } | block
fi

if want hot-paths; then
  section "hot-paths"
  say "Command: \`cargo bench --bench hot_paths -- $CRITERION\` (criterion: low, mean and high estimate of the time per iteration)."
  say ""
  # shellcheck disable=SC2086
  cargo bench --quiet --bench hot_paths -- $CRITERION 2>/dev/null | criterion_lines | block
fi

if want classifier-throughput; then
  section "classifier-throughput"
  say "Command: \`cargo bench --bench classifier_throughput -- $THROUGHPUT_N\` (add \`--peers\` for the Python peers on the"
  say "same samples; the peers' own section below runs them on a point set)."
  say ""
  cargo bench --quiet --bench classifier_throughput -- "$THROUGHPUT_N" 2>/dev/null | block
fi

if want wear-estimator; then
  section "wear-estimator"
  say "Command: \`cargo bench --bench wear -- $THROUGHPUT_N\` (both wheels of the default study classified without and with the per-sample wear estimator, interleaved, best of 2; the estimator's RHS evaluations per wheel by class)."
  say ""
  cargo bench --quiet --bench wear -- "$THROUGHPUT_N" 2>/dev/null | block
fi

if want wear-life; then
  section "wear-life"
  say "Command: \`cargo bench --bench wear_life -- $LIFE_N [studies/excess_toe.toml]\` (the study classified, with the plain answer over the tread's life, and with the shipped (saturated) answer instead, interleaved, best of 2; the wheels each gives a visible polygon within 60,000 km), on the default study and on one where polygons are common."
  say ""
  cargo bench --quiet --bench wear_life -- "$LIFE_N" 2>/dev/null | block
  cargo bench --quiet --bench wear_life -- "$LIFE_N" studies/excess_toe.toml 2>/dev/null | block
fi

if want wear-loop; then
  section "wear-loop"
  say "Command: \`polywear wear --distance-km $WEAR_KM --calibration-band off\` at the default point, both wheels in parallel: the worst case at a steady speed (\`--set wear_share_straight=1 --speed-spread-kmh 0\`), then the shipped defaults (5 km/h of spread) at 5 speeds (the default) and at 1 (\`--speed-nodes 1\`), one after the other; last the shipped defaults with the calibration band (the default: the loop again under the band's ends)."
  say ""
  for args in "--calibration-band off --set wear_share_straight=1 --speed-spread-kmh 0" "--calibration-band off" "--calibration-band off --speed-nodes 1" ""; do
    # shellcheck disable=SC2086
    timed "$bin" wear --quiet --distance-km "$WEAR_KM" $args --out "$work/wear" > "$work/wear.out" 2> "$work/wear.err"
    echo "wear ${args:-(shipped defaults, with the band)}: $(tail -1 "$work/wear.err")"
  done | block
fi

if want chart; then
  section "chart"
  say "Command: \`cargo bench --bench chart -- $CRITERION\` (one speed × toe-in chart of both wheels beside a 200×200 eigenvalue grid of the same box; criterion: low, mean and high estimate)."
  say ""
  # shellcheck disable=SC2086
  cargo bench --quiet --bench chart -- $CRITERION 2>/dev/null | criterion_lines | block
fi

if want cycle; then
  section "cycle"
  say "Command: \`cargo bench --bench cycle -- $CYCLE_REPEATS\` (the WLTC class 3b, 1,801 steps × 2 wheels, beside the same steps classified independently, alternating)."
  say ""
  cargo bench --quiet --bench cycle -- "$CYCLE_REPEATS" 2>/dev/null | block
fi

if want cycle-life; then
  section "cycle-life"
  say "Command: \`polywear cycle data/cycles/wltc_class3b.csv --study studies/default.toml --structure-samples $CYCLE_STRUCTURES -q [--no-wear]\`, two alternating pairs (the vibration alone, and with the one wear answer: each step's profile over the tread's life)."
  say ""
  for pair in 1 2; do
    for stage in no-wear wear; do
      flag=()
      [ "$stage" = no-wear ] && flag=(--no-wear)
      timed_cpu "$bin" cycle data/cycles/wltc_class3b.csv --study studies/default.toml \
        --structure-samples "$CYCLE_STRUCTURES" -q "${flag[@]}" \
        --out "$work/cycle-$stage" > /dev/null 2> "$work/cycle.err"
      echo "pair $pair, $stage: $(tail -1 "$work/cycle.err")"
    done
  done | block
fi

if want sampling; then
  section "sampling"
  say "Command: \`cargo bench --bench sampling -- $CRITERION\` (criterion: low, mean and high estimate of the time per iteration)."
  say ""
  # shellcheck disable=SC2086
  cargo bench --quiet --bench sampling -- $CRITERION 2>/dev/null | criterion_lines | block
fi

if want analyze; then
  section "analyze"
  say "Command: \`RUNS=$ANALYZE_RUNS benches/analyze_scaling.sh $ANALYZE_SIZES\` (explore output reused from data/bench_analyze/)."
  say ""
  # shellcheck disable=SC2086
  RUNS=$ANALYZE_RUNS benches/analyze_scaling.sh $ANALYZE_SIZES | block
fi

if want peers; then
  section "peers"
  if peers_ok; then
    say "Command: \`benches/peers/compare.sh $PEERS_N $PEERS_SCIPY\`."
    say ""
    python3 benches/peers/compare.py "$work/peers" "$bin" "$PEERS_N" "$PEERS_SCIPY" 2>&1 | block
  else
    say "(skipped: python3 lacks scipy or numba; \`benches/peers/compare.sh\` installs them)"
  fi
fi

if want reproduce; then
  section "reproduce"
  say "Command: \`polywear reproduce $REPRODUCE\` (the paper's analyses, both wheels, all three variants)."
  say ""
  # shellcheck disable=SC2086
  timed "$bin" reproduce $REPRODUCE --out "$work/paper" > "$work/reproduce.out" 2> "$work/reproduce.err"
  { tail -n 3 "$work/reproduce.out"; echo "wall: $(tail -1 "$work/reproduce.err")"; } | block
  say "From its report.md:"
  say ""
  sed -n '/^## Table 3/,/^## Figures/p' "$work/paper/report.md" | grep -v "^## Figures" | sed 's/^## /#### /' | tee -a "$report"
fi

if want decoding; then
  section "decoding"
  say "Command: \`polywear explore studies/decoding.toml --samples $DECODING_N\` (robustness to the lost digits)."
  say ""
  timed "$bin" explore studies/decoding.toml --samples "$DECODING_N" --out "$work/decoding" > "$work/decoding.out" 2> "$work/decoding.err"
  { grep -E "samples evaluated|sliding_share (rear \(follower\)|paired|front \(driving\))|lost digits" "$work/decoding.out" || true; echo "wall: $(tail -1 "$work/decoding.err")"; } | block
fi

if want scenarios; then
  section "scenarios"
  say "Command: \`polywear explore studies/toe_and_pressure.toml --samples $SCENARIOS_N\` (three scenarios: each sample evaluated four times), then \`polywear optimize studies/toe_and_pressure.toml --vary toe_deg=0.05..0.40 --vary pressure_kpa=200..300 --objective vibration --samples $OPTIMIZE_N\`."
  say ""
  timed "$bin" explore studies/toe_and_pressure.toml --samples "$SCENARIOS_N" --out "$work/scenarios" > "$work/scenarios.out" 2> "$work/scenarios.err"
  timed "$bin" optimize studies/toe_and_pressure.toml --vary toe_deg=0.05..0.40 --vary pressure_kpa=200..300 --objective vibration --samples "$OPTIMIZE_N" --out "$work/optimum" > "$work/optimize.out" 2> "$work/optimize.err"
  { grep -E "samples evaluated|follower's risk" "$work/scenarios.out" || true; echo "wall: $(tail -1 "$work/scenarios.err")"
    grep -E "evaluated in|optimum:" "$work/optimize.out" || true; echo "wall: $(tail -1 "$work/optimize.err")"; } | block
fi

if want calibrate; then
  section "calibrate"
  if [ "$quick" = 1 ]; then
    say "(skipped in --quick: the fit over 256 lost-digit combinations takes minutes)"
  else
    say "Command: \`polywear calibrate studies/paper_targets.toml\`."
    say ""
    timed "$bin" calibrate studies/paper_targets.toml --out "$work/fit.toml" > "$work/calibrate.out" 2> "$work/calibrate.err"
    { cat "$work/calibrate.out"; echo "wall: $(tail -1 "$work/calibrate.err")"; } | block
  fi
fi

say "Finished $(date -u +%H:%M:%S) UTC; load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)."
echo "report: $report" >&2
