"""From measured base stresses to the interface: tractions p(x), q(x) with calibrated
uncertainty, and the local friction law (issue 21).  Line records (plane strain).

Data.  Samples at uniform positions x_i (the file's frame; no apex assumed) of

    d_zz = -sigma_zz(x, 0)   (compression > 0)   and   d_xz = sigma_xz(x, 0),

either as they are (``view="base"``: what a finite-element model or an unblurred array gives)
or through the sensor's apparatus functions (``view="sensor"``: d = S, S_zz = G_zz (*) d_zz,
S_xz = G_xz (*) d_xz, ``instruments.sensor``; U files are divided by the gains first).

Forward map (linear).  The surface tractions p(x) = -sigma_zz(x, h) >= 0 and q(x) = sigma_xz(x, h)
are expanded in hat functions on nodes t_j of step dt <= h/8 (the film does not resolve much
below h/few) covering the record plus a margin of ``MARGIN_H`` h on each side, so that the
tractions near and beyond the ends of the window are modelled (the base field decays only as
exp(-0.74 |x|/h): the tails that leave the window are not wrapped back, they are simply not
observed).  The response of one hat function at the base is computed through the film's public
base-stress transfer (``physics.film.Film.base_transfer``, physics.md A, B, C) times the
apparatus symbols, on a fine periodic grid (step <= h/128, period the record's span plus 40 h,
images < 1e-9), and interpolated at the lags x_i - t_j: the matrix M (2n x 2m) with
d = M (p, q) + noise.

Prior and hyperparameters.  p and q are independent zero-mean Gaussian processes on the nodes,
Matern-5/2 covariance s^2 (1 + r + r^2/3) exp(-r), r = sqrt(5)|t - t'|/l, each with its own
amplitude s and length l.  The noise is white, Gaussian, with one standard deviation per
component (sigma_zz, sigma_xz).  The six hyperparameters (l_p, l_q, s_p, s_q, sigma_zz, sigma_xz)
maximise the evidence (the marginal likelihood of the data, Gaussian, in closed form); none is
set by hand.  ``summary()`` reports them and the log-evidence.

Posterior.  Gaussian: mean and covariance of the nodal tractions, given the hyperparameters
(their own uncertainty is not propagated: empirical Bayes).  From it:

* P = Int p dx, Q = Int q dx (the hat functions integrate to dt) and Q/P, with sigmas from the
  covariance (Q/P by the first-order (delta) rule with the P-Q correlation);
* pointwise sd of p, q; mu_local = q/p with its delta-rule sd where p is *resolved*: the
  posterior mean exceeds 3 sd (``RESOLVED_Z``);
* the contact interval: on each of 400 posterior draws, the outermost crossings around the peak
  of the level 2 * (median sd of p) (the level below which p is not distinguished from 0);
  reported as the mean and sd of the two edges over the draws;
* the resolution length: the equivalent width (Int R)^2 / Int R^2 of the row of the resolution
  matrix R = I - C K^-1 (how the posterior mean averages the truth) at the peak of p.

Options.  ``positive=True``: p >= 0 at every node; the mean is then the constrained maximum of
the posterior (a bound-constrained quadratic programme) and the covariance that of the free
nodes given the nodes at the bound (which get sd 0): a Laplace approximation on the active face,
which understates the uncertainty of the nodes next to the bound.  ``support=(a, b)`` [m]: the
contact is known to be [a, b]; p = q = 0 outside; the nodes are placed on [a, b] with half-hat
end functions, so that steps of q at the edges (a shear strength) are representable.

Laws.  ``laws`` fits q = mu p (Amontons), q = tau0 + alpha p and q = k p^n to the resolved
(p, q) pairs by generalised least squares with the full posterior covariance of the pairs
(errors in both variables by the effective-variance rule, iterated), gives the parameters with
1-sigma uncertainties, chi^2, its degrees of freedom and p-value, and AIC = chi^2 + 2 k.

Units: lengths in h in the core, stresses in Pa scaled by the data's peak; SI at the edge.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..physics.film import Film
from .inverse_evidence import (  # noqa: F401  (re-exported)
    ENVELOPE_EDGE_MIN_H,
    KERNEL_NU,
    _contact_interval,
    _Evidence,
    _optimise,
    _positive,
)
from .inverse_forward import (  # noqa: F401  (re-exported)
    MARGIN_H,
    NODE_STEP_H,
    LineForward,
    _resolution_length,
    _symbols,
    base_from_tractions,
)
from .inverse_laws import fit_laws
from .inverse_result import LineInversion

__all__ = ["invert", "read_record", "invert_line", "LineInversion", "LineForward", "fit_laws",
           "base_from_tractions", "INVERT_JSON_KEYS", "RESOLVED_Z", "MARGIN_H"]

RESOLVED_Z = 3.0
"""p is resolved where its posterior mean exceeds RESOLVED_Z posterior sd."""
LAW_EDGE_GUARD = 2.0
"""The law fits use resolved nodes at least this many resolution lengths inside the contact
interval's edges."""

