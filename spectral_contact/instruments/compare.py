"""Measured MEMS profiles against the models (the paper's section "Discussion").

Given measured sensor stresses S_zz(x), S_xz(x) on a uniform grid (x in the file's frame; the
sensor-to-apex offset is unknown):

1. Integral estimates (the paper's): P_L = Int S_zz dx, mu_d = Int S_xz dx / Int S_zz dx
   (trapezoid rule over the file's window).
2. Both models (exact, Goodman) solved at (P_L, mu_d) and seen through the sensor
   (``sensor.sensor_view``).
3. Offset: the x of the file at which the model's apex sits, by least squares on both
   components together, J(o) = sum (E_zz - C_zz(x - o))^2 / sum E_zz^2 + (same for xz); a scan
   at the data step then a bounded Brent refinement.  Fitted per model.
4. chi = sqrt(sum (E - C)^2 / sum E^2) per component and model (the paper's measure).
5. Direct fit: P_L, mu_d and the offset by nonlinear least squares (same objective, solves on
   the grid of the first solve so the objective is smooth in the parameters), from the
   integral estimates; ``fit_model`` adds 1-sigma uncertainties and an AIC, for each model.

Model curves outside the solver's periodic domain are taken as 0 (the domain extends several
film thicknesses beyond the contact, where the base stresses have decayed below the tolerance).
"""
from __future__ import annotations

import logging
import math

import numpy as np

from ..errors import InputError

__all__ = ["integral_estimates", "chi", "fit_offset", "compare_models", "fit_load_mu",
           "fit_model", "FIT_KEYS", "model_view"]

_log = logging.getLogger(__name__)  # progress (INFO): models solved, fit solves


def integral_estimates(x_m, S_zz_Pa, S_xz_Pa):
    """(P_L [N/m], mu_d) = (Int S_zz dx, Int S_xz dx / Int S_zz dx) by the trapezoid rule."""
    P = float(np.trapezoid(S_zz_Pa, x_m))
    Q = float(np.trapezoid(S_xz_Pa, x_m))
    if not (P > 0 and math.isfinite(P)):
        raise InputError(f"the integral of S_zz over the profile is {P:g} N/m; it must be > 0 "
                         f"(S_zz is positive in compression)")
    return P, Q / P


def chi(E, C) -> float:
    """sqrt(sum (E - C)^2 / sum E^2)."""
    E = np.asarray(E, dtype=float)
    den = float(np.sum(E * E))
    return float(np.sqrt(np.sum((E - np.asarray(C)) ** 2) / den)) if den > 0 else float("inf")


def model_view(result, apparatus=None):
    """(x_m, S_zz_Pa, S_xz_Pa) of a solved model through the sensor, apex frame."""
    from .sensor import sensor_view

    v = sensor_view(result, apparatus=apparatus)
    return np.asarray(result.x_m, dtype=float), v["S_zz_Pa"], v["S_xz_Pa"]


def _shifted(xm, C, x, offset):
    return np.interp(x - offset, xm, C, left=0.0, right=0.0)


def _objective(x, Ezz, Exz, xm, Czz, Cxz, offset):
    nz, nx = float(np.sum(Ezz**2)), float(np.sum(Exz**2))
    rz = Ezz - _shifted(xm, Czz, x, offset)
    rx = Exz - _shifted(xm, Cxz, x, offset)
    return float(np.sum(rz**2) / nz + (np.sum(rx**2) / nx if nx > 0 else 0.0))


def fit_offset(x, Ezz, Exz, xm, Czz, Cxz) -> float:
    """Least-squares offset o (model apex at x = o in the file's frame)."""
    from scipy.optimize import minimize_scalar

    dx = float(x[1] - x[0])
    span_m = float(xm[-1] - xm[0])
    # apex positions that keep some overlap between the model's support and the data
    lo = float(x[0] - 0.5 * span_m)
    hi = float(x[-1] + 0.5 * span_m)
    step = max(dx, (hi - lo) / 4000.0)
    grid = np.arange(lo, hi + step, step)
    J = np.array([_objective(x, Ezz, Exz, xm, Czz, Cxz, o) for o in grid])
    i = int(np.argmin(J))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    res = minimize_scalar(lambda o: _objective(x, Ezz, Exz, xm, Czz, Cxz, o), bounds=(a, b),
                          method="bounded", options={"xatol": 1e-4 * dx})
    return float(res.x) if res.fun <= J[i] else float(grid[i])


