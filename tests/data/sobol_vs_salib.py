"""Sobol indices of `polywear analyze` against SALib on the same rows.

Usage: python3 sobol_vs_salib.py RUN_DIR
RUN_DIR is a finished `polywear explore` run of a `saltelli` study (its `_report/` written).
For every variant, wheel and output (the vibration indicator: limit cycle or bistable; and
amp_v_mps), the explore rows
are put into SALib's Saltelli order (per base point: A, AB_1 .. AB_D, B), base points with an
unclassified block left out as polywear leaves them out, and `SALib.analyze.sobol.analyze(...,
calc_second_order=False)` gives S1 and ST; they must equal polywear's `first_order` and `total`
to 1e-9. Exits 1 on any difference.
"""
import glob
import json
import sys

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
from SALib.analyze import sobol

run = sys.argv[1]
files = sorted(glob.glob(f"{run}/chunk-*.parquet"))
meta = pq.read_metadata(files[0]).metadata
names = json.loads(meta[b"drawn_names"])
rows = pd.concat(
    [pd.read_parquet(f, columns=["variant", "wheel", "sample_id", "class", "amp_v_mps"]) for f in files]
)
ours = pd.read_parquet(f"{run}/_report/sensitivity.parquet")
d = len(names)
stride = d + 2
vibrating = {"limit_cycle", "bistable"}
classified = vibrating | {"stable"}
worst = 0.0
checked = 0
for (variant, wheel), g in rows.groupby(["variant", "wheel"]):
    g = g.sort_values("sample_id")
    base = g["sample_id"].to_numpy() // stride
    block = g["sample_id"].to_numpy() % stride
    ok = g["class"].isin(classified).to_numpy()
    complete = pd.Series(ok).groupby(base).agg(["all", "size"])
    keep = complete.index[(complete["all"]) & (complete["size"] == stride)]
    sel = np.isin(base, keep)
    for output in ["vibration", "amp_v_mps"]:
        y = g["class"].isin(vibrating).to_numpy(float) if output == "vibration" else g["amp_v_mps"].to_numpy(float)
        # polywear's blocks: 0 = A, 1 = B, 2 + m = AB_m; SALib's: 0 = A, 1 + m = AB_m, d + 1 = B.
        table = np.full((len(keep), stride), np.nan)
        index = {b: i for i, b in enumerate(keep)}
        for b, k, v in zip(base[sel], block[sel], y[sel]):
            salib_block = 0 if k == 0 else (d + 1 if k == 1 else k - 1)
            table[index[b], salib_block] = v
        assert not np.isnan(table).any()
        mine = ours[(ours.variant == variant) & (ours.wheel == wheel) & (ours.output == output)]
        if len(keep) < 2 or np.var(np.r_[table[:, 0], table[:, -1]]) == 0:
            continue
        problem = {"num_vars": d, "names": names, "bounds": [[0.0, 1.0]] * d}
        si = sobol.analyze(problem, table.reshape(-1), calc_second_order=False, num_resamples=10, seed=1)
        for j, name in enumerate(names):
            r = mine[mine.param == name]
            assert len(r) == 1, (variant, wheel, output, name)
            for ours_col, theirs in [("first_order", si["S1"][j]), ("total", si["ST"][j])]:
                diff = abs(float(r[ours_col].iloc[0]) - float(theirs))
                worst = max(worst, diff)
                checked += 1
                status = "ok" if diff <= 1e-9 else "DIFFERS"
                print(f"{status} {variant} {wheel} {output} {name} {ours_col}: polywear {float(r[ours_col].iloc[0]):.12f} SALib {float(theirs):.12f}")
print(f"{checked} indices compared, largest difference {worst:.3e}")
if checked == 0 or worst > 1e-9:
    sys.exit(1)
