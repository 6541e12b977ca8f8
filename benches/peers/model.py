"""The polywear model (MODEL.md#the-physics-step-by-step, steps 1-7, `paper` variant) as a Python
user would write it.

Shared by the SciPy and numba peers: the static quantities are computed once per point in plain
Python; each peer integrates the tread ODE its own way.
"""
import math

DEFAULTS = dict(
    speed_kmh=100.0, toe_deg=0.3, load_n=4000.0, pressure_kpa=240.0, r_b=0.317, r_w=0.155,
    b0=0.166, xi=0.67, psi=115.0, tread_height=0.015, rho=1250.0, g_mod=0.8645e6, c_brush=3.6e7,
    alpha2=4.0e-8, mu_m=0.76, mu_s=0.63, v_s=0.126, phi=0.94, sigma1=10.0, c_s=18.0, c_d=0.315,
    area=2.2, f0=0.0076, f1=0.000056, n_wheels=4.0, n_driven=2.0,
)


# Points closer to the Hopf boundary than this (|Re lambda| in 1/s) are not compared: there a
# fixed integration horizon cannot settle (polywear's `validation::HOPF_BAND`).
HOPF_BAND = 0.05


def class_agreement(rows, ref):
    """(agreeing, compared) classes of a peer's rows (index, wheel, class) against polywear's
    `ref` {(index, wheel): (class, eig_re_max)}, outside the Hopf band."""
    ok = n = 0
    for i, wheel, cls in rows:
        want, re = ref[(i, wheel)]
        if abs(re) >= HOPF_BAND:
            n += 1
            ok += (cls == "limit_cycle") == (want in ("limit_cycle", "bistable"))
    return ok, n


def statics(p, wheel):
    """Steps 1-7: the tread ODE's coefficients and equilibrium for one wheel, or None (no traction)."""
    tan_a = math.tan(math.radians(p["toe_deg"]))
    alpha1 = 1.0 / (2.0 * math.pi * math.sqrt(p["r_b"] * p["r_w"]))
    t = alpha1 * p["load_n"] / (2.0 * p["pressure_kpa"] * 1e3)
    delta = t + math.sqrt(t * t + p["alpha2"] * p["load_n"])
    xd = p["xi"] * delta
    a = 2.0 * math.sqrt(2.0 * p["r_b"] * xd - xd * xd)
    b = p["b0"] * (1.0 - math.exp(-p["psi"] * delta))
    beta = a / p["tread_height"]
    k_s = p["g_mod"] * b * beta * (1.0 - 6.0 / (6.0 + math.pi ** 2 * beta ** 2))
    m = p["rho"] * a * b * p["tread_height"]

    def r_of(s):
        return math.hypot((1.0 + s) * tan_a, s)

    def q_of(s):
        return min(1.0, p["c_brush"] * b * a * a * r_of(s) / (6.0 * p["mu_m"] * p["load_n"]))

    def fx(s):
        if s == 0.0:
            return 0.0
        q = q_of(s)
        return 0.5 * p["c_brush"] * b * s * a * a * (1 - q) ** 2 + p["mu_s"] * p["load_n"] * q * q * (3 - 2 * q) * s / r_of(s)

    s = 0.0
    if wheel == "driving":
        v = p["speed_kmh"]
        f_drive = (p["n_wheels"] * (p["f0"] + p["f1"] * v) * p["load_n"] + p["c_d"] * p["area"] * v * v / 21.15) / p["n_driven"]
        lo, hi = 0.0, 1e-3
        while fx(hi) < f_drive:
            hi *= 4.0
            if hi > 1e3:
                return None
        for _ in range(200):  # bisection to full precision
            mid = 0.5 * (lo + hi)
            if fx(mid) < f_drive:
                lo = mid
            else:
                hi = mid
        s = 0.5 * (lo + hi)
    q = q_of(s)
    share = q * (3 - 2 * q) * (1 + s) * tan_a / r_of(s)
    f_m = p["mu_m"] * p["load_n"] * share
    f_s = p["mu_s"] * p["load_n"] * share
    speed = p["speed_kmh"] / 3.6
    u = speed * math.sin(math.radians(p["toe_deg"]))
    g0 = f_s + (f_m - f_s) * math.exp(-((u / p["v_s"]) ** p["phi"]))
    z0 = -g0 / k_s
    return dict(sigma0=k_s, k_s=k_s, m=m, c_s=p["c_s"], sigma1=p["sigma1"], f_m=f_m, f_s=f_s,
                v_s=p["v_s"], phi=p["phi"], u=u, z0=z0, y0=-z0)


def rhs(t, x, c):
    """Eq. 21 (paper variant), scalar Python."""
    z, y, v = x
    w = v - c["u"]
    wt = abs(w)
    g = c["f_s"] + (c["f_m"] - c["f_s"]) * math.exp(-((wt / c["v_s"]) ** c["phi"]))
    dz = w - c["sigma0"] * wt * z / g
    dv = -(c["c_s"] * v + c["k_s"] * y + c["sigma0"] * z + c["sigma1"] * dz) / c["m"]
    return [dz, v, dv]


# The classification rule both peers use: a 3 s trajectory from the equilibrium with y disturbed by
# 1e-7 m (small enough to start below every limit cycle, so a growing amplitude means an unstable
# equilibrium; MODEL.md#step-9-attractor's 1e-5 m starts above the small cycles near a Hopf point
# and makes them look like decay); compare the velocity amplitude (half peak-to-peak) over
# [T-0.5, T] with that over [T-1.5, T-1]. A limit cycle keeps (or grows) its amplitude; a stable equilibrium lets it decay
# by e^(Re lambda) per second, so the ratio separates |Re lambda| > 0.02 1/s.
HORIZON_S = 3.0
DISTURBANCE_M = 1e-7
RATIO = 0.98
FLOOR_MPS = 1e-5


def verdict(amp_early, amp_late):
    return "limit_cycle" if amp_late > FLOOR_MPS and amp_late >= RATIO * amp_early else "stable"
