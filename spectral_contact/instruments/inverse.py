"""From measured base stresses to the interface: tractions p(x), q(x) with calibrated
uncertainty, and the local friction law (issue 21).  Line records (plane strain).

Data.  Samples at uniform positions x_i (the file's frame; no apex assumed) of

    d_zz = -sigma_zz(x, 0)   (compression > 0)   and   d_xz = sigma_xz(x, 0),

either as they are (``view="base"``: what a finite-element model or an unblurred array gives)
or through the sensor's apparatus functions (``view="sensor"``: d = S, S_zz = G_zz (*) d_zz,
S_xz = G_xz (*) d_xz, ``instruments.sensor``; U files are divided by the gains first).

Forward map (linear).  The surface tractions p(x) = -sigma_zz(x, h) >= 0 and q(x) = sigma_xz(x, h)
are expanded in hat functions on nodes t_j (``inverse_forward.LineForward``).  The response of
one hat function at the base is computed through the film's public base-stress transfer
(``physics.film.Film.base_transfer``, physics.md A, B, C) times the apparatus symbols, on a fine
periodic grid (step <= h/128, period the record's span plus 40 h, images < 1e-9), and
interpolated at the lags x_i - t_j: the matrix M (2n x 2m) with d = M (p, q) + noise.  The
base field decays only as exp(-0.74 |x|/h): what lies beyond the record is modelled (nodes may
lie outside the record; the tails their tractions send beyond it are simply not observed,
never wrapped back).

Prior (default ``prior="contact"``, ``inverse_prior``): the tractions of a contact.  p is a
smooth (Matern-5/2) process times the square-root profile of a window (a smooth indenter's
pressure falls as the square root of the distance to the contact's edge); q = mu0 p + a smooth
multiple of the same profile (a local mu varying across the contact) + a constant on the window
(a shear strength: q steps at the edges); a white nugget on every node.  The window (the contact
interval), the amplitudes, lengths, mu0 and the two noise sd (one per data component, white,
Gaussian) maximise the evidence (the marginal likelihood, closed form, analytic gradient); none
is set by hand.  Two passes: nodes every h/4 over the record +- ``MARGIN_H`` h to place the
window (the evidence on a grid of windows, one local search from the best, an edge scan), then
nodes every h/16 on the window +- 0.75 h (the tractions are zero beyond: the prior's
statement), with a scan of each edge against a second maximum of the evidence.
``prior="envelope"``: the previous prior (Matern-1/2 processes inside an evidence-placed
logistic envelope, nodes every h/8 over the record +- ``MARGIN_H`` h), kept for tractions that
are not a contact's (no square-root edges).  The evidence can be nearly flat in p's length l_p
over a factor 10 (a rigid p with the shape's detail in the varying-mu part, or a flexible p with
a smooth mu), and the window moves with l_p: l_p is integrated on the evidence's profile (l_p
stepped by 0.5 in its log, the other hyperparameters re-maximised at each step; the points
within 5 nats of the best mixed with weights exp(log-evidence), ``regularisation.
evidence_maxima``), with l_p at most the contact's width (``inverse_prior.LP_MAX_WIDTH``: longer
lengths only make p the parametric semi-ellipse, toward which the evidence is flat); on the
varying-mu sensor records one maximum alone gave 2-sd coverage of p near 0.5, two restarts (a
rigid and a flexible p) 0.60, the profile to 20 h 0.75, the capped profile 1.00
(studies/README).

Model-error floor (both priors).  The noise sd of each data component is at least
``inverse_prior.model_error_floor``: 1e-3 of the data's peak per sample at the contact prior's
node step h/16, times sqrt(h/16 / sample step) for samples finer than that (``NOISE_FLOOR``).
It stands for the forward map's own discretisation error, which no noise sd below it can
describe: the base response of the exact tractions minus that of their hat interpolant on
h/16 nodes has rms 5.4e-4 (zz) and 3.3e-4 (xz) of the peak on the solver's noise-free record,
largest 1.9e-3, correlated over ~h (a semi-ellipse on the same window: 6.1e-4, 3.6e-4).  The
two priors' likelihoods share it, so that ``auto`` compares them on the tractions: with the
floor on the contact prior only, the envelope prior fitted a noise-free record to 4e-6 of its
peak and won the evidence by ~7600 nats on that alone (solve(load=200, mu=1): Q 200.32 +- 0.08
N/m, right edge 0.26 mm = 16 sd out, every law rejected).  On records of 0.01-0.1 % noise and
noise-free ones both priors' noise sd sit at the floor; at 1 % noise it is inactive (the 132
calibration records' numbers are unchanged to the last digit).

Posterior.  Gaussian given the hyperparameters; with ``hyper=True`` (default, contact prior)
the other hyperparameters' own uncertainty is added to first order at each profile point
(Laplace: S + J Sigma_theta J^T, ``inverse_prior.propagate``).  From it:

* P = Int p dx, Q = Int q dx (the hat functions integrate to dt) and Q/P, with sigmas from the
  covariance (Q/P by the first-order (delta) rule with the P-Q correlation);
* pointwise sd of p, q; mu_local = q/p with its delta-rule sd where p is *resolved*: the
  posterior mean exceeds 3 sd (``RESOLVED_Z``);
* the contact interval: the contact prior's window widened by its rounding's offset (0.087
  node steps each side, ``inverse_prior.rounding_offset``), with the sd of its edges from the
  Laplace covariance of the hyperparameters (envelope prior: from 400 posterior draws, the outermost
  crossings around the peak of the level 2 * (median sd of p));
* the resolution length: pi / k_c, k_c the largest wavenumber whose sinusoid of the peak
  pressure still shows in the data at 3 noise sd (``inverse_forward._resolution_length``).

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
from types import SimpleNamespace

import numpy as np

from ..errors import InputError, named
from ..numerics.blas_threads import single_blas_thread
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
from .inverse_prior import fit_contact, model_error_floor, propagate, regularisation_record, rounding_offset
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
                    "view", "points", "nodes", "positive", "support_m", "laws",
                    "contact_within_record")


# --- the inversion ----------------------------------------------------------------------------


SCREEN_STEP_H = 0.5
"""Node step [h] of the envelope prior's screen under ``prior="auto"``: its log-evidence on
nodes every h/2 was within 0.1-2.2 nats of that on its own h/8 nodes on 8 calibration records
(and h/4 within 0.5), at a tenth of the cost (studies/README, inverse, speed)."""
SCREEN_NATS = 10.0
"""Under ``prior="auto"`` the envelope prior is fitted on its own nodes only if its screen's
log-evidence comes within this of the contact prior's (else the contact prior is kept: the
envelope's evidence cannot reach it with the screen's error)."""


def _envelope_screen(x_m, zz_Pa, xz_Pa, thickness, poisson, view, apparatus, support):
    """The envelope prior's maximum log-evidence (in the units of ``invert_line``'s
    ``log_evidence``) on nodes every ``SCREEN_STEP_H`` h, or None where it cannot be
    evaluated."""
    from .sensor import _resolve

    h = float(thickness)
    x, dz, dxz = _check_record(x_m, zz_Pa, xz_Pa)
    x, dz, dxz, _ = _bin(x, dz, dxz, BIN_STEP_H * h)
    scale = max(float(np.max(np.abs(dz))), float(np.max(np.abs(dxz))))
    symbols = _symbols(_resolve(apparatus) if view == "sensor" else None, h)
    sup_h = None if support is None else (float(support[0]) / h, float(support[1]) / h)
    try:
        fwd = LineForward.build(x / h, Film(1.0, poisson), symbols, support=sup_h,
                                step=SCREEN_STEP_H)
        ev = _Evidence(fwd, dz / scale, dxz / scale, envelope=sup_h is None)
        fl = model_error_floor((x[1] - x[0]) / h)
        _, le, _ = _optimise(ev, dz / scale, dxz / scale, fwd.nodes[1] - fwd.nodes[0],
                             ftol=1e-7, gtol=1e-2, noise_floor=(fl, fl))
    except (ValueError, ArithmeticError, np.linalg.LinAlgError):
        return None
    return float(le - 2 * x.size * math.log(scale)) if math.isfinite(le) else None


BIN_STEP_H = 1.0 / 32.0
"""Records sampled finer than this [h] are averaged in consecutive groups of k samples (k the
largest with k dx <= BIN_STEP_H h) before the inversion: for white noise the group means carry
the same information (sd sigma / sqrt k) as long as the forward map is linear across a group,
and the film's responses vary on h, not on h/32 (the tail of fewer than k samples at the end is
dropped).  The cost then does not grow with the number of samples beyond that."""


def _bin(x, zz, xz, step):
    """(x, zz, xz, k): group means of k consecutive samples (k = 1: unchanged)."""
    dx = (x[-1] - x[0]) / (x.size - 1)
    k = int(step // dx)
    if k < 2 or x.size // k < 8:
        return x, zz, xz, 1
    n = (x.size // k) * k
    return (x[:n].reshape(-1, k).mean(axis=1), zz[:n].reshape(-1, k).mean(axis=1),
            xz[:n].reshape(-1, k).mean(axis=1), k)


PROPAGATE_MIN_WEIGHT = 0.05
"""Profile points of smaller weight enter the mixture at their hyperparameters (no Laplace step
for the others: it costs 2 d evaluations of the evidence with the gradient, and these points
carry 5-10 % of the weight together); their window's edge sd is the weighted mean of the
propagated points'."""


