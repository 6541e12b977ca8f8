"""First-order indices of `polywear analyze` (first_order.parquet) against SALib's given-data
estimator on the same rows.

Usage: python3 first_order_vs_salib.py RUN_DIR
RUN_DIR is a finished `polywear explore` run of any design (its `_report/` written; of a
Saltelli design, the rows of its base matrices A and B). For every variant and wheel, the
classified rows (stable, limit cycle, bistable) give X (the drawn
parameters' columns) and Y (1 when the wheel vibrates: limit cycle or bistable). SALib's
`delta.analyze(..., method="sobol")` gives S1 and its S1_conf (1.96 bootstrap standard
deviations); polywear's `first_order` must lie within S1 ± S1_conf, and so must the same
estimator on the unresampled rows (`delta.sobol_first`). polywear's own `first_order_conf`
must be within a factor of 2 of SALib's. Exits 1 on any failure.
"""
import glob
import json
import sys

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
from SALib.analyze import delta

run = sys.argv[1]
files = sorted(glob.glob(f"{run}/chunk-*.parquet"))
meta = pq.read_metadata(files[0]).metadata
names = json.loads(meta[b"drawn_names"])
rows = pd.concat(
    [pd.read_parquet(f, columns=["variant", "wheel", "sample_id", "class"] + names) for f in files]
)
if meta[b"design"] == b"saltelli":  # only the base matrices A and B are independent draws
    rows = rows[rows.sample_id % (len(names) + 2) < 2]
ours = pd.read_parquet(f"{run}/_report/first_order.parquet")
vibrating = {"limit_cycle", "bistable"}
classified = vibrating | {"stable"}
failed = checked = 0
for (variant, wheel), g in rows.groupby(["variant", "wheel"]):
    g = g[g["class"].isin(classified)]
    x = g[names].to_numpy(float)
    y = g["class"].isin(vibrating).to_numpy(float)
    if np.ptp(y) == 0:
        continue
    problem = {"num_vars": len(names), "names": names, "bounds": [[0.0, 1.0]] * len(names)}
    si = delta.analyze(problem, x, y, num_resamples=100, seed=1, method="sobol")
    n = len(y)
    exp = 2.0 / (7.0 + np.tanh((1500.0 - n) / 500.0))
    m = np.linspace(0, n, int(np.round(min(int(np.ceil(n**exp)), 48))) + 1)
    for j, name in enumerate(names):
        mine = ours[(ours.variant == variant) & (ours.wheel == wheel) & (ours.param == name)]
        assert len(mine) == 1, (variant, wheel, name)
        s1, conf = float(mine.first_order.iloc[0]), float(mine.first_order_conf.iloc[0])
        theirs, their_conf = float(si["S1"][j]), float(si["S1_conf"][j])
        raw = float(delta.sobol_first(y, x[:, j], m))
        ok = (
            abs(s1 - theirs) <= their_conf
            and abs(s1 - raw) <= their_conf
            and 0.5 <= conf / their_conf <= 2.0
            and int(mine.rows.iloc[0]) == n
        )
        checked += 1
        failed += not ok
        print(
            f"{'ok' if ok else 'DIFFERS'} {variant} {wheel} {name}: polywear {s1:.4f} ± {conf:.4f}, "
            f"SALib {theirs:.4f} ± {their_conf:.4f} (same rows unresampled {raw:.4f}), {n} rows"
        )
print(f"{checked} first-order indices compared, {failed} outside SALib's interval")
if checked == 0 or failed:
    sys.exit(1)
