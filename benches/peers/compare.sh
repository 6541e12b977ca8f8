#!/usr/bin/env bash
# polywear against what users would otherwise write (SciPy solve_ivp, numba), on the same
# points, one after another. Installs the Python peers with pip, builds polywear, prints the
# table and writes data/peers/results.csv.
# Usage: benches/peers/compare.sh [N_POINTS=1000] [N_SCIPY=50]
set -euo pipefail
cd "$(dirname "$0")/../.."
python3 -m pip install --quiet --disable-pip-version-check scipy numba pandas pyarrow 2>&1 | grep -v "as the 'root' user" || true
cargo build --release --quiet
python3 benches/peers/compare.py data/peers "${CARGO_TARGET_DIR:-target}/release/polywear" "${1:-1000}" "${2:-50}"