def _mix_modes(ev, modes, free, hyper, h, known):
    """Posterior mean and covariance mixed over the evidence's maxima (weights exp(log-evidence),
    normalised), each with its hyperparameters' uncertainty propagated when ``hyper``; the
    windows [(edges [m], edge sd [m])] and the weights."""
    les = np.array([le for _, le in modes])
    wts = np.exp(les - les.max())
    wts /= wts.sum()
    means, covs, windows = [], [], []
    held = free.copy()
    if len(modes) > 1:  # l_p is integrated by the profile's points (``inverse_prior._modes``)
        held[3] = False
    for (th, _), wt in zip(modes, wts):
        sig, idx = None, []
        if hyper and (wt >= PROPAGATE_MIN_WEIGHT or len(modes) == 1):
            le, g, (mk, ck, _) = ev.evaluate(th, grad=True, full=True)
            mk, ck, sig, idx = propagate(ev, th, held, mk, ck, centre=(le, g))
        else:
            _, (mk, ck, _) = ev.evaluate(th, full=True)
        means.append(mk)
        covs.append(ck)
        windows.append(_window_interval(th, sig, idx, h, known, rounding_offset(ev.dt)))
    mbar = sum(w * mk for w, mk in zip(wts, means))
    cov = sum(w * (ck + np.outer(mk - mbar, mk - mbar)) for w, mk, ck in zip(wts, means, covs))
    return mbar, cov, windows, wts


