"""From measured base-stress maps to the interface: tractions p(x, y), q_x(x, y), q_y(x, y)
with pointwise uncertainty, the totals F, Q_x, Q_y and the local friction law (issue 21,
surfaces; the line records are ``instruments.inverse``).

Data.  On a uniform grid x_i, y_j (the file's frame; no apex assumed), arrays [x, y] of

    d_zz = -sigma_zz(x, y, 0)  (compression > 0),  d_xz = sigma_xz(x, y, 0),  d_yz = sigma_yz(x, y, 0)

(``view="base"``: the package's ``--maps`` keys and signs) or the MEMS view through the 2D
apparatus functions (``view="sensor"``: S_zz = G_zz (*) d_zz, S_xz = G_xz (*) d_xz,
S_yz = G_xz (*) d_yz, as ``instruments.sensor.sensor_maps`` writes them).

Forward map.  Linear and diagonal in Fourier space: per wavevector k the 3x3 symbol M(k) that
takes the surface tractions (p^, q_x^, q_y^) to the data, built from the film's public base
transfer (``physics.film.Film.base_transfer``: physics3d.md A, B, C and sech K) times the
apparatus symbols; M(0) = I (the base carries the loads).  Nyquist planes: the terms odd in n
are averaged over the two aliases (``Grid.alias_average``), as the solver does.

The window.  A stationary model is exact on a periodic record.  ``solve --maps`` writes the
solver's periodic domain, whose margin lets the base field decay (~1e-4 of its peak at the
border): there the record *is* one period, and nothing lies beyond it.  A record cut from a
larger field (a measured window) still carries 4-12 % of the peak at its border, and a
periodic model would wrap those tails.  Such records are refused, not inverted: after the fit,
if the re-predicted data on the outermost rows or columns exceed ``BORDER_Z`` noise sd and
``BORDER_REL`` of the peak, or the record's mean along one side exceeds ``BORDER_MEAN_Z`` sd of
that mean (a tail below the noise per sample: a disc cut at +-3.75 r under 1 % noise had its F
and Q_x 1.5-5 sigma low before), the call raises InputError (an axis along which the field does not
vary, a line record repeated along y, is periodic and not checked) (modelling tractions beyond a window,
as the line inverse does with its margins, is not done for maps).

Priors.  Two, chosen by the evidence (``prior="auto"``, the default, fits both and keeps the
one of higher evidence; ``"contact"`` or ``"smooth"`` forces one): the contact prior
(``inverse_maps_contact``: an ellipse fitted by evidence carries p = sqrt(1 - u^2) g, a smooth
g, and q = mu0 p + the same shapes + a shear strength; a white nugget everywhere; its
posterior sd is larger where the contact's shape leaves the tractions uncertain) and the
stationary ("smooth") prior below, whose sd is the same at every point.

Smooth prior.  p, q_x, q_y are independent zero-mean stationary Gaussian processes with Matern
spectral densities, per field f

    lambda_f(k) = s_f^2 4 pi nu l_f^2 (1 + k^2 l_f^2)^-(nu + 1)     (pointwise variance s_f^2),

amplitudes s_p, s_qx, s_qy, lengths l_p and l_q (q_x and q_y share one), smoothness nu.  The
noise is white and Gaussian, one sd per component (sigma_zz, sigma_xz, sigma_yz).  The eight
hyperparameters maximise the evidence, exact for a stationary model on a periodic record and
cheap: per mode the data covariance M Lambda M^H + Sigma_n is 3x3 (Whittle's form, exact for a
periodic field); analytic gradient (checked against differences), L-BFGS-B; nu is then chosen
among ``KERNEL_NUS`` by the same evidence.  None is set by hand.

Model-error floor (both priors).  Each noise sd is at least ``MODEL_ERROR_FLOOR`` = 1e-4 of
the data's peak (``regularisation.model_error_floor_Pa`` in the JSON): the contact prior's own
discretisation misfit, a model error, not a measurement's.  The contact prior takes the
smooth fit's noise, so both likelihoods share it.  Measured on the solver's noise-free sphere
map (``inverse_maps_stationary.MODEL_ERROR_FLOOR``): the base response of the exact tractions
minus that of their best fit by the contact prior's basis has rms 1e-4 of the peak where the
data exceed 1 % of it with the edge rounded over 0.1 cell, 1.6e-5 over 0.01 cell (now); the
floor keeps the first, since below ~5e-5 the fit's own error decides (that docstring).  Now
that map gives F, Q_x within 0.04 sigma (5e-7), the 2-sd band holding p, q_x, q_y at 0.96,
0.99, 1.00 of the contact's cells, L2 0.4 %, Amontons kept (mu 0.99999 +- 3e-5, chi^2 0.8 on
56 dof; 4.7 min wall at a load of ~3, 512^2 cells), its fit still flagged not converged
(remaining step 0.12 sd; was 5.2).  Before (bound 1e-8) a noise-free map's noise sd went to 1e-8 of its
peak, and the local laws were judged against bands of that size: on the sphere map of
``solve --indenter sphere --force 1 --mu 1 --thickness 0.0025 --maps`` every law was rejected
(Amontons chi^2 442 on 296 dof), the fit not converged.  At 1 % noise it is inactive.

Posterior (smooth prior).  Per mode: A = M^H D^-1 M + Lambda^-1, mean A^-1 M^H D^-1 d^, covariance A^-1.  The
pointwise variance (1/N) Sum_k diag A^-1(k) is exact, and the same at every point (the prior is
stationary): it is the posterior's average uncertainty, not larger at the contact's edges where
the errors concentrate (see studies/inverse_maps.py for the coverage this gives).  The
covariance of two cells is the inverse transform of A^-1 at their offset.  Totals F = Int p dA,
Q = Int q dA are the k = 0 mode, with variances N A^-1(0) dA^2.  (The tractions are on the
record's grid; the margin of the solver's domain is part of it.)

Resolution length.  The posterior mean of p is the truth seen through the point-spread
function R_pp = [A^-1 M^H D^-1 M]_pp of the smooth prior (what the film, the apparatus and the
noise let through, whichever prior is kept: the contact prior's response to a point load is
the ellipse's smooth shapes, not a resolution); the resolution length is sqrt of its
equivalent area (Int R)^2 / Int R^2 (the side of the square of equal area).

Laws.  The local (p, q_par) pairs, q_par = q . e with e the direction of the total tangential
force, at cells where p is resolved (mean > ``RESOLVED_Z`` sd) and at least
``LAW_EDGE_GUARD`` resolution lengths inside the resolved region, thinned to a lattice of step
half a resolution length (at most ``LAW_MAX_PAIRS``), go to ``inverse.fit_laws`` with their full
posterior covariance: Amontons, q = tau0 + alpha p and the power law, sigmas and AIC.

Modules: ``inverse_maps_forward`` (M(k)), ``inverse_maps_stationary`` (smooth prior),
``inverse_maps_contact`` (contact prior), ``inverse_maps_result`` (``MapInversion``),
``inverse_maps_io`` (reading, checks); this one chooses the prior, the totals and the laws.

Units: lengths in h in the core, stresses scaled by the data's peak; SI at the edge.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..numerics.blas_threads import single_blas_thread
from ..numerics.grid import Grid
from ..physics.film import Film
from .inverse_maps_forward import base_maps_from_tractions
from .inverse_maps_forward import mode_weights as _weights  # noqa: F401
from .inverse_maps_forward import symbol as _symbol
from .inverse_maps_io import MIN_POINTS, read_maps
from .inverse_maps_io import check_maps as _check_maps
from .inverse_maps_result import MAP_OUT_KEYS, MapInversion
from .inverse_maps_stationary import KERNEL_NU, KERNEL_NUS, MODEL_ERROR_FLOOR
from .inverse_maps_stationary import StationaryModel as _Model
from .inverse_maps_stationary import optimise_stationary as _optimise

__all__ = ["invert", "invert_maps", "read_maps", "MapInversion", "MAP_INVERT_JSON_KEYS",
           "MAP_OUT_KEYS", "base_maps_from_tractions", "KERNEL_NUS", "BORDER_Z", "PRIORS"]

_ = (KERNEL_NU, MIN_POINTS, _Model)  # re-exported for the tests and older imports

PRIORS = ("auto", "contact", "smooth")
"""``prior`` values: auto keeps the one of higher evidence."""
BORDER_Z = 3.0
BORDER_REL = 1e-3
"""A record is a window (refused) if its re-predicted border data exceed this many noise sd
and ``BORDER_REL`` of the data's peak (noise-free records: the peak alone)."""
BORDER_MEAN_Z = 5.0
"""... or if one side's mean of the record exceeds this many sd of that mean (noise/sqrt(n))
and ``BORDER_REL`` of the peak: a tail below the noise per sample but plain over a side (noise
alone passes: 12 side means beyond 5 sd have a probability of ~7e-6)."""
RESOLVED_Z = 3.0
LAW_EDGE_GUARD = {"smooth": 1.0, "contact": 0.5}
"""Pairs at least this many resolution lengths inside the resolved region, by prior (the
contact prior's covariance carries the edges' uncertainty; the smooth prior's bias there is
not in its covariance)."""
LAW_MAX_PAIRS = 300

