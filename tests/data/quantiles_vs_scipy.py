#!/usr/bin/env python3
"""polywear's quantile functions against SciPy's ppf.

Reads the JSON lines of `cargo run --release --example dump_quantiles` (a file argument, or
stdin): per distribution, 10,000 probabilities from 1e-12 to 1 - 1e-12 and polywear's quantile
at each. Every value must agree with SciPy's `ppf` to a relative error of 1e-10. Where the two
disagree by more, an mpmath evaluation at 60 digits referees: if SciPy is off there by more than
1e-12 (SciPy is not accurate at that point), polywear is held to 1e-10 of mpmath instead;
otherwise the point fails. Relative error is taken against max(|x|, 1e-6 * scale), scale being
the distribution's sd (its width for uniform and levels), since a quantile that crosses zero has
only absolute accuracy there, whoever computes it.

Independently of SciPy, every 50th probability of each continuous distribution (and both ends)
is checked against mpmath alone, to the same tolerance.

Exit status 0 if every point passes, 1 otherwise.
"""

import json
import sys

import mpmath as mp
import numpy as np
from scipy import stats

TOL = 1e-10
SCIPY_ACCURATE = 1e-12
mp.mp.dps = 60


def scipy_ppf(d, p):
    kind = d["dist"]
    if kind == "uniform":
        return stats.uniform(loc=d["min"], scale=d["max"] - d["min"]).ppf(p)
    if kind == "normal":
        return stats.norm(loc=d["mean"], scale=d["sd"]).ppf(p)
    if kind == "lognormal":
        return stats.lognorm(s=d["sigma"], scale=d["median"]).ppf(p)
    if kind == "truncated_normal":
        a = (d["min"] - d["mean"]) / d["sd"]
        b = (d["max"] - d["mean"]) / d["sd"]
        return stats.truncnorm(a, b, loc=d["mean"], scale=d["sd"]).ppf(p)
    if kind == "levels":
        levels = np.array(d["levels"])
        return levels[stats.randint(0, len(levels)).ppf(p).astype(int)]
    raise ValueError(kind)


def scale(d):
    kind = d["dist"]
    if kind in ("normal", "truncated_normal"):
        return d["sd"]
    if kind == "lognormal":
        return d["median"] * d["sigma"]
    if kind == "uniform":
        return d["max"] - d["min"]
    return max(d["levels"]) - min(d["levels"])


def mp_ppf(d, p, guess):
    """High-precision quantile: solves ln F(z) = ln target on the side where F is small."""
    u = mp.mpf(p)
    kind = d["dist"]
    cdf = lambda z: mp.ncdf(z)  # noqa: E731
    sf = lambda z: mp.ncdf(-z)  # noqa: E731
    if kind == "normal" or kind == "lognormal":
        mean, sd = (d["mean"], d["sd"]) if kind == "normal" else (0.0, d["sigma"])
        if u < 0.5:
            f, target = cdf, u
        else:
            f, target = sf, 1 - u
        z0 = (guess - mean) / sd if kind == "normal" else mp.log(guess / d["median"]) / sd
    elif kind == "truncated_normal":
        mean, sd = d["mean"], d["sd"]
        a = (mp.mpf(d["min"]) - mean) / sd
        b = (mp.mpf(d["max"]) - mean) / sd
        if a < 0:
            f, target = cdf, cdf(a) + u * (cdf(b) - cdf(a))
        else:
            f, target = sf, sf(a) - u * (sf(a) - sf(b))
        z0 = (guess - mean) / sd
    else:
        return None
    lt = mp.log(target)
    z = mp.findroot(lambda z: mp.log(f(z)) - lt, mp.mpf(z0))
    if kind == "lognormal":
        return float(d["median"] * mp.exp(sd * z))
    return float(mean + sd * z)


def main():
    src = open(sys.argv[1]) if len(sys.argv) > 1 else sys.stdin
    failures = 0
    total = 0
    worst_overall = 0.0
    mp_worst_overall = 0.0
    for line in src:
        d = json.loads(line)
        p = np.array(d["p"])
        x = np.array(d["x"])
        ref = scipy_ppf(d, p)
        floor = 1e-6 * scale(d)
        rel = np.abs(x - ref) / np.maximum(np.abs(ref), floor)
        if d["dist"] == "levels":
            # A discrete ppf is a step: SciPy takes the lower level at an exact step (p·n
            # whole), polywear the upper; compare away from the steps.
            n = len(d["levels"])
            rel[np.abs(p * n - np.round(p * n)) < 1e-9] = 0.0
        bad = np.flatnonzero(~(rel <= TOL))
        refereed, case_fail = 0, []
        for i in bad:
            m = mp_ppf(d, p[i], x[i])
            if m is None:
                case_fail.append((p[i], x[i], ref[i], None))
                continue
            scipy_err = abs(ref[i] - m) / max(abs(m), floor)
            ours_err = abs(x[i] - m) / max(abs(m), floor)
            if scipy_err > SCIPY_ACCURATE and ours_err <= TOL:
                refereed += 1
            else:
                case_fail.append((p[i], x[i], ref[i], m))
        ok = np.ones(len(p), bool)
        ok[bad] = False
        worst = float(np.max(rel[ok])) if ok.any() else float("nan")
        worst_overall = max(worst_overall, worst)
        # An independent check of polywear alone: mpmath at every 50th probability and both ends.
        mp_worst = 0.0
        if d["dist"] in ("normal", "lognormal", "truncated_normal"):
            for i in sorted((set(range(0, len(p), 50)) | {0, len(p) - 1}) - set(bad)):
                m = mp_ppf(d, p[i], x[i])
                err = abs(x[i] - m) / max(abs(m), floor)
                mp_worst = max(mp_worst, err)
                if not err <= TOL:
                    case_fail.append((p[i], x[i], ref[i], m))
        mp_worst_overall = max(mp_worst_overall, mp_worst)
        total += len(p)
        status = "ok" if not case_fail else "FAIL"
        print(
            f"{status:4} {d['case']:34} {d['dist']:16} n={len(p)} "
            f"max rel err vs SciPy {worst:.1e}, vs mpmath {mp_worst:.1e}"
            + (f"; SciPy inaccurate at {refereed} points (off by > {SCIPY_ACCURATE} from mpmath), polywear within {TOL} of mpmath there" if refereed else "")
        )
        for p_i, x_i, r_i, m_i in case_fail[:5]:
            print(f"     p={float(p_i)!r}: polywear {float(x_i)!r}, SciPy {float(r_i)!r}, mpmath {m_i!r}")
        failures += len(case_fail)
    print(
        f"{total} quantiles checked: worst relative error {worst_overall:.1e} vs SciPy (points within "
        f"tolerance), {mp_worst_overall:.1e} vs mpmath (every 50th point); {failures} failures (tolerance {TOL})"
    )
    sys.exit(1 if failures or total == 0 else 0)


if __name__ == "__main__":
    main()