def _window_interval(theta, sig, idx, h, known, offset=0.0):
    """The contact prior's window [c - w0, c + w0] [m], widened by ``offset`` [h] on each side
    (the rounding's, ``inverse_prior.rounding_offset``), and the sd of its two edges from the
    Laplace covariance of (c, log w0) (NaN where not propagated or at a bound; 0 if known)."""
    c, w0 = float(theta[0]), math.exp(theta[1])
    edges = [(c - w0 - offset) * h, (c + w0 + offset) * h]
    if known is not None:
        return [known[0] * h, known[1] * h], [0.0, 0.0]
    if sig is None or 0 not in idx or 1 not in idx:
        return edges, [float("nan"), float("nan")]
    i, j = idx.index(0), idx.index(1)
    vc, vl, cl = sig[i, i], sig[j, j], sig[i, j]
    va = vc + w0 * w0 * vl - 2 * w0 * cl
    vb = vc + w0 * w0 * vl + 2 * w0 * cl
    return edges, [math.sqrt(max(va, 0.0)) * h, math.sqrt(max(vb, 0.0)) * h]


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
    big = max(float(np.max(np.abs(zz))), float(np.max(np.abs(xz))))
    if not VALUE_RANGE_PA[0] <= big <= VALUE_RANGE_PA[1]:
        raise InputError(f"the record's largest |stress| is {big:.3g} Pa: the inversion takes "
                         f"{VALUE_RANGE_PA[0]:g} ... {VALUE_RANGE_PA[1]:g} Pa")
    return x, zz, xz