MAP_INVERT_JSON_KEYS = ("force_N", "force_sigma_N", "tangential_force_x_N",
                        "tangential_force_x_sigma_N", "tangential_force_y_N",
                        "tangential_force_y_sigma_N", "Q_over_P", "Q_over_P_sigma",
                        "resolution_length_m", "regularisation", "log_evidence",
                        "noise_sd_zz_Pa", "noise_sd_xz_Pa", "noise_sd_yz_Pa", "view", "points",
                        "laws")


class _Posterior:
    """One prior's posterior on the record (scaled units): mean, var (3, nx, ny); tot: the
    covariance of the three fields' sums over the cells; cov(a, b, ci, cj): covariance of field
    a at cells ci with field b at cells cj ((n, 2) index arrays); resolve(f): the mean of
    the noise-free data of f; psf: the point-spread of p; noise; logev; reg (the record's
    regularisation)."""

    def __init__(self, **kw):
        self.__dict__.update(kw)


def _index_kernels(C, shape):
    """c_ab(r) = Cov(f_a(x + r), f_b(x)) from per-mode covariances C (kshape, 3, 3)."""
    return [[np.fft.irfft2(C[..., a, b], s=shape) for b in range(3)] for a in range(3)]


def _lagged(kern, rows, cols, shape):
    di = (rows[:, 0][:, None] - cols[:, 0][None, :]) % shape[0]
    dj = (rows[:, 1][:, None] - cols[:, 1][None, :]) % shape[1]
    return kern[di, dj]


