#!/usr/bin/env bash
# The long-term loop's answer over its field-fitted constants (docs/lab/2026-12-07-two-levels-and-the-first-calibration.md#the-loops-constants-searched):
# `polywear wear` at the calibration point (110 km/h, 0.45 deg) and at the default study's median
# point (115 km/h, 0.25 deg), the nominal tire at the default load and pressure, for each
# (phi_s, sigma_V, carcass_share) of the design below; one CSV line per run on stdout:
#
#   phi_s,sigma_v_kmh,carcass_share,speed_kmh,toe_deg,follower_km,follower_sides,driving_km,driving_sides
#
# where *_km is the distance to a visible polygon, or `worn` (the tire is worn out first) or
# `none` (no polygon within the run's distance). Each run takes about 40 s on one core; the whole
# design (52 runs) about 20 minutes on 2 cores.
#
#   POLYWEAR=target/release/polywear studies/loop_constants.sh > loop_constants.csv
set -euo pipefail
polywear=${POLYWEAR:-polywear}
jobs=${JOBS:-2}

one() {
    local phi=$1 sigma=$2 carcass=$3 speed=$4 toe=$5 line f d
    line=$("$polywear" wear --speed "$speed" --toe "$toe" --set wear_share_straight="$phi" \
        --set speed_spread_kmh="$sigma" --set carcass_share="$carcass" --calibration-band off \
        | sed -n 2p)
    f=${line%%; driving:*}
    d=${line#*; driving:}
    echo "$phi,$sigma,$carcass,$speed,$toe,$(verdict "$f"),$(verdict "$d")"
}

# `follower: an 18-sided polygon becomes visible after 24,800 km ...` -> `24800,18`.
verdict() {
    if [[ $1 =~ ([0-9]+)-sided\ polygon\ becomes\ visible\ after\ ([0-9,]+)\ km ]]; then
        echo "${BASH_REMATCH[2]//,/},${BASH_REMATCH[1]}"
    elif [[ $1 == *"worn out"* ]]; then
        echo "worn,"
    else
        echo "none,"
    fi
}
export -f one verdict
export polywear

design() {
    for phi in 0.22 0.25 0.28 0.32 0.36 0.42 0.5; do
        for sigma in 2 5 10; do
            echo "$phi $sigma 0.5 110 0.45"
            echo "$phi $sigma 0.5 115 0.25"
        done
    done
    for carcass in 0.3 0.7; do
        for pair in "0.2 5" "0.22 5" "0.25 5" "0.28 5" "0.36 10"; do
            echo "${pair% *} ${pair#* } $carcass 110 0.45"
        done
    done
}

echo "phi_s,sigma_v_kmh,carcass_share,speed_kmh,toe_deg,follower_km,follower_sides,driving_km,driving_sides"
design | xargs -P "$jobs" -L 1 bash -c 'one "$@"' _ | sort -t, -k3,3 -k1,1g -k2,2g -k4,4g
