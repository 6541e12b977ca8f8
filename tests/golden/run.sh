#!/usr/bin/env bash
# tests/golden/run.sh BIN OUT: runs every shipped study and command (and a few refusals) with the
# binary BIN into OUT, from the repository root. Run it with the binary before and after a
# refactor, then `python3 tests/golden/compare.py OUT_BEFORE OUT_AFTER` (pyarrow) compares them
# file by file: Parquet rows (NaN = NaN) and metadata key by key, text with timings masked. Copy
# each binary to one path first (the `command` metadata names it). Not run by CI: a maintainer's
# check that a change meant to keep the outputs keeps them.
BIN=$1; OUT=$2
rm -rf "$OUT"; mkdir -p "$OUT"
export RAYON_NUM_THREADS=2
n=0
case_() {
  local name=$1; shift
  mkdir -p "$OUT/$name"
  ( "$BIN" "$@" > "$OUT/$name/stdout" 2> "$OUT/$name/stderr"; echo $? > "$OUT/$name/rc" )
  echo "$name rc=$(cat $OUT/$name/rc)"
}
O=$OUT
case_ explore_default explore --samples 3000 --out $O/explore_default/out --quiet
case_ explore_default_nowear explore --samples 2000 --no-wear --out $O/explore_default_nowear/out --quiet
for s in decoding default excess_toe fleet_telematics grid_4axes toe_and_pressure wide_structure; do
  case_ study_$s explore studies/$s.toml --samples 1500 --out $O/study_$s/out --quiet
done
case_ study_grid_4axes_whole explore studies/grid_4axes.toml --out $O/study_grid_4axes_whole/out --quiet
case_ shard0 explore studies/wide_structure.toml --samples 1200 --shard 0/2 --out $O/shard0/out --quiet
case_ shard1 explore studies/wide_structure.toml --samples 1200 --shard 1/2 --out $O/shard1/out --quiet
case_ analyze_shards analyze $O/shard0/out $O/shard1/out --out $O/analyze_shards/out
case_ analyze_pair analyze $O/explore_default/out --pair g_mod,load_n --out $O/analyze_pair/out
case_ classify_points classify tests/data/points.csv --out $O/classify_points/out.csv
case_ classify_fleet classify studies/fleet_telematics.csv --weight hours --out $O/classify_fleet/out.csv
case_ cycle_wltc cycle data/cycles/wltc_class3b.csv --set toe_deg=0.3 --out $O/cycle_wltc/out
case_ cycle_hwfet cycle data/cycles/hwfet.csv --study studies/default.toml --structure-samples 8 --out $O/cycle_hwfet/out
case_ optimize optimize studies/toe_and_pressure.toml --vary toe_deg=0.05..0.40 --vary pressure_kpa=200..300 --samples 400 --grid 4 --levels 1 --out $O/optimize/out
case_ optimize_vib optimize --vary toe_deg=0.05..0.40 --objective vibration --wheel follower --samples 300 --grid 5 --levels 1 --out $O/optimize_vib/out
case_ simulate simulate
case_ simulate_json simulate --speed 150 --toe 0.4 --variant paper --json
case_ simulate_plot simulate --plot $O/simulate_plot/p.png --out $O/simulate_plot/p.parquet
case_ cycle_params_note cycle data/cycles/hwfet.csv --params studies/params_r0.toml --set g_mod=0.9e6 --out $O/cycle_params_note/out
case_ simulate_params_note simulate --params studies/params_r0.toml --set g_mod=0.9e6
case_ wear wear --out $O/wear/out
case_ wear_est wear --set wear_share_straight=1 --speed-spread-kmh 0 --estimate --out $O/wear_est/out
case_ wear_cycle wear --cycle data/cycles/hwfet.csv --distance-km 20000 --out $O/wear_cycle/out
case_ bifurcation bifurcation --param speed_kmh --from 40 --to 260 --steps 60 --out $O/bifurcation/out
case_ bifurcation_r0 bifurcation --param toe_deg --from 0.05 --to 1 --steps 40 --params studies/params_r0.toml --out $O/bifurcation_r0/out
case_ chart chart --x speed_kmh --x-from 60 --x-to 250 --y toe_deg --y-from 0.05 --y-to 0.6 --out $O/chart/chart.parquet
case_ reproduce reproduce --out $O/reproduce/out
case_ calibrate calibrate studies/paper_targets.toml --out $O/calibrate/fit.toml
case_ validate validate --points 12 --seed 1 --out $O/validate/out.csv
case_ params params
case_ params_md params --markdown
case_ bad_samples explore --samples -1 --out $O/bad_samples/out
case_ bad_set simulate --set toe_deg=99
case_ bad_wear wear --speed 0 --out $O/bad_wear/out
case_ bad_key simulate --set toe_dge=0.2
case_ bad_vary optimize --vary toe_deg=0.4..0.1 --out $O/bad_vary/out