def compare_models(x_m, S_zz_Pa, S_xz_Pa, scene, tol: float = 1e-4, apparatus=None,
                   models=("exact", "goodman")) -> dict:
    """Solve each model at ``scene`` and compare with the measured profiles.

    Returns {model: {"result", "x_m", "S_zz_Pa", "S_xz_Pa", "offset_m", "chi_zz", "chi_xz"}}.
    """
    from ..api import solve

    out = {}
    for model in models:
        _log.info("compare: solving the %s model (P_L = %.4g N/m, mu_d = %.4g)", model,
                  scene.load, scene.mu)
        r = solve(scene, model=model, tol=tol)
        xm, czz, cxz = model_view(r, apparatus)
        o = fit_offset(x_m, S_zz_Pa, S_xz_Pa, xm, czz, cxz)
        out[model] = {"result": r, "x_m": xm, "S_zz_Pa": czz, "S_xz_Pa": cxz, "offset_m": o,
                      "chi_zz": chi(S_zz_Pa, _shifted(xm, czz, x_m, o)),
                      "chi_xz": chi(S_xz_Pa, _shifted(xm, cxz, x_m, o))}
    return out


def fit_load_mu(x_m, S_zz_Pa, S_xz_Pa, scene, offset0: float, model: str = "exact",
                tol: float = 1e-4, apparatus=None, max_solves: int = 80,
                _keep_jacobian: bool = False, fit_poisson: bool = False,
                fit_interface: bool = False) -> dict:
    """Least-squares fit of (P_L, mu_d, offset) of ``model`` to the measured profiles, from
    ``scene`` (its load and mu are the starting point) and ``offset0``.

    Returns {"load_N_per_m", "mu", "offset_m", "chi_zz", "chi_xz", "solves", "x_m",
    "S_zz_Pa", "S_xz_Pa"} (the last three: the fitted model curves, apex frame).
    """
    from scipy.optimize import least_squares

    from ..api import solve

    x = np.asarray(x_m, dtype=float)
    Ezz, Exz = np.asarray(S_zz_Pa, float), np.asarray(S_xz_Pa, float)
    nz = math.sqrt(float(np.sum(Ezz**2)))
    nx = math.sqrt(float(np.sum(Exz**2))) or 1.0
    first = solve(scene, model=model, tol=tol)
    N, L = first.grid_points, first.domain_length * scene.length_unit
    cache = {}
    P0, mu0 = scene.load, scene.mu
    names = (("poisson",) if fit_poisson else ()) + (("interface_compliance",) if fit_interface else ())
    c_unit = scene.displacement_unit / scene.stress_unit  # m/Pa per unit of c

    def view(P, mu, *extra):
        key = (round(P, 12), round(mu, 12)) + tuple(round(e, 12) for e in extra)
        if key not in cache:
            if len(cache) >= max_solves:
                raise InputError(f"fit of P_L and mu did not settle within {max_solves} solves")
            _log.info("fit of P_L, mu_d: solve %d (P_L = %.5g N/m, mu_d = %.5g, grid %d points)",
                      len(cache) + 2, P, mu, N)
            changes = dict(zip(names, extra))
            if "interface_compliance" in changes:  # fitted as c, the core's units
                changes["interface_compliance"] = max(changes["interface_compliance"], 0.0) * c_unit
            r = solve(scene.with_(load=P, mu=mu, **changes), model=model, tol=tol, grid_points=N,
                      domain_length=L)
            cache[key] = model_view(r, apparatus)
        return cache[key]

    def residuals(p):
        P, mu, o = P0 * math.exp(p[0]), p[1], p[2]
        xm, czz, cxz = view(P, mu, *p[3:])
        return np.concatenate([(Ezz - _shifted(xm, czz, x, o)) / nz,
                               (Exz - _shifted(xm, cxz, x, o)) / nx])

    h = scene.thickness
    x0, x_scale = [0.0, mu0, offset0], [0.05, 0.05, 0.02 * h]
    diff_step, bounds = [1e-4, 1e-4 / max(abs(mu0), 1.0), 1e-5], (-np.inf, np.inf)
    lo, hi = [-np.inf] * 3, [np.inf] * 3
    if fit_poisson:  # nu in [0, 0.5], from the scene's (0.5 started just inside)
        x0.append(min(scene.poisson, 0.49))
        x_scale.append(0.01)
        diff_step.append(1e-3)
        lo.append(0.0)
        hi.append(0.5)
    if fit_interface:  # c = C (G h/2R)/(h^2/2R) >= 0, from 0.05
        x0.append(0.05)
        x_scale.append(0.02)
        diff_step.append(1e-3)
        lo.append(0.0)
        hi.append(np.inf)
    if fit_poisson or fit_interface:
        bounds = (lo, hi)
    sol = least_squares(residuals, x0=x0, x_scale=x_scale, diff_step=diff_step, bounds=bounds,
                        method="trf", xtol=1e-8, ftol=1e-10, gtol=1e-10, max_nfev=40)
    P, mu, o = P0 * math.exp(sol.x[0]), float(sol.x[1]), float(sol.x[2])
    xm, czz, cxz = view(P, mu, *sol.x[3:])
    out = {"load_N_per_m": P, "mu": mu, "offset_m": o,
           "chi_zz": chi(Ezz, _shifted(xm, czz, x, o)),
           "chi_xz": chi(Exz, _shifted(xm, cxz, x, o)),
           "solves": len(cache) + 1, "x_m": xm, "S_zz_Pa": czz, "S_xz_Pa": cxz}
    for i, name in enumerate(names):
        if name == "poisson":
            out["poisson"] = float(sol.x[3 + i])
        else:
            out["interface_compliance_m_per_Pa"] = float(sol.x[3 + i]) * c_unit
    if _keep_jacobian:  # for fit_model's covariance: d(residual)/d(ln P, mu, offset)
        out["_jacobian"] = (np.asarray(sol.jac, dtype=float), nz, nx)
    return out


