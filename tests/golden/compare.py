#!/usr/bin/env python3
"""tests/golden/compare.py A B (see run.sh): every file under A against B. Parquet: rows (NaN = NaN) and metadata key by
key; text: line by line after masking timings and the run folder; others: bytes."""
import os, re, sys, math
import pyarrow.parquet as pq

A, B = sys.argv[1], sys.argv[2]
IGN = re.compile(r"(\d+(\.\d+)?\s*(s|ms|µs|min)\b|samples/s|elapsed|wall|ETA|\d+(\.\d+)? ?[kM]?B\b)")
def mask(text, root):
    text = text.replace(root, "<OUT>")
    return [IGN.sub("<T>", l) for l in text.splitlines()]

def files(root):
    out = set()
    for d, _, fs in os.walk(root):
        for f in fs:
            out.add(os.path.relpath(os.path.join(d, f), root))
    return out

fa, fb = files(A), files(B)
bad = 0
for f in sorted(fa ^ fb):
    print("ONLY IN", "A" if f in fa else "B", f); bad += 1
for f in sorted(fa & fb):
    pa, pb = os.path.join(A, f), os.path.join(B, f)
    if f.endswith(".parquet"):
        ta, tb = pq.read_table(pa), pq.read_table(pb)
        if ta.schema.names != tb.schema.names:
            print("COLUMNS", f, ta.schema.names, tb.schema.names); bad += 1; continue
        if ta.num_rows != tb.num_rows:
            print("ROWS", f, ta.num_rows, tb.num_rows); bad += 1; continue
        for c in ta.schema.names:
            xa, xb = ta.column(c).to_pylist(), tb.column(c).to_pylist()
            eq = all((x == y) or (isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y)) for x, y in zip(xa, xb))
            if not eq:
                print("VALUES", f, c); bad += 1
        ma = {k.decode(): v.decode() for k, v in (pq.read_metadata(pa).metadata or {}).items()}
        mb = {k.decode(): v.decode() for k, v in (pq.read_metadata(pb).metadata or {}).items()}
        for k in sorted(set(ma) | set(mb)):
            va, vb = ma.get(k), mb.get(k)
            if va is not None and vb is not None:
                va, vb = va.replace(A, "<OUT>"), vb.replace(B, "<OUT>")
            if va != vb:
                if k in ("created", "elapsed_s", "ARROW:schema"):
                    continue
                print("META", f, k, (va or "")[:200], "|", (vb or "")[:200]); bad += 1
        continue
    ba, bb = open(pa, "rb").read(), open(pb, "rb").read()
    if ba == bb:
        continue
    try:
        la, lb = mask(ba.decode(), A), mask(bb.decode(), B)
    except UnicodeDecodeError:
        print("BYTES", f, len(ba), len(bb)); bad += 1; continue
    if la != lb:
        import difflib
        d = list(difflib.unified_diff(la, lb, lineterm="", n=0))
        print("TEXT", f, f"({len(d)} diff lines)")
        for l in d[:12]:
            print("   ", l[:220])
        bad += 1
print(f"{bad} differences over {len(fa | fb)} files")