def _smooth_posterior(M, Y, shape, steps, ds, smoothness, say, logscale):
    nx, ny = shape
    dx, dy = steps
    N = nx * ny
    kmag = Grid((nx, ny), (nx * dx, ny * dy)).kmag
    fits = []
    th_prev = None
    for knu in smoothness:
        say(f"smooth prior: evidence, Matern nu = {knu:g}")
        model = _Model(M, Y, (nx, ny), dx * dy, kmag, float(knu))
        th, logev, opt = _optimise(model, ds, min(dx, dy), th_prev)
        th_prev = th
        fits.append((logev, float(knu), th, opt, model))
    logev, knu, theta, opt, model = max(fits, key=lambda f: f[0])
    noise = np.exp(theta[5:8])
    C, mean_k, _ = model.posterior(theta)
    mean = np.fft.irfft2(np.moveaxis(mean_k, -1, 0), s=shape, axes=(1, 2))
    w = _weights(shape)
    var = np.array([float(np.sum(w * C[..., i, i].real)) / N for i in range(3)])
    Rfull = np.einsum("...ij,...kj,k,...kl->...il", C, M.conj(), 1.0 / noise**2, M)
    psf = np.fft.irfft2(Rfull[..., 0, 0].real, s=shape)
    kern = []

    def cov(a, b, ci, cj):
        if not kern:
            kern.extend(_index_kernels(C, shape))
        return _lagged(kern[a][b], ci, cj, shape)

    def resolve(f):
        fk = np.moveaxis(np.fft.rfft2(np.asarray(f, float), axes=(1, 2)), 0, -1)
        return np.fft.irfft2(np.moveaxis(np.einsum("...ij,...j->...i", Rfull, fk), -1, 0),
                             s=shape, axes=(1, 2))

    lp, lq = np.exp(theta[:2])
    reg = {"prior": f"smooth: p, q_x, q_y independent zero-mean stationary Gaussian processes, "
                    f"Matern spectra (nu = {knu:g})",
           "smoothness_nu": knu,
           "log_evidence_by_nu": {f"{f[1]:g}": float(f[0] - logscale) for f in fits},
           "length_p_h": float(lp), "length_q_h": float(lq),
           "amplitude_scaled": [float(v) for v in np.exp(theta[2:5])],
           "chosen_by": "maximum evidence (marginal likelihood of the periodic record, exact "
                        "per mode)",
           "optimizer_converged": bool(opt.success)}
    return _Posterior(name="smooth", mean=mean, var=np.broadcast_to(var[:, None, None],
                                                                   (3,) + shape).copy(),
                      tot=N * C[0, 0].real, cov=cov, resolve=resolve, psf=psf, noise=noise,
                      logev=logev, reg=reg,
                      variance="exact per mode (stationary prior on the periodic record): the "
                               "same sd at every point")