def fit_model(x_m, S_zz_Pa, S_xz_Pa, scene, offset0: float, model: str = "exact",
              tol: float = 1e-4, apparatus=None, max_solves: int = 80,
              fit_poisson: bool = False, fit_interface: bool = False) -> dict:
    """Direct least-squares fit of ``model`` (P_L, mu_d and the sensor-apex offset; with
    ``fit_poisson`` also the film's Poisson ratio, in [0, 0.5]; with ``fit_interface`` a linear
    interface compliance C >= 0) with 1-sigma uncertainties and
    an information criterion.

    The fit is ``fit_load_mu``'s (same objective, each component normalised by its norm).  Then:

    * noise: sigma_c^2 = RSS_c / (n - k/2) per component c (zz, xz), from the residuals at the
      optimum (the k = 3 or 4 parameters shared by the two components);
    * covariance: (J_w^T J_w)^-1, J_w the Jacobian of the model curves with respect to
      (ln P_L, mu_d, offset) weighted by 1/sigma_c (least_squares' finite-difference Jacobian at
      the optimum); load_sigma = P_L sigma(ln P_L);
    * AIC = sum_c n ln(RSS_c / n) + 2 (k + 2) (the parameters and the two noise levels):
      Gaussian noise of unknown level per component; lower is better, differences > 2 matter.

    Returns {"model", "load_N_per_m", "load_sigma", "mu", "mu_sigma", "offset_m",
    "offset_sigma", "chi_zz", "chi_xz", "aic", "sigma_zz_Pa", "sigma_xz_Pa", "solves", "x_m",
    "S_zz_Pa", "S_xz_Pa"} (the last three: the fitted model's curves, apex frame), plus
    "poisson", "poisson_sigma" with ``fit_poisson`` and "interface_compliance_m_per_Pa",
    "interface_compliance_sigma" with ``fit_interface``.
    """
    out = fit_load_mu(x_m, S_zz_Pa, S_xz_Pa, scene, offset0, model=model, tol=tol,
                      apparatus=apparatus, max_solves=max_solves, _keep_jacobian=True,
                      fit_poisson=fit_poisson, fit_interface=fit_interface)
    k = 3 + int(fit_poisson) + int(fit_interface)
    x = np.asarray(x_m, dtype=float)
    Ezz, Exz = np.asarray(S_zz_Pa, float), np.asarray(S_xz_Pa, float)
    n = x.size
    o = out["offset_m"]
    rzz = Ezz - _shifted(out["x_m"], out["S_zz_Pa"], x, o)
    rxz = Exz - _shifted(out["x_m"], out["S_xz_Pa"], x, o)
    rss = {"zz": float(np.sum(rzz**2)), "xz": float(np.sum(rxz**2))}
    dof = max(n - 0.5 * k, 1.0)
    sig = {c: math.sqrt(v / dof) if v > 0 else 1e-300 for c, v in rss.items()}
    jac, nz, nx = out.pop("_jacobian")
    # the residuals of the fit were (E - C)/norm: d(C_c)/dp = -norm_c d(r_c)/dp
    Jw = np.vstack([jac[:n] * (nz / sig["zz"]), jac[n:] * (nx / sig["xz"])])
    try:
        cov = np.linalg.inv(Jw.T @ Jw)
        sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    except np.linalg.LinAlgError:
        sd = np.full(k, np.nan)
    aic = sum(n * math.log(max(v, 1e-300) / n) for v in rss.values()) + 2 * (k + 2)
    out.update({"model": model, "load_sigma": out["load_N_per_m"] * float(sd[0]),
                "mu_sigma": float(sd[1]), "offset_sigma": float(sd[2]), "aic": float(aic),
                "sigma_zz_Pa": sig["zz"], "sigma_xz_Pa": sig["xz"]})
    if fit_poisson:
        out["poisson_sigma"] = float(sd[3])
    if fit_interface:
        out["interface_compliance_sigma"] = float(sd[k - 1]) * (scene.displacement_unit
                                                                 / scene.stress_unit)
    return out


FIT_KEYS = ("load_N_per_m", "load_sigma", "mu", "mu_sigma", "offset_m", "offset_sigma",
            "chi_zz", "chi_xz", "aic")
"""The keys of each model's record in ``compare``'s JSON ``fits``."""
