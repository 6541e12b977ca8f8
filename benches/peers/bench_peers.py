"""The peers' half of `cargo bench --bench classifier_throughput -- --peers`: the SciPy and numba
peers on the first N samples of the default study (drawn by polywear itself, so the points are
the bench's), printing rows of the bench's table: samples/s, cores, mean and p95 RHS evaluations
per integrated wheel, and class agreement with polywear outside the Hopf band.

Usage: python3 benches/peers/bench_peers.py POLYWEAR_BINARY N_SAMPLES SEED [N_SCIPY=50]
"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import pandas as pd

sys.path.insert(0, os.path.dirname(__file__))
import model  # noqa: E402

binary, n, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
n_scipy = min(n, int(sys.argv[4]) if len(sys.argv) > 4 else 50)
cores = os.cpu_count()

with tempfile.TemporaryDirectory() as tmp:
    run_dir = os.path.join(tmp, "run")
    subprocess.run([binary, "explore", "--samples", str(n), "--seed", str(seed), "--no-report",
                    "--quiet", "--out", run_dir], check=True)
    df = pd.read_parquet(run_dir)
variant = df.variant.iloc[0]
df = df[df.variant == variant]
params = [k for k in model.DEFAULTS if k in df.columns]
pts = df[df.wheel == "follower"].sort_values("sample_id")[params].reset_index(drop=True)
points = [dict(model.DEFAULTS, **{k: float(row[k]) for k in params}) for _, row in pts.iterrows()]
ref = {(int(r.sample_id), r.wheel): (r["class"], r.eig_re_max) for _, r in df.iterrows()}


def agreement(rows):
    return "{}/{}".format(*model.class_agreement(rows, ref))


def row(name, samples, secs, c, evals, rows):
    e = np.array(evals, dtype=float)
    print(f"{name:<28} {samples:>9} {c:>7} {samples / secs:>12.1f} {e.mean():>16.0f} "
          f"(p95 {np.percentile(e, 95):.0f}; classes agree with polywear `{variant}`: {agreement(rows)})")


import numba_peer  # noqa: E402

numba_peer.warm_up()
t0 = time.perf_counter()
rows, evals = numba_peer.run_counted(points)
row("numba DP5 batch (prange)", n, time.perf_counter() - t0, cores, evals, rows)

import scipy_peer  # noqa: E402

t0 = time.perf_counter()
rows, evals = scipy_peer.run_counted(points[:n_scipy])
row("SciPy solve_ivp DOP853", n_scipy, time.perf_counter() - t0, 1, evals, rows)