def _contact_posterior(M, Y, shape, steps, smooth, say, logscale):
    from .inverse_maps_contact import (
        CONVERGED_STEP_SD,
        OPT_GTOL,
        PRIOR_NAMES,
        fit_contact,
        propagate,
        remaining_step,
    )

    nx, ny = shape
    tot = smooth.mean.sum(axis=(1, 2))
    nrm = math.hypot(tot[1], tot[2])
    e = (tot[1] / nrm, tot[2] / nrm) if nrm > 0 else (1.0, 0.0)
    mu_start = nrm / tot[0] if tot[0] > 0 else 0.0
    prior, th, s_out, logev, fit = fit_contact(
        M, Y, shape, steps, smooth.noise, e, smooth.mean[0], math.sqrt(smooth.var[0, 0, 0]),
        mu_start, progress=say)
    mean, var, C0, Z, (bx, by), Zsum = prior.posterior(th, s_out)
    say("contact prior: the hyperparameters' uncertainty (Laplace)")
    J, Sig, sd_th = propagate(prior, th, s_out)
    step_sd, converged = remaining_step(fit, Sig, sd_th)
    var = var + np.einsum("fxyi,ij,fxyj->fxy", J, Sig, J)
    Jsum = J.sum(axis=(1, 2))                                   # (3, 8)
    N = nx * ny
    tot_cov = N * C0[0, 0].real + Zsum @ Zsum.T + Jsum @ Sig @ Jsum.T
    px = np.full(nx, -1)
    px[bx] = np.arange(bx.size)
    py = np.full(ny, -1)
    py[by] = np.arange(by.size)
    kern = []

    def cov(a, b, ci, cj):
        if not kern:
            kern.extend(_index_kernels(C0, shape))
        bi, bj = (px[ci[:, 0]], py[ci[:, 1]]), (px[cj[:, 0]], py[cj[:, 1]])
        if min(v.min() for v in bi + bj) < 0:
            raise ValueError("cells outside the contact prior's covariance box")
        return (_lagged(kern[a][b], ci, cj, shape) + Z[a][bi] @ Z[b][bj].T
                + J[a][ci[:, 0], ci[:, 1]] @ Sig @ J[b][cj[:, 0], cj[:, 1]].T)

    def resolve(f):
        fk = np.moveaxis(np.fft.rfft2(np.asarray(f, float), axes=(1, 2)), 0, -1)
        return prior.mean_of(th, s_out, np.einsum("...ij,...j->...i", M, fk))

    ax, ay = math.exp(th[2]), math.exp(th[3])
    reg = {"prior": "contact: an ellipse (centre, semi-axes by evidence) carries p = sqrt(1 - "
                    "u^2) g_p and q = mu0 e p + sqrt(1 - u^2) g_q + tau (Matern-5/2 g, "
                    "amplitude s_p for all, tau ~ N(0, s_p^2)); a white nugget everywhere",
           "smoothness_nu": 2.5, "centre_h": [float(th[0]), float(th[1])], "semi_axes_h": [ax, ay],
           "length_p_h": float(math.exp(th[5])), "length_q_h": float(math.exp(th[7])),
           "mu0": float(th[6]), "direction": [float(e[0]), float(e[1])],
           "amplitude_scaled": float(math.exp(th[4])), "nugget_scaled": float(s_out),
           "chosen_by": "maximum evidence (Woodbury on the ellipse's unknowns, exact)",
           "optimizer_converged": converged,
           "optimizer_iterations": fit["iterations"],
           "optimizer_rounds": fit["rounds"],
           "optimizer_gradient_norm": fit["gradient_norm"],
           "optimizer_step_sd": step_sd,
           "optimizer_message": fit["message"],
           "optimizer_rule": f"L-BFGS-B with the analytic gradient of the log-evidence "
                             f"(stops at a projected gradient <= {OPT_GTOL:g} or when the "
                             f"evidence stops changing), alternating with the nugget's choice "
                             f"until it settles; converged: the nugget settled and the Newton "
                             f"step left at the end (Laplace covariance times the projected "
                             f"gradient) <= {CONVERGED_STEP_SD:g} of each hyperparameter's sd "
                             f"(optimizer_step_sd)",
           "hyperparameter_sd": dict(zip(PRIOR_NAMES, map(float, sd_th)))}
    return _Posterior(name="contact", mean=mean, var=var, tot=tot_cov, cov=cov,
                      resolve=resolve, psf=smooth.psf, noise=smooth.noise, logev=logev, reg=reg,
                      variance="the contact prior's posterior at its evidence-maximising "
                               "hyperparameters (nugget: per mode; ellipse: dense), plus the "
                               "hyperparameters' own uncertainty to first order (Laplace)")


