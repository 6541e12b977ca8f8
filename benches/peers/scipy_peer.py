"""Peer (a): SciPy's solve_ivp per point and wheel, a fixed horizon, the tail read (the paper's
method), as a competent SciPy user writes it."""
import numpy as np
from scipy.integrate import solve_ivp

import model


def classify(c, rtol=1e-8):
    return classify_counted(c, rtol)[0]


def classify_counted(c, rtol=1e-8):
    """The class and the RHS evaluations it took."""
    x0 = [c["z0"], c["y0"] + model.DISTURBANCE_M, 0.0]
    atol = [rtol * abs(c["z0"]), rtol * abs(c["y0"]), rtol * c["u"]]
    t_eval = np.concatenate([
        np.arange(model.HORIZON_S - 1.5, model.HORIZON_S - 1.0, 5e-5),
        np.arange(model.HORIZON_S - 0.5, model.HORIZON_S, 5e-5),
    ])
    sol = solve_ivp(model.rhs, (0.0, model.HORIZON_S), x0, method="DOP853", rtol=rtol, atol=atol,
                    t_eval=t_eval, args=(c,))
    if not sol.success:
        return "failed", sol.nfev
    v = sol.y[2]
    early = v[sol.t < model.HORIZON_S - 0.9]
    late = v[sol.t >= model.HORIZON_S - 0.5]
    amp = lambda s: 0.5 * (s.max() - s.min())
    return model.verdict(amp(early), amp(late)), sol.nfev


def run(points):
    """points: list of parameter dicts -> list of (index, wheel, class)."""
    return run_counted(points)[0]


def run_counted(points):
    """Like `run`, and the RHS evaluations of each integrated wheel."""
    out, evals = [], []
    for i, p in enumerate(points):
        for wheel in ("follower", "driving"):
            c = model.statics(p, wheel)
            if c is None:
                out.append((i, wheel, "no_traction"))
            else:
                cls, n = classify_counted(c)
                out.append((i, wheel, cls))
                evals.append(n)
    return out, evals
