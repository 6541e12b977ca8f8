"""Runs polywear and the Python peers on the same points and prints the comparison table.

Usage: python3 benches/peers/compare.py OUT_DIR POLYWEAR_BINARY [N_POINTS] [N_SCIPY]
"""
import csv
import os
import subprocess
import sys
import time

import pandas as pd

sys.path.insert(0, os.path.dirname(__file__))
import model  # noqa: E402

out_dir, binary = sys.argv[1], sys.argv[2]
n_points = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
n_scipy = int(sys.argv[4]) if len(sys.argv) > 4 else 50
os.makedirs(out_dir, exist_ok=True)
cores = os.cpu_count()

# The point set: n_points samples of the default study (operating point and tire structure).
run_dir = os.path.join(out_dir, "points_run")
subprocess.run(["rm", "-rf", run_dir], check=True)
subprocess.run([binary, "explore", "--samples", str(n_points), "--seed", "7", "--no-report", "--quiet",
                "--out", run_dir], check=True)
df = pd.read_parquet(run_dir)
params = ["speed_kmh", "toe_deg", "load_n", "pressure_kpa", "g_mod", "c_brush", "tread_height", "rho"]
pts = df[df.wheel == "follower"].sort_values("sample_id")[params].reset_index(drop=True)
points_csv = os.path.join(out_dir, "points.csv")
pts.to_csv(points_csv, index=False, float_format="%.17g")
points = [dict(model.DEFAULTS, **{k: float(row[k]) for k in params}) for _, row in pts.iterrows()]

# polywear, all cores.
poly_csv = os.path.join(out_dir, "polywear.csv")
t0 = time.perf_counter()
subprocess.run([binary, "classify", points_csv, "--out", poly_csv], check=True, stderr=subprocess.DEVNULL)
t_poly = time.perf_counter() - t0
poly = pd.read_csv(poly_csv)
ref = {(r.point, r.wheel): (r["class"], r.eig_re_max) for _, r in poly.iterrows()}


def agreement(rows):
    return model.class_agreement(rows, ref)


results = [("polywear (shooting)", n_points, t_poly, cores, *agreement(
    [(r.point, r.wheel, r["class"]) for _, r in poly.iterrows()]))]

import numba_peer  # noqa: E402

t0 = time.perf_counter()
numba_peer.warm_up()
t_compile = time.perf_counter() - t0
t0 = time.perf_counter()
rows = numba_peer.run(points)
t_numba = time.perf_counter() - t0
results.append(("numba DP5 batch (prange)", n_points, t_numba, cores, *agreement(rows)))

import scipy_peer  # noqa: E402

t0 = time.perf_counter()
rows = scipy_peer.run(points[:n_scipy])
t_scipy = time.perf_counter() - t0
results.append(("SciPy solve_ivp DOP853", n_scipy, t_scipy, 1, *agreement(rows)))

poly_rate = n_points / t_poly
print(f"\nSame {n_points} points of the default study (both wheels each), paper variant, {cores} cores.")
print(f"numba compile time (excluded): {t_compile:.1f} s\n")
hdr = f"{'tool':<28} {'points':>7} {'wall [s]':>9} {'points/s':>10} {'cores':>6} {'agree':>11} {'polywear is':>13}"
print(hdr)
print("-" * len(hdr))
with open(os.path.join(out_dir, "results.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["tool", "points", "wall_s", "points_per_s", "cores", "agree", "compared", "polywear_speedup"])
    for name, n, t, c, ok, cmp_ in results:
        rate = n / t
        ratio = poly_rate / rate
        print(f"{name:<28} {n:>7} {t:>9.2f} {rate:>10.1f} {c:>6} {ok:>5}/{cmp_:<5} {ratio:>12.1f}x")
        w.writerow([name, n, f"{t:.4f}", f"{rate:.3f}", c, ok, cmp_, f"{ratio:.2f}"])
    per_core = poly_rate / cores / (n_scipy / t_scipy)
    print(f"\nper core, polywear vs SciPy: {per_core:.0f}x (SciPy runs on one core)")
print(f"results: {os.path.join(out_dir, 'results.csv')}")