def _check_spans(x, y, h):
    """Each axis's span and step against the film thickness h [m], as the line inverse's
    (``inverse.SPAN_RANGE_H``, a step of at most h): x in millimetres under ``x_m`` is refused
    in one line (it ended in an optimiser's ValueError)."""
    from ..errors import named
    from .inverse import SPAN_RANGE_H

    lo, hi = SPAN_RANGE_H
    for a, nm in ((x, "x_m"), (y, "y_m")):
        span, step = float(a[-1] - a[0]), float(a[1] - a[0])
        if not lo * h <= span <= hi * h or step > h:
            raise InputError(f"{nm} spans {span:.3g} m in steps of {step:.3g} m, i.e. "
                             f"{span / h:.3g} film thicknesses ({named('thickness')} {h:g} m): "
                             f"the inversion takes maps spanning {lo:g} ... {hi:g} thicknesses "
                             f"with a step of at most one (is {nm} in metres, the thickness "
                             f"right?)")


@single_blas_thread()
def invert_maps(x_m, y_m, zz_Pa, xz_Pa, yz_Pa, *, thickness: float = 0.002,
                poisson: float = 0.5, view: str = "base", apparatus=None,
                smoothness=KERNEL_NUS, prior: str = "auto", progress=None) -> MapInversion:
    """Interface tractions from maps (see the module docstring).

    x_m, y_m : uniform increasing axes [m]; zz_Pa : -sigma_zz(x, y, 0) (compression > 0) or
    S_zz; xz_Pa, yz_Pa : sigma_xz, sigma_yz (x, y, 0) or S_xz, S_yz; arrays [x, y].
    view : "base" or "sensor" (apparatus: None for the paper's G_zz, G_xz or a pair of
    ``ApparatusFunction``); thickness [m], poisson : the film; smoothness : the Matern nu
    values of the smooth prior; prior : "auto" (both, the higher evidence kept), "contact" or
    "smooth"; progress : None or a callable(str).
    """
    from ..physics.scene import check_poisson, check_positive

    say = progress or (lambda s: None)
    h = check_positive("thickness", thickness, "m")
    nu = check_poisson(poisson)
    x, y, d = _check_maps(x_m, y_m, (zz_Pa, xz_Pa, yz_Pa), ("zz", "xz", "yz"))
    _check_spans(x, y, h)
    if view not in ("base", "sensor"):
        raise InputError(f"view must be 'base' or 'sensor'; got {view!r}")
    if prior == "envelope":  # the line inverse's name for its smooth alternative
        prior = "smooth"
    if prior not in PRIORS:
        raise InputError(f"prior must be one of {', '.join(PRIORS)}; got {prior!r}")
    if view == "sensor":
        from .sensor import _resolve

        apparatus = _resolve(apparatus)
    elif apparatus is not None:
        raise InputError("an apparatus applies to sensor maps (view='sensor'), not to base "
                         "stresses")
    d = np.stack(d)
    nx, ny = x.size, y.size
    dx, dy = (x[-1] - x[0]) / (nx - 1) / h, (y[-1] - y[0]) / (ny - 1) / h
    scale = float(np.max(np.abs(d)))
    ds = d / scale
    grid = Grid((nx, ny), (nx * dx, ny * dy))
    M = _symbol(grid, Film(1.0, nu), apparatus, h)
    Y = np.moveaxis(np.fft.rfft2(ds, axes=(1, 2)), 0, -1)
    logscale = 3 * nx * ny * math.log(scale)
    first = (KERNEL_NU,) if prior == "auto" and KERNEL_NU in smoothness else smoothness
    post = smooth = _smooth_posterior(M, Y, (nx, ny), (dx, dy), ds, first, say, logscale)
    choice = {"smooth": float(smooth.logev - logscale)}
    _border_check(_predict(M, smooth.mean), smooth.noise, ds)  # a window: refused first
    if prior in ("auto", "contact"):
        try:
            contact = _contact_posterior(M, Y, (nx, ny), (dx, dy), smooth, say, logscale)
        except (np.linalg.LinAlgError, ValueError) as exc:
            if prior == "contact":
                raise InputError(f"prior='contact': no contact found in the maps ({exc})") \
                    from None
            contact = None
        if contact is not None:
            choice["contact"] = float(contact.logev - logscale)
            if prior == "contact" or contact.logev > smooth.logev:
                post = contact
    if post is smooth and tuple(first) != tuple(smoothness):  # the other nu values
        post = smooth = _smooth_posterior(M, Y, (nx, ny), (dx, dy), ds, smoothness, say,
                                          logscale)
        choice["smooth"] = float(smooth.logev - logscale)
    return _finish(x, y, d, scale, M, post, choice, (dx, dy), h, nu, view)