INVERT_JSON_KEYS = ("load_N_per_m", "load_sigma_N_per_m", "tangential_load_N_per_m",
                    "tangential_load_sigma_N_per_m", "Q_over_P", "Q_over_P_sigma",
                    "contact_interval_m", "contact_interval_sigma_m", "resolution_length_m",
                    "regularisation", "log_evidence", "noise_sd_zz_Pa", "noise_sd_xz_Pa",
                    "view", "points", "nodes", "positive", "support_m", "laws")


# --- the inversion ----------------------------------------------------------------------------


def _check_record(x_m, zz, xz):
    x = np.asarray(x_m, dtype=float)
    zz = np.asarray(zz, dtype=float)
    xz = np.asarray(xz, dtype=float)
    if x.ndim != 1 or x.shape != zz.shape or x.shape != xz.shape:
        raise InputError("x_m and the two stress profiles must be 1D arrays of one length")
    if x.size < 8:
        raise InputError(f"only {x.size} samples; the inversion needs at least 8")
    for a, nm in ((x, "x_m"), (zz, "zz"), (xz, "xz")):
        if not np.all(np.isfinite(a)):
            raise InputError(f"{nm} has non-finite values")
    d = np.diff(x)
    step = (x[-1] - x[0]) / (x.size - 1)
    if np.any(d <= 0) or np.max(np.abs(d - step)) > 1e-3 * step:
        raise InputError("x_m must be strictly increasing and uniformly spaced (within 0.1 %)")
    if not np.any(zz) and not np.any(xz):
        raise InputError("the record is zero everywhere: nothing to invert")
    return x, zz, xz