VALUE_RANGE_PA = (1e-100, 1e100)
"""The largest |stress| of a record the inversion takes (subnormal or huge values are refused:
the evidence squares them)."""
SPAN_RANGE_H = (0.5, 100.0)
"""The record's x span, in film thicknesses, that the inversion takes (beyond 100 h its traction
nodes, h/8 apart, make matrices of > 1 GB; below 0.5 h the record sees no contact; x in
millimetres under an ``x_m`` header falls outside)."""


def _check_span(x, h):
    """The record's span and step against the film thickness h [m] (``SPAN_RANGE_H``; a step
    of at most h, the scale on which base stresses vary)."""
    span, step = float(x[-1] - x[0]), float(x[1] - x[0])
    lo, hi = SPAN_RANGE_H
    if not lo * h <= span <= hi * h or step > h:
        raise InputError(f"x_m spans {span:.3g} m in steps of {step:.3g} m, i.e. {span / h:.3g} "
                         f"film thicknesses ({named('thickness')} {h:g} m): the inversion takes "
                         f"records spanning {lo:g} ... {hi:g} thicknesses with a step of at most "
                         f"one (is x in metres, the thickness right?)")


@single_blas_thread()
def invert_line(x_m, zz_Pa, xz_Pa, *, thickness: float = 0.002, poisson: float = 0.5,
                view: str = "base", apparatus=None, positive: bool = False, support=None,
                draws: int = 400, seed: int = 0, prior: str = "auto",
                hyper: bool = True) -> LineInversion:
    """Interface tractions from a line record (see the module docstring).

    x_m : uniform increasing positions [m]; zz_Pa : -sigma_zz(x, 0) (compression > 0) or S_zz;
    xz_Pa : sigma_xz(x, 0) or S_xz; view : "base" (no apparatus) or "sensor" (apparatus: None
    for the paper's G_zz, G_xz, or a pair of ``ApparatusFunction``); thickness [m], poisson : the
    film; positive : p >= 0; support : (a, b) [m] known contact; draws, seed : posterior draws
    for the contact interval's uncertainty.  prior : "auto" (default: both priors fitted to the
    same data and the one of higher evidence kept, equal prior odds; a contact prior whose
    search fails is reported as such in ``regularisation["prior_choice"]``), "contact" or
    "envelope".  Both priors' noise sd are at least the model-error floor (the module
    docstring; ``regularisation["model_error_floor_Pa"]``, per original sample).
    """
    if prior == "auto":
        return _invert_auto(x_m, zz_Pa, xz_Pa, dict(
            thickness=thickness, poisson=poisson, view=view, apparatus=apparatus,
            positive=positive, support=support, draws=draws, seed=seed, hyper=hyper))
    d = _prepare(x_m, zz_Pa, xz_Pa, thickness, poisson, view, apparatus, support, prior)
    f = _fit(prior, d, hyper)
    m = f.fwd.nodes.size
    mean, cov = f.mean, f.cov
    if positive:
        mean, cov, _ = _positive(mean, cov, m)
    # SI: stresses * scale; lengths * h
    h, scale = d.h, d.scale
    p, q = mean[:m] * scale, mean[m:] * scale
    cov_si = cov * scale**2
    sd = np.sqrt(np.maximum(np.diag(cov_si), 0.0))
    sp_, sq_ = sd[:m], sd[m:]
    totals = _totals(f.fwd.weights, p, q, cov_si, h)
    resolved, mu, mu_sd = _local_mu(p, q, sp_, sq_, cov_si)
    if prior == "contact":  # the contact interval is the prior's window, with its Laplace sd
        interval, interval_sd = _window_mixture(f.windows, f.weights)
    else:  # contact interval from posterior draws
        interval, interval_sd = _contact_interval(f.fwd.nodes * h, p, cov_si[:m, :m], sp_, draws,
                                                  seed)
    # resolution length: equivalent width of the resolution-matrix row at the peak of p
    res_len = _resolution_length(f.fwd, d.symbols, d.film, min(f.nz, f.nx) * scale, d.x.size,
                                 float(np.max(p)), h)
    laws = _laws(f.fwd.nodes * h, p, q, cov_si, resolved, interval, res_len)
    rec = _record(d, f, totals, interval, interval_sd, res_len, laws, prior, view, positive,
                  support, hyper)
    fz, fx = f.fwd.apply(mean[:m], mean[m:])
    data = {"x_m": d.x, "zz": d.dz, "xz": d.dxz, "zz_fit": fz * scale, "xz_fit": fx * scale}
    return LineInversion(f.fwd.nodes * h, p, sp_, q, sq_, mu, mu_sd, rec, data, cov_si)