def _border_check(fit, noise, data=None):
    """Refuse a window cut from a larger field (module docstring, The window): a border
    sample of the re-predicted data above ``BORDER_Z`` noise sd, or (``data``: the record
    itself) the mean of one side's n samples above ``BORDER_MEAN_Z`` of its own sd,
    noise / sqrt(n) (a tail of 2 % of the peak under 1 % noise passes the first, not the
    second), either also above ``BORDER_REL`` of the peak."""
    edges, sides = [np.zeros((3, 1))], []
    for ax in (1, 2):
        if np.any(np.ptp(fit, axis=ax).max(axis=-1) > BORDER_Z * noise):
            edges.append(np.abs(np.take(fit, [0, -1], axis=ax)).reshape(3, -1))
            if data is not None:
                for i in (0, -1):
                    side = np.take(data, i, axis=ax)  # (3, n)
                    sides.append((np.abs(side.mean(axis=-1)), side.shape[-1]))
    border = np.concatenate(edges, axis=1).max(axis=1)
    border_z = border / noise
    what = None
    if np.any((border_z > BORDER_Z) & (border > BORDER_REL)):
        c = int(np.argmax(border_z))
        what = f"{border_z[c]:.3g} noise sd of signal ({('zz', 'xz', 'yz')[c]})"
    for m, n in sides:
        z = m * math.sqrt(n) / noise
        if what is None and np.any((z > BORDER_MEAN_Z) & (m > BORDER_REL)):
            c = int(np.argmax(np.where(m > BORDER_REL, z, 0.0)))
            what = (f"a mean of {m[c] / noise[c]:.3g} noise sd along one side "
                    f"({('zz', 'xz', 'yz')[c]}; {z[c]:.3g} sd of that mean)")
    if what is not None:
        raise InputError(f"the record's border carries {what}: a window cut from a larger "
                         f"field, which a periodic model would wrap; give maps that extend "
                         f"until the base field has decayed (as solve --maps writes them)")
    return border_z


def _predict(M, f):
    """The data M f (3, nx, ny) of tractions f (3, nx, ny)."""
    fk = np.moveaxis(np.fft.rfft2(f, axes=(1, 2)), 0, -1)
    return np.fft.irfft2(np.moveaxis(np.einsum("...ij,...j->...i", M, fk), -1, 0),
                         s=f.shape[1:], axes=(1, 2))