def invert_line(x_m, zz_Pa, xz_Pa, *, thickness: float = 0.002, poisson: float = 0.5,
                view: str = "base", apparatus=None, positive: bool = False, support=None,
                draws: int = 400, seed: int = 0) -> LineInversion:
    """Interface tractions from a line record (see the module docstring).

    x_m : uniform increasing positions [m]; zz_Pa : -sigma_zz(x, 0) (compression > 0) or S_zz;
    xz_Pa : sigma_xz(x, 0) or S_xz; view : "base" (no apparatus) or "sensor" (apparatus: None
    for the paper's G_zz, G_xz, or a pair of ``ApparatusFunction``); thickness [m], poisson : the
    film; positive : p >= 0; support : (a, b) [m] known contact; draws, seed : posterior draws
    for the contact interval's uncertainty.
    """
    from ..physics.scene import check_poisson, check_positive

    h = check_positive("thickness", thickness, "m")
    nu = check_poisson(poisson)
    x, dz, dxz = _check_record(x_m, zz_Pa, xz_Pa)
    if view not in ("base", "sensor"):
        raise InputError(f"view must be 'base' or 'sensor'; got {view!r}")
    if view == "sensor":
        from .sensor import _resolve

        apparatus = _resolve(apparatus)
    elif apparatus is not None:
        raise InputError("an apparatus applies to sensor records (view='sensor'), not to base "
                         "stresses")
    sup_h = None
    if support is not None:
        a, b = (float(s) for s in support)
        if not (math.isfinite(a) and math.isfinite(b) and b > a):
            raise InputError(f"support must be an interval (a, b) with b > a [m]; got {support}")
        sup_h = (a / h, b / h)
    scale = max(float(np.max(np.abs(dz))), float(np.max(np.abs(dxz))))
    xh = x / h
    film = Film(1.0, nu)
    symbols = _symbols(apparatus, h)
    fwd = LineForward.build(xh, film, symbols, support=sup_h)
    m = fwd.nodes.size
    zs, xs = dz / scale, dxz / scale
    ev = _Evidence(fwd, zs, xs, envelope=sup_h is None)
    theta, logev, free = _optimise(ev, zs, xs, fwd.nodes[1] - fwd.nodes[0])
    _, (mean, cov, H) = ev.evaluate(theta, full=True)
    active = np.zeros(2 * m, bool)
    if positive:
        mean, cov, active = _positive(mean, cov, m)
    lp, lq, sp, sq, s_out, nz, nx = np.exp(theta[:7])
    # SI: stresses * scale; lengths * h
    w = fwd.weights
    p, q = mean[:m] * scale, mean[m:] * scale
    cov_si = cov * scale**2
    sd = np.sqrt(np.maximum(np.diag(cov_si), 0.0))
    sp_, sq_ = sd[:m], sd[m:]
    wv = np.concatenate([w, np.zeros(m)]) * h
    wq = np.concatenate([np.zeros(m), w]) * h
    P, Q = float(wv @ np.concatenate([p, q])), float(wq @ np.concatenate([p, q]))
    vP, vQ, cPQ = float(wv @ cov_si @ wv), float(wq @ cov_si @ wq), float(wv @ cov_si @ wq)
    ratio = Q / P if P != 0 else float("nan")
    vR = (vQ - 2 * ratio * cPQ + ratio**2 * vP) / P**2 if P != 0 else float("nan")
    # local mu
    resolved = p > RESOLVED_Z * sp_
    cpq_d = np.diag(cov_si[:m, m:])
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(resolved, q / p, np.nan)
        mu_sd = np.where(resolved, np.sqrt(np.maximum(sq_**2 - 2 * mu * cpq_d + mu**2 * sp_**2,
                                                      0.0)) / np.abs(p), np.nan)
    # contact interval from posterior draws
    interval, interval_sd = _contact_interval(fwd.nodes * h, p, cov_si[:m, :m], sp_, draws, seed)
    # resolution length: equivalent width of the resolution-matrix row at the peak of p
    res_len = _resolution_length(fwd, symbols, film, min(nz, nx) * scale, x.size,
                                 float(np.max(p)), h)
    # laws on resolved pairs away from the contact edges (there the smoothing mixes in the
    # zeros outside and the steps of a shear strength: LAW_EDGE_GUARD resolution lengths)
    xn = fwd.nodes * h
    inside = np.ones(m, bool)
    if np.all(np.isfinite(interval)):
        g = LAW_EDGE_GUARD * res_len if math.isfinite(res_len) else 0.0
        inside = (xn > interval[0] + g) & (xn < interval[1] - g)
    idx = np.nonzero(resolved & inside)[0]
    laws = fit_laws(p[idx], q[idx], cov_si[np.ix_(idx, idx)], cov_si[np.ix_(m + idx, m + idx)],
                    cov_si[np.ix_(idx, m + idx)])
    fz, fx = fwd.apply(mean[:m], mean[m:])
    rec = {"load_N_per_m": P, "load_sigma_N_per_m": math.sqrt(max(vP, 0.0)),
           "tangential_load_N_per_m": Q, "tangential_load_sigma_N_per_m": math.sqrt(max(vQ, 0.0)),
           "Q_over_P": ratio, "Q_over_P_sigma": math.sqrt(max(vR, 0.0)),
           "contact_interval_m": interval, "contact_interval_sigma_m": interval_sd,
           "resolution_length_m": res_len,
           "regularisation": {"prior": f"p, q: Matern-{2 * KERNEL_NU:g}/2 Gaussian process inside an "
                                       f"envelope + exponential-correlation process at its "
                                       f"edges, zero mean",
                              "rough_amplitude_p_Pa": float(math.exp(theta[10]) * scale),
                              "rough_amplitude_q_Pa": float(math.exp(theta[11]) * scale),
                              "rough_length_m": float(math.exp(theta[12]) * h),
                              "length_p_m": float(lp * h), "length_q_m": float(lq * h),
                              "amplitude_p_Pa": float(sp * scale),
                              "amplitude_q_Pa": float(sq * scale),
                              "amplitude_outside_Pa": float(s_out * scale) if free[4] else None,
                              "window_m": ([float((theta[7] - math.exp(theta[8])) * h),
                                            float((theta[7] + math.exp(theta[8])) * h)]
                                           if free[7] else None),
                              "window_edge_m": float(math.exp(theta[9]) * h) if free[9] else None,
                              "chosen_by": "maximum evidence (marginal likelihood)"},
           "log_evidence": float(logev - 2 * x.size * math.log(scale)),
           "noise_sd_zz_Pa": float(nz * scale), "noise_sd_xz_Pa": float(nx * scale),
           "view": view, "points": int(x.size), "nodes": int(m), "positive": bool(positive),
           "support_m": None if support is None else [float(s) for s in support],
           "resolved_rule": f"mu_local where p > {RESOLVED_Z:g} sd(p)",
           "thickness_m": h, "poisson": nu, "laws": laws}
    data = {"x_m": x, "zz": dz, "xz": dxz, "zz_fit": fz * scale, "xz_fit": fx * scale}
    return LineInversion(fwd.nodes * h, p, sp_, q, sq_, mu, mu_sd, rec, data, cov_si)


# --- entry: files, results, arrays ------------------------------------------------------------

_VIEWS = {"S": ("x_m", "S_zz_Pa", "S_xz_Pa"), "U": ("x_m", "U_zz_mV", "U_xz_mV"),
          "base": ("x_m", "base_sigma_zz_Pa", "base_sigma_xz_Pa")}