def _invert_auto(x_m, zz_Pa, xz_Pa, kw):
    """``prior="auto"``: the contact prior, the envelope prior screened on coarse nodes (or
    fitted on its own), the one of higher evidence kept, with the choice's record."""
    try:
        con = invert_line(x_m, zz_Pa, xz_Pa, prior="contact", **kw)
        failed = None if math.isfinite(con.record["log_evidence"]) else "log-evidence not finite"
    except InputError:
        raise
    except (ValueError, IndexError, ArithmeticError, np.linalg.LinAlgError) as exc:
        # what fails here is the contact prior's window search, not the record's checks
        con, failed = None, f"{type(exc).__name__}: {exc}"
    screen = None
    if con is not None and failed is None:
        screen = _envelope_screen(x_m, zz_Pa, xz_Pa, kw["thickness"], kw["poisson"], kw["view"],
                                  kw["apparatus"], kw["support"])
    if screen is not None and screen < con.record["log_evidence"] - SCREEN_NATS:
        best, le_env = con, screen
    else:
        env = invert_line(x_m, zz_Pa, xz_Pa, prior="envelope", **kw)
        le_env, screen = env.record["log_evidence"], None
        best = env if con is None or failed or le_env > con.record["log_evidence"] else con
    best.record["regularisation"]["prior_choice"] = {
        "rule": "the prior of higher log-evidence on the same data (equal prior odds)",
        "log_evidence_contact": None if con is None else con.record["log_evidence"],
        "log_evidence_envelope": le_env,
        "envelope_screened": (None if screen is None else
                              f"the envelope's evidence on nodes every {SCREEN_STEP_H:g} h "
                              f"(within ~2 nats of its h/8 nodes' on the calibration "
                              f"records) is more than {SCREEN_NATS:g} nats below the "
                              f"contact's: not refitted on h/8 nodes"),
        "contact_failed": failed,
        "chosen": "contact" if best is con else "envelope"}
    return best


def _prepare(x_m, zz_Pa, xz_Pa, thickness, poisson, view, apparatus, support, prior):
    """The checked, binned record (SI) with h, nu, points, nbin, scale, film, symbols, sup_h."""
    from ..physics.scene import check_poisson, check_positive

    h = check_positive("thickness", thickness, "m")
    nu = check_poisson(poisson)
    x, dz, dxz = _check_record(x_m, zz_Pa, xz_Pa)
    _check_span(x, h)
    if prior not in ("contact", "envelope"):
        raise InputError(f"prior must be 'auto', 'contact' or 'envelope'; got {prior!r}")
    if view not in ("base", "sensor"):
        raise InputError(f"view must be 'base' or 'sensor'; got {view!r}")
    if view == "sensor":
        from .sensor import _resolve

        apparatus = _resolve(apparatus)
    elif apparatus is not None:
        raise InputError("an apparatus applies to sensor records (view='sensor'), not to base "
                         "stresses")
    sup_h = _check_support(support, x, h)
    points = x.size
    x, dz, dxz, nbin = _bin(x, dz, dxz, BIN_STEP_H * h)
    scale = max(float(np.max(np.abs(dz))), float(np.max(np.abs(dxz))))
    return SimpleNamespace(h=h, nu=nu, x=x, dz=dz, dxz=dxz, points=points, nbin=nbin, scale=scale,
                           film=Film(1.0, nu), symbols=_symbols(apparatus, h), sup_h=sup_h)


def _check_support(support, x, h):
    """A known contact (a, b) [m] in h, or None."""
    if support is None:
        return None
    a, b = (float(s) for s in support)
    if not (math.isfinite(a) and math.isfinite(b) and b > a):
        raise InputError(f"support must be an interval (a, b) with b > a [m]; got {support}")
    lo, hi = x[0] - MARGIN_H * h, x[-1] + MARGIN_H * h  # where the tractions are modelled
    if a < lo or b > hi:
        raise InputError(f"{named('support')} {a:g} {b:g}: the known contact must lie within "
                         f"the record extended by {MARGIN_H:g} thicknesses, [{lo:.6g}, "
                         f"{hi:.6g}] m")
    return (a / h, b / h)


