"""Other Parquet layouts of the same explore rows, for docs/book/src/maintainers/benchmarks.md#output-size.

Usage: python3 benches/parquet_layouts.py RUN_DIR
Reads every chunk of RUN_DIR (a `polywear explore` output) into one table and writes it back with
pyarrow in several layouts, one row group per 8192 rows as explore's chunks have: the size per
million samples (two rows per sample) and the best of 5 polars reads of each. Lossless layouts
keep every value bit for bit; the float32 line, which does not, only shows what rounding would
buy.
"""
import glob
import os
import sys
import tempfile
import time

import polars as pl
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

run = sys.argv[1]
t = pa.concat_tables([pq.read_table(f) for f in sorted(glob.glob(f"{run}/chunk-*.parquet"))])
samples = t.num_rows / 2
floats = [f.name for f in t.schema if pa.types.is_floating(f.type)]
names = [f.name for f in t.schema if pa.types.is_string(f.type)]
ints = [f.name for f in t.schema if pa.types.is_integer(f.type)]
# The columns that differ between a sample's two wheels; the rest repeat on both rows.
per_row = ["slip_ratio", "q", "f_m", "f_s", "z0_m", "y0_m", "eig_re_max", "eig_freq_hz"]
shared = [c for c in floats if c not in per_row and c not in
          ["amp_y_m", "amp_v_mps", "freq_hz", "polygon_order", "energy_per_cycle_j", "floquet_max"]]
plain = dict(use_dictionary=names + ints)
layouts = {
    "dictionary everywhere, zstd 3 (0.5.0)": (t, dict(compression_level=3)),
    "floats plain, zstd 3 (this version)": (t, dict(compression_level=3, **plain)),
    "floats plain, zstd 9": (t, dict(compression_level=9, **plain)),
    "floats plain, zstd 19": (t, dict(compression_level=19, **plain)),
    "floats byte-stream-split, zstd 3": (t, dict(compression_level=3, use_byte_stream_split=floats, **plain)),
    "byte-stream-split where the wheels differ, zstd 3": (t, dict(compression_level=3, use_byte_stream_split=per_row, **plain)),
    "float32 (lossy), zstd 3": (
        pa.Table.from_arrays([pc.cast(t[c], pa.float32()) if c in floats else t[c] for c in t.column_names], names=t.column_names),
        dict(compression_level=3, **plain),
    ),
}
tmp = tempfile.mkdtemp()
print(f"{'layout':52s} {'MB per 1e6 samples':>19s} {'polars read':>12s}")
for name, (table, kw) in layouts.items():
    path = os.path.join(tmp, "t.parquet")
    pq.write_table(table, path, row_group_size=8192, compression="zstd", **kw)
    size = os.path.getsize(path) / samples
    best = min((lambda t0: (pl.read_parquet(path), time.perf_counter() - t0)[1])(time.perf_counter()) for _ in range(5))
    print(f"{name:52s} {size:19.1f} {best:11.3f}s")
# The inputs a sample's two rows share, moved to a table of their own (one row per sample).
fol = t.filter(pc.equal(t["wheel"], "follower")).select(["sample_id"] + shared)
rest = t.drop_columns(shared)
pq.write_table(fol, os.path.join(tmp, "a.parquet"), row_group_size=4096, compression="zstd", compression_level=3, use_dictionary=False)
pq.write_table(rest, os.path.join(tmp, "b.parquet"), row_group_size=8192, compression="zstd", compression_level=3, **{"use_dictionary": names + ints})
size = (os.path.getsize(os.path.join(tmp, "a.parquet")) + os.path.getsize(os.path.join(tmp, "b.parquet"))) / samples
print(f"{'shared inputs in a per-sample table, zstd 3':52s} {size:19.1f} {'':>12s}")