def read_record(path, A_zz_mV_per_bar: float | None = None, A_xz_mV_per_bar: float | None = None):
    """A line record from a CSV: ``x_m,S_zz_Pa,S_xz_Pa`` (the MEMS view, S_zz > 0 in
    compression), ``x_m,U_zz_mV,U_xz_mV`` (outputs; divided by the gains A [mV/bar], paper's by
    default) or ``x_m,base_sigma_zz_Pa,base_sigma_xz_Pa`` (base stresses, the package's names
    and signs: sigma_zz < 0 in compression).  One view per file; x uniform and increasing, at
    least 8 rows.  Returns (x_m, d_zz, d_xz, view) with d_zz > 0 in compression and view
    "sensor" or "base".  Raises InputError (one line naming the file)."""
    from ..units import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR, PA_PER_BAR
    from .measured_io import check_uniform, read_table

    name = str(path)
    what = " or ".join(",".join(v) for v in _VIEWS.values())
    cols = read_table(path, required=("x_m",), any_of=tuple(_VIEWS.values()), what=what)
    present = [k for k, v in _VIEWS.items() if any(c in cols for c in v[1:])]
    if len(present) > 1:
        names = ", ".join(c for k in present for c in _VIEWS[k][1:] if c in cols)
        raise InputError(f"{name}: mixes views ({names}); give one of {what}")
    kind = present[0]
    x = cols["x_m"]
    check_uniform(x, name, "x_m")
    zz, xz = cols[_VIEWS[kind][1]], cols[_VIEWS[kind][2]]
    if kind == "base":
        return x, -zz, xz, "base"
    if kind == "U":
        a_zz = A_ZZ_MV_PER_BAR if A_zz_mV_per_bar is None else A_zz_mV_per_bar
        a_xz = A_XZ_MV_PER_BAR if A_xz_mV_per_bar is None else A_xz_mV_per_bar
        return x, zz * PA_PER_BAR / a_zz, xz * PA_PER_BAR / a_xz, "sensor"
    return x, zz, xz, "sensor"


def invert(source=None, *, x_m=None, zz_Pa=None, xz_Pa=None, view: str | None = None,
           thickness: float | None = None, poisson: float | None = None, apparatus=None,
           A_zz_mV_per_bar: float | None = None, A_xz_mV_per_bar: float | None = None,
           positive: bool = False, support=None) -> LineInversion:
    """Interface tractions p(x), q(x) with uncertainties from a line record of base stresses.

        >>> from spectral_contact import invert, solve
        >>> inv = invert(solve(load=200, mu=1))          # its base stresses, noise-free
        >>> inv.summary()["load_N_per_m"], inv.laws["best"]
        >>> inv = invert("record.csv", thickness=0.002)  # a measured file (see ``read_record``)
        >>> inv.plot()

    source : a CSV path (``read_record``; S/U files are read through the apparatus), a
        ``ContactResult`` (its base stresses on its grid, view "base"; thickness and poisson
        from its scene), or None with ``x_m, zz_Pa, xz_Pa`` arrays (zz > 0 in compression:
        -sigma_zz(x, 0) or S_zz) and ``view`` ("base" default, or "sensor").
    thickness [m] (default 0.002 or the result's), poisson (0.5 or the result's): the film.
    apparatus : sensor views only: None (the paper's G_zz, G_xz) or a pair of
        ``ApparatusFunction`` (``instruments.apparatus.load_apparatus_csv``).
    positive, support : see ``invert_line``.
    """
    if source is not None and hasattr(source, "base_sigma_zz_Pa"):
        r = source
        x = np.asarray(r.x_m, float)
        zz, xz, kind = -np.asarray(r.base_sigma_zz_Pa), np.asarray(r.base_sigma_xz_Pa), "base"
        thickness = r.scene.thickness if thickness is None else thickness
        poisson = r.scene.poisson if poisson is None else poisson
    elif source is not None:
        x, zz, xz, kind = read_record(source, A_zz_mV_per_bar, A_xz_mV_per_bar)
        if view is not None and view != kind:
            raise InputError(f"{source}: holds a {kind} record; view={view!r} does not apply")
    else:
        if x_m is None or zz_Pa is None or xz_Pa is None:
            raise InputError("give a source (file or result) or x_m, zz_Pa and xz_Pa")
        x, zz, xz, kind = x_m, zz_Pa, xz_Pa, view or "base"
    return invert_line(x, zz, xz, thickness=0.002 if thickness is None else thickness,
                       poisson=0.5 if poisson is None else poisson, view=kind,
                       apparatus=apparatus, positive=positive, support=support)