def _finish(x, y, d, scale, M, post, choice, steps, h, nu, view):
    nx, ny = x.size, y.size
    dx, dy = steps
    fit = _predict(M, post.mean)
    noise = post.noise
    border_z = _border_check(fit, noise)
    cellA = dx * dy * h * h
    F, Qx, Qy = post.mean.sum(axis=(1, 2)) * cellA * scale
    vtot = post.tot * (cellA * scale) ** 2
    ratio = Qx / F if F else float("nan")
    vR = ((vtot[1, 1] - 2 * ratio * vtot[0, 1] + ratio**2 * vtot[0, 0]) / F**2 if F
          else float("nan"))
    psf = post.psf
    res_h = math.sqrt(float(psf.sum() ** 2 / np.sum(psf**2)) * dx * dy)
    sd = np.sqrt(np.maximum(post.var, 0.0))
    pairs, laws = _laws(post, post.mean * scale, sd * scale, scale, (nx, ny), steps, res_h,
                        (Qx, Qy))
    reg = dict(post.reg)
    reg["prior_choice"] = {"chosen": post.name,
                           "log_evidence": choice,
                           "rule": "the prior of higher evidence (prior='auto'), or the one "
                                   "asked for; the smooth prior's evidence with nu = 1.5 "
                                   "alone unless it was kept"}
    reg["length_p_m"], reg["length_q_m"] = reg["length_p_h"] * h, reg["length_q_h"] * h
    reg["model_error_floor_Pa"] = float(MODEL_ERROR_FLOOR * scale)
    rec = {"force_N": float(F), "force_sigma_N": float(math.sqrt(max(vtot[0, 0], 0.0))),
           "tangential_force_x_N": float(Qx),
           "tangential_force_x_sigma_N": float(math.sqrt(max(vtot[1, 1], 0.0))),
           "tangential_force_y_N": float(Qy),
           "tangential_force_y_sigma_N": float(math.sqrt(max(vtot[2, 2], 0.0))),
           "Q_over_P": float(ratio), "Q_over_P_sigma": float(math.sqrt(max(vR, 0.0))),
           "resolution_length_m": res_h * h,
           "resolution_rule": "sqrt of the equivalent area (Int R)^2 / Int R^2 of the "
                              "smooth prior's point-spread function R for p",
           "regularisation": reg,
           "log_evidence": float(post.logev - 3 * nx * ny * math.log(scale)),
           "noise_sd_zz_Pa": float(noise[0] * scale), "noise_sd_xz_Pa": float(noise[1] * scale),
           "noise_sd_yz_Pa": float(noise[2] * scale),
           "border_signal_over_noise": [float(v) for v in border_z],
           "variance": post.variance,
           "view": view, "points": [int(nx), int(ny)], "thickness_m": h, "poisson": nu,
           "resolved_rule": f"laws on cells where p > {RESOLVED_Z:g} sd(p), at least "
                            f"{LAW_EDGE_GUARD[post.name]:g} resolution lengths inside that "
                            f"region, on a lattice of half a resolution length",
           "laws": laws}
    data = {"data": d, "fit": fit * scale}
    mm, sdm = post.mean * scale, sd * scale

    def resolution_operator(f):
        out = post.resolve(np.asarray(f, float) / scale) * scale
        return out[0], out[1], out[2]

    return MapInversion(x, y, mm[0], sdm[0], mm[1], sdm[1], mm[2], sdm[2], rec, data, pairs,
                        resolution_operator)


def _laws(post, mean, sd, scale, shape, steps, res, Q):
    """Local (p, q_par) pairs and the law fits (see the module docstring), with the pairs'
    full posterior covariance (``post.cov``, scaled units)."""
    from scipy.ndimage import distance_transform_edt

    from .inverse_laws import fit_laws

    dx, dy = steps
    p, qx, qy = mean
    Qx, Qy = Q
    nrm = math.hypot(Qx, Qy)
    e = (Qx / nrm, Qy / nrm) if nrm > 0 else (1.0, 0.0)
    q = e[0] * qx + e[1] * qy
    resolved = p > RESOLVED_Z * sd[0]
    dist = distance_transform_edt(resolved, sampling=(dx, dy))
    guard = LAW_EDGE_GUARD[post.name]
    inside = resolved & (dist > guard * res)
    sx, sy = max(1, int(round(0.5 * res / dx))), max(1, int(round(0.5 * res / dy)))
    lattice = np.zeros(shape, bool)
    lattice[::sx, ::sy] = True
    sel = np.argwhere(inside & lattice)
    if len(sel) > LAW_MAX_PAIRS:
        sel = sel[np.linspace(0, len(sel) - 1, LAW_MAX_PAIRS).astype(int)]
    empty = {"p": np.zeros(0), "q": np.zeros(0), "p_sd": np.zeros(0), "q_sd": np.zeros(0)}
    if len(sel) < 3:
        return empty, {"note": f"only {len(sel)} resolved cells at least {guard:g} "
                               f"resolution lengths inside the contact: no law fitted",
                       "best": None}
    s2 = scale * scale
    Cpp = post.cov(0, 0, sel, sel) * s2
    Cqq = sum(e[a - 1] * e[b - 1] * post.cov(a, b, sel, sel) for a in (1, 2) for b in (1, 2)) * s2
    Cpq = (e[0] * post.cov(0, 1, sel, sel) + e[1] * post.cov(0, 2, sel, sel)) * s2
    ii, jj = sel[:, 0], sel[:, 1]
    pp, qq = p[ii, jj], q[ii, jj]
    laws = fit_laws(pp, qq, 0.5 * (Cpp + Cpp.T), 0.5 * (Cqq + Cqq.T), Cpq)
    laws["direction"] = [float(e[0]), float(e[1])]
    laws["pairs"] = int(len(sel))
    pairs = {"p": pp, "q": qq, "p_sd": np.sqrt(np.diag(Cpp)), "q_sd": np.sqrt(np.diag(Cqq))}
    return pairs, laws