def _fit(prior, d, hyper):
    """The prior's nodes, hyperparameters and posterior (scaled units): fwd, theta, logev, free,
    mean, cov, nz, nx; modes, windows, weights (contact prior; else None)."""
    xh, zs, xs = d.x / d.h, d.dz / d.scale, d.dxz / d.scale
    if prior == "contact":
        fwd, ev, modes, free = fit_contact(xh, d.film, d.symbols, zs, xs, d.sup_h)
        theta, logev = modes[0]
        mean, cov, windows, weights = _mix_modes(ev, modes, free, hyper, d.h, d.sup_h)
        nz, nx = np.exp(theta[10:12])
    else:
        fwd = LineForward.build(xh, d.film, d.symbols, support=d.sup_h)
        ev = _Evidence(fwd, zs, xs, envelope=d.sup_h is None)
        fl = model_error_floor((d.x[1] - d.x[0]) / d.h)  # the same floor as the contact's
        theta, logev, free = _optimise(ev, zs, xs, fwd.nodes[1] - fwd.nodes[0],
                                       noise_floor=(fl, fl))
        _, (mean, cov, _) = ev.evaluate(theta, full=True)
        nz, nx = np.exp(theta[5:7])
        modes = windows = weights = None
    return SimpleNamespace(fwd=fwd, theta=theta, logev=logev, free=free, mean=mean, cov=cov,
                           nz=nz, nx=nx, modes=modes, windows=windows, weights=weights)


def _totals(w, p, q, cov_si, h):
    """(P, Q, var P, var Q, Q/P, var Q/P): the node weights w [h] integrate p, q [Pa]; the
    ratio's variance by the delta rule with the P-Q covariance."""
    m = w.size
    wv = np.concatenate([w, np.zeros(m)]) * h
    wq = np.concatenate([np.zeros(m), w]) * h
    P, Q = float(wv @ np.concatenate([p, q])), float(wq @ np.concatenate([p, q]))
    vP, vQ, cPQ = float(wv @ cov_si @ wv), float(wq @ cov_si @ wq), float(wv @ cov_si @ wq)
    ratio = Q / P if P != 0 else float("nan")
    vR = (vQ - 2 * ratio * cPQ + ratio**2 * vP) / P**2 if P != 0 else float("nan")
    return P, Q, vP, vQ, ratio, vR


def _local_mu(p, q, sp_, sq_, cov_si):
    """(resolved, mu_local, its sd): q/p and its delta-rule sd where p > RESOLVED_Z sd(p)."""
    m = p.size
    resolved = p > RESOLVED_Z * sp_
    cpq_d = np.diag(cov_si[:m, m:])
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(resolved, q / p, np.nan)
        mu_sd = np.where(resolved, np.sqrt(np.maximum(sq_**2 - 2 * mu * cpq_d + mu**2 * sp_**2,
                                                      0.0)) / np.abs(p), np.nan)
    return resolved, mu, mu_sd


def _window_mixture(windows, weights):
    """The contact prior's interval [m] and its edges' sd mixed over the evidence's maxima."""
    e = np.array([w[0] for w in windows])
    v = np.array([w[1] for w in windows]) ** 2
    for i in (0, 1):  # points not propagated (PROPAGATE_MIN_WEIGHT): the others' mean
        ok = np.isfinite(v[:, i])
        if ok.any() and not ok.all():
            v[~ok, i] = weights[ok] @ v[ok, i] / weights[ok].sum()
    ebar = weights @ e
    interval = [float(ebar[0]), float(ebar[1])]
    interval_sd = [float(math.sqrt(max(weights @ (v[:, i] + (e[:, i] - ebar[i]) ** 2), 0.0)))
                   for i in (0, 1)]
    return interval, interval_sd


