"""Friction laws fitted to the local (p, q) pairs of the line inverse (issue 21)."""
from __future__ import annotations

import numpy as np

__all__ = ["fit_laws", "law_lines", "best_line", "law_curves", "REJECT_P"]

REJECT_P = 1e-3
"""A law whose chi^2 p-value is below this is rejected by the pairs' uncertainties."""

_LAWS = {
    "amontons": (("mu",), lambda p, th: th[0] * p, lambda p, th: np.full_like(p, th[0])),
    "linear": (("tau0_Pa", "alpha"), lambda p, th: th[0] + th[1] * p,
               lambda p, th: np.full_like(p, th[1])),
    "power": (("k_Pa", "n"), lambda p, th: th[0] * (p / _PREF[0]) ** th[1],
              lambda p, th: th[0] * th[1] * (p / _PREF[0]) ** (th[1] - 1.0) / _PREF[0]),
}
_PREF = [1.0]


def _pinv_sqrt(C, rcond=1e-10):
    w, V = np.linalg.eigh(0.5 * (C + C.T))
    keep = w > rcond * w.max()
    return (V[:, keep] / np.sqrt(w[keep])).T, int(keep.sum())


def fit_laws(p, q, Cpp, Cqq, Cpq) -> dict:
    """Fit Amontons, q = tau0 + alpha p and q = k (p/p_ref)^n (p_ref = median p) to pairs (p_i,
    q_i) [Pa] with joint Gaussian errors (covariance blocks Cpp, Cqq, Cpq [Pa^2]).

    Generalised least squares with the effective covariance Cov(r) = Cqq - Cqp J - J Cpq +
    J Cpp J of the residual r = q - f(p) (J = diag f'(p)), re-evaluated three times; the
    pseudo-inverse drops the directions the covariance does not constrain (eigenvalues below
    1e-10 of the largest) and the degrees of freedom are its rank minus the parameters.
    Returns {law: {params..., params_sigma..., chi2, dof, p_value, aic}} and "best" (lowest AIC).
    """
    from scipy.optimize import least_squares
    from scipy.special import chdtrc  # chi^2 survival function (scipy.stats.chi2.sf's own;
    # importing scipy.stats costs 0.3-0.8 s, more than a line inversion)

    p = np.asarray(p, float)
    q = np.asarray(q, float)
    out = {}
    if p.size < 3:
        return {"note": f"only {p.size} resolved nodes: no law fitted"}
    _PREF[0] = float(np.median(p))
    # starting values from ordinary least squares
    A = np.vstack([np.ones_like(p), p]).T
    t0_lin = np.linalg.lstsq(A, q, rcond=None)[0]
    starts = {"amontons": [float(q @ p / (p @ p))], "linear": list(map(float, t0_lin)),
              "power": [float(np.median(q)) or 1.0, 1.0]}
    for law, (names, f, fp) in _LAWS.items():
        th = np.array(starts[law], float)
        ok = True
        for _ in range(3):
            J = fp(p, th)
            C = Cqq - Cpq.T * J[None, :] - J[:, None] * Cpq + J[:, None] * Cpp * J[None, :]
            W, rank = _pinv_sqrt(C)
            try:
                sol = least_squares(lambda t: W @ (q - f(p, t)), th, method="lm")
            except ValueError:
                ok = False
                break
            th = sol.x
        if not ok or not np.all(np.isfinite(th)):
            out[law] = {"note": "fit failed"}
            continue
        r = W @ (q - f(p, th))
        chi2 = float(r @ r)
        k = len(names)
        Jt = sol.jac
        try:
            cov = np.linalg.inv(Jt.T @ Jt)
            sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
        except np.linalg.LinAlgError:
            sd = np.full(k, np.nan)
        dof = max(rank - k, 1)
        rec = {}
        for nm, v, s in zip(names, th, sd):
            rec[nm] = float(v)
            rec[nm + "_sigma"] = float(s)
        if law == "power":
            rec["p_ref_Pa"] = _PREF[0]
        rec.update({"chi2": chi2, "dof": dof, "p_value": float(chdtrc(dof, chi2)),
                    "aic": chi2 + 2 * k})
        out[law] = rec
    fitted = {k: v for k, v in out.items() if "aic" in v}
    out["best"] = min(fitted, key=lambda k: fitted[k]["aic"]) if fitted else None
    if fitted and all(v["p_value"] < REJECT_P for v in fitted.values()):
        # AIC ranks the laws but does not test them: say when none fits (a noise-free record,
        # whose noise floor is below the forward model's own error, or a law outside these)
        out["note"] = (f"every law rejected by chi2 (p < {REJECT_P:g}): the best by AIC is the "
                       f"least bad, not a description of the pairs (noise-free data, or a law "
                       f"outside these three)")
    return out


def law_lines(laws: dict) -> list[str]:
    """One text line per fitted law of ``fit_laws``' record (its parameters with sigmas, chi^2,
    p-value, AIC), for the command line's summaries of line and map inversions."""
    lines = []
    for law in ("amontons", "linear", "power"):
        r = laws.get(law, {})
        if "aic" not in r:
            continue
        pars = ", ".join(f"{k} = {r[k]:.4g} +- {r[k + '_sigma']:.2g}" for k in r
                         if k + "_sigma" in r)
        lines.append(f"  law {law:<9s} {pars}; chi2 {r['chi2']:.1f}/{r['dof']} "
                     f"(p {r['p_value']:.2g}), AIC {r['aic']:.1f}")
    return lines


def best_line(laws: dict) -> str:
    """The summaries' closing line: the best law by AIC, with the record's note when every law
    is rejected, or why none was fitted."""
    note = laws.get("note")
    if laws.get("best"):
        return f"  best law (AIC): {laws['best']}" + (f" ({note})" if note else "")
    return f"  best law (AIC): none ({note or 'no law could be fitted'})"


_CURVES = {"amontons": lambda p, r: r["mu"] * p,
           "linear": lambda p, r: r["tau0_Pa"] + r["alpha"] * p,
           "power": lambda p, r: r["k_Pa"] * (p / r["p_ref_Pa"]) ** r["n"]}


def law_curves(laws: dict, p) -> list:
    """(label, q(p) [Pa]) of every fitted law of ``fit_laws``' record at pressures ``p`` [Pa],
    for the q-against-p panels of the line and map inversions' plots."""
    return [(f"{law} (AIC {laws[law]['aic']:.1f})", f(np.asarray(p, float), laws[law]))
            for law, f in _CURVES.items() if "aic" in laws.get(law, {})]
