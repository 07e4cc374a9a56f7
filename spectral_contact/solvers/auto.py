"""``--model auto``: the cheapest model whose error at the scene is below the tolerance.

Cost order: hertz (closed form) < goodman (one frictionless solve) < exact.  The error of a model
is read from a fitted bound, ``model_error_bound(model, s, mu)`` with s = a_Hertz/h =
sqrt(P/2pi) (the Hertz half-space half-width in film thicknesses) and mu the friction
coefficient.  The error it bounds is the largest of the relative differences from the exact model
of: the half-width a, the contact centre (relative to a), the indentation, the peak pressure, and
the base-stress profiles (max |diff| / max |exact| of sigma_zz(x, 0) and of sigma_xz(x, 0)), i.e.
everything ``tol`` promises plus the base profiles.

The bound (``studies/model_map.py`` fits and validates it)::

    goodman:  e_G = K_G * mu_e * C_G * s_e**P_G
    hertz:    e_H = K_H * (C_H * s_e**P_H + mu_e * C_G * s_e**P_G)

with s_e = max(s, S_MIN) and mu_e = max(|mu|, MU_MIN) (0 when mu = 0).  Why this shape: with
mu = 0 Goodman's model *is* the exact model (error 0); the friction coupling shifts the contact
by x_c/a = mu s/pi (measured 0.318 mu s for s <~ 0.1: the film tilts under the load) and changes
the base profiles by ~0.5 mu s^2, linearly in mu; the Hertz pressure misses the film's stiffening
(a shrinks by ~0.5 s^2) and, like
Goodman, the friction coupling.  Clamping s and |mu| up to the smallest sampled values keeps the
bound conservative below the map (the errors grow with both); above the map (s > S_MAX or
|mu| > MU_MAX) auto does not extrapolate: it picks the exact model.  When in doubt, exact.

Provenance of the constants: PROVENANCE below (the full ``python -m studies.model_map`` run they
were fitted on, and what its validation found).
"""
from __future__ import annotations

import math

__all__ = ["model_error_bound", "choose_model", "COST_ORDER",
           "BOUND", "S_MIN", "S_MAX", "MU_MIN", "MU_MAX", "PROVENANCE"]

COST_ORDER = ("hertz", "goodman", "exact")

# --- the fitted bound (studies/model_map.py, full run; see PROVENANCE) --------------------------
BOUND = {
    "C_H": 0.3664, "P_H": 1.869, "K_H": 1.612,
    "C_G": 0.2798, "P_G": 0.9418, "K_G": 2.276,
}
S_MIN, S_MAX = 0.05, 10.0   # validated range of s = a_Hertz / h
MU_MIN, MU_MAX = 0.05, 5.0  # validated range of |mu| (mu = 0 exactly: Goodman = exact)
PROVENANCE = (
    "python -m studies.model_map (full run, 2026-11-22, on commit 0eece8a plus this change): "
    "22 values of a_Hertz/h log-spaced in [0.05, 10] x 16 values of mu_d in [0, 5] (352 scenes); "
    "reference: exact model, fft method, tol 1e-5.  Fitted on the 11 even-index a/h rows (log "
    "least squares over errors in (1e-4, 0.3)): hertz at mu = 0 -> C_H, P_H; goodman error/mu "
    "-> C_G, P_G; K = 1.5 x the largest measured/fitted ratio on those rows (1.075 hertz, "
    "1.517 goodman).  Validated on the 11 odd rows: measured/bound <= 0.66 (hertz and goodman), "
    "no point where the bound is < 0.1 and below the measured error; on the whole map auto's "
    "pick never has a measured error >= tol (tol 1e-3, 1e-2, 5e-2)."
)


def _clamped(s: float, mu: float):
    s_e = max(float(s), S_MIN)
    mu_e = 0.0 if mu == 0 else max(abs(float(mu)), MU_MIN)
    return s_e, mu_e


def model_error_bound(model: str, s: float, mu: float, coeffs: dict | None = None) -> float:
    """Bound on the relative error of ``model`` against the exact model at s = a_Hertz/h and mu.

    0 for "exact"; inf outside the validated map (s > S_MAX or |mu| > MU_MAX).  ``coeffs``
    overrides BOUND (used by the study to evaluate a fresh fit)."""
    if model == "exact":
        return 0.0
    c = BOUND if coeffs is None else coeffs
    if not (math.isfinite(s) and math.isfinite(mu)) or s > S_MAX or abs(mu) > MU_MAX:
        return math.inf
    s_e, mu_e = _clamped(s, mu)
    friction = mu_e * c["C_G"] * s_e ** c["P_G"]
    if model == "goodman":
        return c["K_G"] * friction
    if model == "hertz":
        return c["K_H"] * (c["C_H"] * s_e ** c["P_H"] + friction)
    raise ValueError(f"unknown model {model!r}")


def choose_model(s: float, mu: float, tol: float):
    """(model, reason, bounds): the cheapest model whose bound is below tol."""
    bounds = {m: model_error_bound(m, s, mu) for m in COST_ORDER}
    where = f"a/h_hertz = {s:.3g}, |mu| = {abs(mu):.3g}"
    if s > S_MAX or abs(mu) > MU_MAX:
        return ("exact", f"exact: {where} outside the validated map (a/h_hertz <= {S_MAX:g}, "
                         f"|mu| <= {MU_MAX:g}); no extrapolation", bounds)
    for m in COST_ORDER[:-1]:
        if bounds[m] < tol:
            return (m, f"{m}: its error bound {bounds[m]:.2g} < tol {tol:.2g} at {where} "
                       f"(fitted bound, solvers/auto.py; validated by studies/model_map)", bounds)
    return ("exact", f"exact: error bounds hertz {bounds['hertz']:.2g}, goodman "
                     f"{bounds['goodman']:.2g} >= tol {tol:.2g} at {where}", bounds)