# --- entry: the package's ``invert`` for lines and maps ---------------------------------------

def invert(source=None, *, x_m=None, y_m=None, zz_Pa=None, xz_Pa=None, yz_Pa=None,
           view: str | None = None, thickness: float | None = None,
           poisson: float | None = None, apparatus=None, prior: str = "auto",
           **line_options):
    """Interface tractions with uncertainties from base stresses: a line record (-> the line
    inverse, ``instruments.inverse.invert``, with all its options) or maps (-> ``invert_maps``):

        >>> from spectral_contact import invert, solve
        >>> inv = invert(solve(indenter="sphere", force=1.0, mu=1.0))  # its base maps
        >>> inv.summary()["force_N"], inv.maps()["pressure_Pa"].shape
        >>> inv = invert("maps.npz", thickness=0.002)  # solve --maps, or S_* maps
        >>> inv.plot()

    Maps when ``source`` is a 3D result (``ContactResult3D``: its base maps, view "base",
    thickness and poisson from its scene), an .npz path (``read_maps``), or when ``y_m`` is
    given with ``x_m, zz_Pa, xz_Pa, yz_Pa`` arrays [x, y] (zz > 0 in compression:
    -sigma_zz(x, y, 0) or S_zz; ``view`` "base" by default, or "sensor").  Returns a
    ``MapInversion``; otherwise what the line inverse returns (``LineInversion``)."""
    is_result3d = source is not None and hasattr(source, "base_sigma_yz")
    is_npz = isinstance(source, (str,)) or hasattr(source, "__fspath__")
    is_npz = is_npz and str(source).lower().endswith(".npz")
    if not (is_result3d or is_npz or y_m is not None):
        from .inverse import invert as invert_line_entry

        if yz_Pa is not None:
            raise InputError("yz_Pa is for maps: give y_m as well (arrays [x, y])")
        return invert_line_entry(source, x_m=x_m, zz_Pa=zz_Pa, xz_Pa=xz_Pa, view=view,
                                 thickness=thickness, poisson=poisson, apparatus=apparatus,
                                 prior=prior, **line_options)
    bad = [k for k, v in line_options.items() if v not in (None, False)]
    if bad:
        raise InputError(f"{bad[0]}: not available for maps; line records only")
    if is_result3d:
        mp = source.maps()
        x, y, kind = mp["x_m"], mp["y_m"], "base"
        zz, xz, yz = -mp["base_sigma_zz_Pa"], mp["base_sigma_xz_Pa"], mp["base_sigma_yz_Pa"]
        thickness = source.scene.thickness if thickness is None else thickness
        poisson = source.scene.poisson if poisson is None else poisson
    elif is_npz:
        x, y, (zz, xz, yz), kind = read_maps(source)
        if view is not None and view != kind:
            raise InputError(f"{source}: holds {kind} maps; view={view!r} does not apply")
    else:
        if x_m is None or zz_Pa is None or xz_Pa is None or yz_Pa is None:
            raise InputError("maps need x_m, y_m, zz_Pa, xz_Pa and yz_Pa")
        x, y, zz, xz, yz, kind = x_m, y_m, zz_Pa, xz_Pa, yz_Pa, view or "base"
    return invert_maps(x, y, zz, xz, yz, thickness=0.002 if thickness is None else thickness,
                       poisson=0.5 if poisson is None else poisson, view=kind,
                       apparatus=apparatus, prior=prior)