def _laws(xn, p, q, cov_si, resolved, interval, res_len):
    """The law fits on resolved pairs away from the contact edges (there the smoothing mixes in
    the zeros outside and the steps of a shear strength: LAW_EDGE_GUARD resolution lengths)."""
    m = p.size
    inside = np.ones(m, bool)
    if np.all(np.isfinite(interval)):
        g = LAW_EDGE_GUARD * res_len if math.isfinite(res_len) else 0.0
        inside = (xn > interval[0] + g) & (xn < interval[1] - g)
    idx = np.nonzero(resolved & inside)[0]
    laws = fit_laws(p[idx], q[idx], cov_si[np.ix_(idx, idx)], cov_si[np.ix_(m + idx, m + idx)],
                    cov_si[np.ix_(idx, m + idx)])
    if "note" in laws and not laws.get("best"):  # no law fitted: say which nodes count
        laws["note"] += (f" (the fits use nodes where p > {RESOLVED_Z:g} sd(p), at least "
                         f"{LAW_EDGE_GUARD:g} resolution lengths inside the contact interval; "
                         f"{int(resolved.sum())} of {m} nodes have p > {RESOLVED_Z:g} sd)")
    return laws


def _record(d, f, totals, interval, interval_sd, res_len, laws, prior, view, positive, support,
            hyper):
    """The JSON record (``INVERT_JSON_KEYS`` and more), SI."""
    P, Q, vP, vQ, ratio, vR = totals
    h, scale = d.h, d.scale
    rec = {"load_N_per_m": P, "load_sigma_N_per_m": math.sqrt(max(vP, 0.0)),
           "tangential_load_N_per_m": Q, "tangential_load_sigma_N_per_m": math.sqrt(max(vQ, 0.0)),
           "Q_over_P": ratio, "Q_over_P_sigma": math.sqrt(max(vR, 0.0)),
           "contact_interval_m": interval, "contact_interval_sigma_m": interval_sd,
           "resolution_length_m": res_len,
           "regularisation": regularisation_record(prior, f.theta, f.free, scale, h, hyper),
           "log_evidence": float(f.logev - 2 * d.x.size * math.log(scale)),
           "noise_sd_zz_Pa": float(f.nz * scale * math.sqrt(d.nbin)),
           "noise_sd_xz_Pa": float(f.nx * scale * math.sqrt(d.nbin)),
           "view": view, "points": int(d.points), "binned_by": int(d.nbin),
           "nodes": int(f.fwd.nodes.size), "positive": bool(positive),
           "support_m": None if support is None else [float(s) for s in support],
           "resolved_rule": f"mu_local where p > {RESOLVED_Z:g} sd(p)",
           "thickness_m": h, "poisson": d.nu, "laws": laws}
    # a contact edge beyond the record's ends: P, Q and the window there are the prior's
    # extrapolation (a noise-free record ending at the contact's centre gave P 86 +- 7 N/m for
    # 200): flagged, not refused (with 1 % noise the same record's band held the truth)
    rec["record_m"] = [float(d.x[0]), float(d.x[-1])]
    rec["contact_within_record"] = bool(not np.all(np.isfinite(interval))
                                        or (interval[0] >= d.x[0] and interval[1] <= d.x[-1]))
    rec["regularisation"]["model_error_floor_Pa"] = float(
        model_error_floor((d.x[1] - d.x[0]) / h) * scale * math.sqrt(d.nbin))
    if prior == "contact":
        rec["regularisation"]["evidence_maxima"] = [
            {"log_evidence_below_best": float(f.logev - le), "weight": float(wt),
             "length_p_m": float(math.exp(th[3]) * h), "mu0": float(th[4]),
             "window_m": [float(w_[0][0]), float(w_[0][1])]}
            for (th, le), wt, w_ in zip(f.modes, f.weights, f.windows)]
    return rec


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
    if kind != "U" and (A_zz_mV_per_bar is not None or A_xz_mV_per_bar is not None):
        raise InputError(f"{name}: the gains (--a-zz/--a-xz, A_zz_mV_per_bar/A_xz_mV_per_bar) "
                         f"apply to U_zz_mV,U_xz_mV files only; this file holds "
                         f"{','.join(_VIEWS[kind][1:])}: drop them")
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
           positive: bool = False, support=None, prior: str = "auto") -> LineInversion:
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
    positive, support, prior : see ``invert_line``.
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
                       apparatus=apparatus, positive=positive, support=support, prior=prior)
