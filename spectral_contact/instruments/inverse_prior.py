"""The line inverse's contact prior (issue 21): tractions shaped as a contact's are, with every
hyperparameter chosen by the evidence, and the propagation of the hyperparameters' own
uncertainty into the posterior (Laplace over the log-hyperparameters).

Prior (nodes t_j, lengths in h).  A window of centre c and half-width w0 (hyperparameters),
u = (t - c)/w0, z = 1 - u^2, carries

    p = W g_p + n_p,
    q = mu0 p + W g_r + I tau + n_q,

with W = diag(w), w = sqrt(z+) the square-root profile of a contact's edges (a smooth indenter's
pressure falls to zero as the square root of the distance to the edge, for the exact model as
for Hertz), I = (1 on the window) (a shear strength tau0 makes q step at the edges), g_p, g_r
independent zero-mean Matern-5/2 processes (amplitudes s_p, s_r, lengths l_p, l_r: smooth
inside the contact), tau ~ N(0, s_t^2) one constant, and n_p, n_q an independent white nugget of
sd s_out on each node (whatever the shapes above do not hold, inside or outside the window).
q is correlated with p through mu0 (Amontons: g_r = tau = 0); its departures are a smooth
multiple of the edge profile (a local mu varying across the contact) and a constant that need
not vanish at the edges (q = tau0 + alpha p: mu0 = alpha, tau = tau0).  (A smooth tau(x) was
tried: the evidence then prefers it to W g_r for a varying mu, and its steps at the edges cost
4-6 % of L2 error; one constant does not mimic a varying mu.)  tau's prior sd is s_p, not a
hyperparameter of its own: a free s_t went to zero whenever the data could not show the step
(sensor view), where the Laplace width is not defined, and the posterior then excluded a shear
strength the data allowed (2-sd coverage 0.0-0.4, Q biased); one coefficient with a broad prior
costs little evidence and carries its uncertainty in the posterior itself.  For the same reason
the varying-mu part's amplitude s_r is s_p (``TIE_MU_PART``; a local mu departing from mu0 by
~1 is allowed a priori): a free s_r went to zero on the sensor view of a varying mu, leaving p
biased (2-sd coverage of p 0.64 -> 0.84 tied, L2 of q 12 % -> 5 %).
p's length l_p is at most the contact's width, 2 w0 (``LP_MAX_WIDTH``; the first pass's window,
or the known support): on a window of half-width w0 a Matern process of length l >> w0 is a
constant plus terms in u^k of prior variance ~ (w0/l)^(2k), so longer lengths only turn p into
the parametric shape constant x sqrt(z+), the Hertz semi-ellipse, which a film's pressure under
shear is not (its smooth factor tilts and bulges at the contact's own scale).  The evidence is
nearly flat toward that end (at 1 % noise, above all through the apparatus), and without the cap
the log-uniform integral of l_p up to 20 h gave it most of the weight: the bands were then a
one-parameter fit's, and on the varying-mu sensor records they missed p by 2-8 sd (2-sd coverage
of p 0.75; studies/README, inverse).  (Tried instead: a quadratic trend of p's factor, Legendre
P0-P2 in the window's coordinate with coefficients of sd s_p: it fixed that row, but the rigid end
was then a quadratic's fit, accepted by the evidence, and the bands lost coverage at 0.3 % noise;
with the cap the trend added nothing measurable.  The varying-mu part's l_r capped likewise
widened q's bands past nominal, 0.99-1.00, and raised L2 of q 2.7 -> 3.4 %: not capped.)
``z+`` is z rounded at the scale of a quarter node
step (softplus), so that the evidence is a smooth function of c and w0.  With a known support
(a, b) the window is (a, b) exactly (w = sqrt(max(z, 0)), I = 1) and c, w0 are not free.

The nine hyperparameters (c, log w0, log s_p, log l_p, mu0, log l_r, log s_out, log sigma_zz,
log sigma_xz; the last two the white noise of the two data components; theta[5], theta[7] and
theta[8] are placeholders, not used while tied) maximise the evidence (closed form,
Gaussian), with its analytic gradient.

Hyperparameter uncertainty.  ``propagate`` takes the Hessian of the log-evidence over the free
log-hyperparameters (central differences of the analytic gradient), its inverse Sigma_theta
(the Laplace approximation to their posterior under a flat prior), the Jacobian J of the
posterior mean of the tractions with respect to them (central differences) and returns the
covariance S + J Sigma_theta J^T: the first-order total variance of the tractions once the
hyperparameters are integrated over rather than fixed at their maximum.  A length at a bound
of its search (l_p at its cap, the evidence flat toward a rigid p) is integrated on a
grid instead (``propagate``).  l_p itself is integrated on the evidence's profile (``_modes``:
the other hyperparameters re-maximised at each l_p, as the window moves with it), and
``propagate`` then integrates the others at each profile point.
"""
from __future__ import annotations

import math

import numpy as np

from .inverse_evidence import (
    KERNEL_NU,
    _logistic,
    _maximise,
    _noise_gradient,
    _noise_guess,
    _posterior,
    _statistics,
)
from .inverse_evidence import _matern52 as _matern

__all__ = ["ContactPrior", "optimise_contact", "propagate", "PRIOR_NAMES"]

PRIOR_NAMES = ("centre", "log_half_width", "log_s_p", "log_l_p", "mu0", "log_s_r", "log_l_r",
               "log_s_t", "log_l_t", "log_s_out", "log_noise_zz", "log_noise_xz")
_N = len(PRIOR_NAMES)
NOISE_FLOOR = 1e-3
"""Smallest noise sd, relative to the data's peak, times sqrt(node step / sample step) when the
samples are finer than the nodes.  On a clean record the forward map's own error (hats on a
square-root edge: ~1e-3 of the peak, correlated over a node step) is the noise; treated as
white noise on samples finer than that, it would count as more information than it is (by the
ratio of the steps), and the evidence then buys a rough, large prior that fits the
discretisation (measured: L2 130 % on the solver's 8192-sample clean record at a floor of 1e-3,
1-2 % with the factor)."""


def model_error_floor(sample_step_h):
    """The noise floor (relative to the data's peak, per sample of step ``sample_step_h`` [h])
    that both priors' likelihoods share (``NOISE_FLOOR`` at the contact prior's fine node step
    ``FINE_STEP_H``): the forward map's own error, a model-error term, not a measurement's.
    Measured on the solver's noise-free record (load 200 N/m, mu 1, averaged to steps of
    0.029 h): the base response of the exact tractions minus that of their hat interpolant on
    h/16 nodes has rms 5.4e-4 (zz) and 3.3e-4 (xz) of the peak, largest 1.9e-3, correlated over
    ~h; a semi-ellipse on the same window gives 6.1e-4 and 3.6e-4; on h/8 nodes 1.6e-3 and
    1.1e-3.  The envelope prior (h/8 nodes, rough edge parts) otherwise fits a noise-free
    record to 4e-6 of its peak and wins the evidence by that alone (7600 nats; its window 0.5
    mm wide of the truth, Q 4 sigma off); under the common floor the evidences compare the
    priors on the tractions."""
    return NOISE_FLOOR * math.sqrt(max(1.0, FINE_STEP_H / sample_step_h))


TIE_MU_PART = True
"""The varying-mu part's prior sd is s_p (module docstring)."""
_ROUND = 0.25
"""The window's edges are rounded over this fraction of a node step."""


def rounding_offset(dt):
    """How far [h] outside the window's nominal edge c +- w0 its rounded profile's square-root
    edge lies, for nodes dt [h] apart: near an edge z = 1 - u^2 = 2 s / w0 (s the distance
    inside), and the softplus's value there, eps ln 2 with eps = _ROUND dt / w0, is the sharp
    window's at s = ln 2 _ROUND dt / 2 (0.087 node steps).  The fit matches the truth's edge with
    the rounded profile, so its nominal edge sits that far inside (measured: rounding at 0.02
    instead of 0.25 of a node step moved the noise-free edges out by 2-16 um, predicted 10 um at
    h = 2 mm); the reported interval adds it back."""
    return math.log(2.0) * _ROUND * dt / 2.0


def _matern52(t, length):
    """Matern-5/2 correlation on nodes t and its derivative with respect to log(length)."""
    return _matern(t, length, 2.5)


def _softplus(z, eps):
    return eps * np.logaddexp(0.0, z / eps)


class ContactPrior:
    """Sufficient statistics of a record for the contact prior; log-evidence, gradient and the
    posterior (see the module docstring).  ``fwd``: ``LineForward``; dz, dx: the data (scaled);
    ``known``: the window is the node span (a known support)."""

    def __init__(self, fwd, dz, dx, known=False):
        _statistics(self, fwd, dz, dx)
        self.dt = float(self.t[1] - self.t[0])
        self.known = known
        self._cache = {}
        self.lp_max = None  # the cap on l_p [h] (``LP_MAX_WIDTH``); None: the search's 20 h
        self._ones = np.ones((self.m, self.m))
        self._zeros = np.zeros((self.m, self.m))

    # -- prior covariance and its derivatives -------------------------------------------------
    def window(self, th):
        """(w, dw/dc, dw/dlog w0, I, dI/dc, dI/dlog w0) on the nodes."""
        t = self.t
        c, w0 = th[0], math.exp(th[1])
        u = (t - c) / w0
        z = 1.0 - u * u
        dz_dc, dz_dl = 2.0 * u / w0, 2.0 * u * u
        if self.known:
            w = np.sqrt(np.clip(z, 0.0, None))
            one = np.ones_like(t)
            zero = np.zeros_like(t)
            return w, zero, zero, one, zero, zero
        eps = _ROUND * self.dt / w0
        sp = _softplus(z, eps) + 1e-30
        w = np.sqrt(sp)
        # d sp / d theta = sigma(z/eps) dz/dtheta + (d eps/dtheta)(sp/eps - z sigma / eps);
        # eps depends on w0 only (d eps / d log w0 = -eps)
        sig = _logistic(z / eps)
        dsp_dl = sig * dz_dl - (sp - z * sig)
        dw_dc = sig * dz_dc / (2.0 * w)
        dw_dl = dsp_dl / (2.0 * w)
        ind = sig
        dind = sig * (1.0 - sig) / eps
        di_dc = dind * dz_dc
        di_dl = dind * (dz_dl + z)  # d(z/eps)/dlog w0 = dz_dl/eps + z/eps
        return w, dw_dc, dw_dl, ind, di_dc, di_dl

    def _corr(self, length):
        key = round(length, 14)
        c = self._cache.get(key)
        if c is None:
            if len(self._cache) > 64:
                self._cache.clear()
            c = self._cache[key] = _matern52(self.t, length)
        return c

    def covariance(self, th):
        """Prior covariance blocks: Kp (of p), Kr (of q - mu0 p), and the pieces for the
        gradient."""
        m = self.m
        w, dwc, dwl, ind, dic, dil = self.window(th)
        sp2, so2 = (math.exp(2 * th[k]) for k in (2, 9))
        s_r2 = sp2 if TIE_MU_PART else math.exp(2 * th[5])
        st2 = sp2  # the step's prior sd is the pressure's amplitude (theta[7] not used)
        Cp, dCp = self._corr(math.exp(th[3]))
        Cr, dCr = self._corr(math.exp(th[6]))
        Ct, dCt = self._ones, self._zeros  # the step part is one constant (l_t not used)
        eye = np.eye(m)
        Ap = w[:, None] * Cp * w[None, :]
        Ar = w[:, None] * Cr * w[None, :]
        At = ind[:, None] * Ct * ind[None, :]
        Kp = sp2 * Ap + so2 * eye
        Kr = s_r2 * Ar + st2 * At + so2 * eye
        return Kp, Kr, dict(w=w, dwc=dwc, dwl=dwl, ind=ind, dic=dic, dil=dil, sp2=sp2, sr2=s_r2,
                            st2=st2, so2=so2, Cp=Cp, dCp=dCp, Cr=Cr, dCr=dCr, Ct=Ct, dCt=dCt,
                            Ap=Ap, Ar=Ar, At=At)

    # -- evidence -----------------------------------------------------------------------------
    def evaluate(self, th, grad=False, full=False):
        """log-evidence [, gradient (len 12)] [, (mean, covariance, H)] of the nodal (p, q)."""
        m = self.m
        mu0 = th[4]
        nz, nx = math.exp(th[10]), math.exp(th[11])
        Kp, Kr, pc = self.covariance(th)
        jit = 1e-10 * max(float(np.max(np.diag(Kp))), float(np.max(np.diag(Kr))))
        Kp[np.diag_indices(m)] += jit
        Kr[np.diag_indices(m)] += jit
        Lp = np.linalg.cholesky(Kp)
        Lr = np.linalg.cholesky(Kr)
        Lk = np.zeros((2 * m, 2 * m))
        Lk[:m, :m] = Lp
        Lk[m:, :m] = mu0 * Lp
        Lk[m:, m:] = Lr

        def lthl(H):
            # Lk^T H Lk by m x m blocks (Lk = [[Lp, 0], [mu0 Lp, Lr]]): 7 products of m x m
            # instead of 2 of 2m x 2m (a fifth of an evaluation's time)
            H11, H12, H22 = H[:m, :m], H[:m, m:], H[m:, m:]
            T1 = Lp.T @ (H11 + mu0 * H12.T)
            T2 = Lp.T @ (H12 + mu0 * H22)
            B = np.empty((2 * m, 2 * m))
            B[:m, :m] = (T1 + mu0 * T2) @ Lp
            B[:m, m:] = T2 @ Lr
            B[m:, :m] = B[:m, m:].T
            B[m:, m:] = Lr.T @ H22 @ Lr
            return B

        logev, post = _posterior(self, Lk, lthl, nz, nx, th[10] + th[11], grad, full)
        if post is None:
            return logev
        mean, S, H, Wm = post  # d logev = 1/2 tr(Wm dK) (``inverse_evidence._evidence_weight``)
        out = [logev]
        if grad:
            g = np.zeros(_N)
            Wpp, Wpq, Wqq = Wm[:m, :m], Wm[:m, m:], Wm[m:, m:]
            Wp = Wpp + 2.0 * mu0 * Wpq + mu0 * mu0 * Wqq  # K_f = [[Kp, mu0 Kp], [., mu0^2 Kp + Kr]]
            Wp = 0.5 * (Wp + Wp.T)
            w = pc["w"]
            g[2] = float(np.sum(Wp * pc["Ap"])) * pc["sp2"]
            g[3] = 0.5 * pc["sp2"] * float(np.sum(Wp * (w[:, None] * pc["dCp"] * w[None, :])))
            g[4] = float(np.sum(Wpq * Kp)) + mu0 * float(np.sum(Wqq * Kp))
            g[5] = float(np.sum(Wqq * pc["Ar"])) * pc["sr2"]
            if TIE_MU_PART:
                g[2] += g[5]
                g[5] = 0.0
            g[6] = 0.5 * pc["sr2"] * float(np.sum(Wqq * (w[:, None] * pc["dCr"] * w[None, :])))
            ind = pc["ind"]
            g[2] += float(np.sum(Wqq * pc["At"])) * pc["st2"]  # the step's sd is s_p
            g[8] = 0.5 * pc["st2"] * float(np.sum(Wqq * (ind[:, None] * pc["dCt"] * ind[None, :])))
            g[9] = pc["so2"] * float(np.trace(Wp) + np.trace(Wqq))
            if not self.known:
                # d(W C W) = dW C W + W C dW: 1/2 tr(X d(WCW)) = dw . ((X * C) @ w)
                vp = pc["sp2"] * ((Wp * pc["Cp"]) @ w) + pc["sr2"] * ((Wqq * pc["Cr"]) @ w)
                vt = pc["st2"] * ((Wqq * pc["Ct"]) @ ind)
                g[0] = float(pc["dwc"] @ vp + pc["dic"] @ vt)
                g[1] = float(pc["dwl"] @ vp + pc["dil"] @ vt)
            _noise_gradient(g, (10, 11), self, nz, nx, mean, S)
            out.append(g)
        if full:
            out.append((mean, S, H))
        return tuple(out)


def _bounds(ev: ContactPrior, scale, noise_floor=None):
    t, dt = ev.t, ev.dt
    x = ev.fwd.x
    dxh = float(x[-1] - x[0]) / (x.size - 1)
    floor = (NOISE_FLOOR if noise_floor is None else noise_floor) * math.sqrt(max(1.0, dt / dxh))
    span = float(t[-1] - t[0])
    lmin, lmax = math.log(max(dt, 0.05)), math.log(20.0)
    amin, amax = math.log(1e-5 * scale), math.log(1e3 * scale)
    lpmax = lmax if ev.lp_max is None else max(min(lmax, math.log(ev.lp_max)), lmin)
    lo = np.array([t[0], math.log(2 * dt), amin, lmin, -5.0, amin, lmin, amin, lmin,
                   math.log(1e-7 * scale), math.log(floor * scale), math.log(floor * scale)])
    hi = np.array([t[-1], math.log(0.5 * span), amax, lpmax, 5.0, amax, lmax, amax, lmax,
                   amax, math.log(10 * scale), math.log(10 * scale)])
    return lo, hi


def _start(ev: ContactPrior, dz, dx, c0, w0):
    """A start for the hyperparameters: the window (c0, w0) [h]; p's amplitude from the data's
    peak, lengths the window's half-width, mu0 the ratio of the data's integrals, the noise sd
    from second differences (clipped to the search's bounds)."""
    scale = max(float(np.max(np.abs(dz))), float(np.max(np.abs(dx))), 1e-300)
    lo, hi = _bounds(ev, scale)
    nz0 = min(max(_noise_guess(dz), 1e-4 * scale), 0.3 * scale)
    nx0 = min(max(_noise_guess(dx), 1e-4 * scale), 0.3 * scale)
    Iz, Ix = float(np.sum(dz)), float(np.sum(dx))
    mu00 = float(np.clip(Ix / Iz, -4.0, 4.0)) if Iz > 0 else 0.0
    sp0 = 1.3 * float(np.max(np.abs(dz)))
    ln = math.log(max(w0, 0.1))
    th0 = np.array([c0, math.log(w0), math.log(sp0), ln, mu00, math.log(0.05 * sp0), ln,
                    math.log(0.05 * sp0), ln, math.log(1e-3 * sp0), math.log(nz0),
                    math.log(nx0)])
    return np.clip(th0, lo, hi)


def _data_window(ev: ContactPrior, dz):
    """(a0, b0) [h]: where d_zz exceeds a quarter of its peak (the record's ends if nowhere)."""
    x = ev.fwd.x
    big = dz > 0.25 * np.max(dz)
    if big.any():
        return float(x[big].min()), float(x[big].max())
    return float(x[0]), float(x[-1])


SCAN_STEP_H = 0.5
"""Step [h] of the first pass's scan of the window's centre."""
SCAN_WIDTHS = (0.4, 0.7, 1.0, 1.4)
"""Half-widths of the first pass's scan, times the data's half-width."""


def scan_windows(ev: ContactPrior, dz, dx):
    """The first pass's start: the log-evidence at the start hyperparameters (``_start``) over
    a grid of windows, centres every ``SCAN_STEP_H`` h from 1 h before to 1 h after the data's
    window (``_data_window``), half-widths ``SCAN_WIDTHS`` times the data's half-width; returns
    the best (theta, log-evidence).  (The data's window alone misplaces the contact when the
    shear is large: the B coupling moves d_zz's peak; on the example U profile, mu = 2, every
    start from it went to a window beyond the record's edge, 150 nats below the contact's.)
    Cost: ~30 evaluations without gradient, about that of 10 with it."""
    a0, b0 = _data_window(ev, dz)
    hw = max(0.5 * (b0 - a0), 2.0 * ev.dt)
    best = (None, -np.inf)
    for c in np.arange(a0 - 1.0, b0 + 1.0 + 1e-9, SCAN_STEP_H):
        for f in SCAN_WIDTHS:
            th = _start(ev, dz, dx, c, max(f * hw, 2.0 * ev.dt))
            try:
                v = ev.evaluate(th)
            except np.linalg.LinAlgError:
                continue
            if np.isfinite(v) and v > best[1]:
                best = (th, v)
    return best


OPT_FTOL = 1e-7
"""L-BFGS-B's relative tolerance on the log-evidence (~3e-4 nats at the calibration records'
~3000), with a projected-gradient tolerance ``OPT_GTOL``: the hyperparameters' own Laplace sd
are 1e-2 ... 1 in their logs, so the posterior does not change at that level (was 1e-11 and
1e-4: 20-40 % more evaluations for changes below 0.01 nats)."""
OPT_GTOL = 1e-2


def optimise_contact(ev: ContactPrior, dz, dx, window=None, start=None, noise_floor=None,
                     gtol=OPT_GTOL, hold=()):
    """Maximum of the log-evidence over the hyperparameters (L-BFGS-B, analytic gradient), from
    ``start`` (a full theta), or from ``_start`` at the window ``window`` (c, w0) [h], at the
    known support, or at the best window of ``scan_windows``; ``hold``: indices held at the
    start's values (not in the returned free mask's search).  Returns (theta, log-evidence,
    free mask)."""
    scale = max(float(np.max(np.abs(dz))), float(np.max(np.abs(dx))), 1e-300)
    lo, hi = _bounds(ev, scale, noise_floor)
    free = np.ones(_N, bool)
    free[[7, 8]] = False  # the step part is a constant of prior sd s_p
    if TIE_MU_PART:
        free[5] = False
    if ev.known:
        free[[0, 1]] = False
        c0, w00 = 0.5 * (ev.t[0] + ev.t[-1]), 0.5 * (ev.t[-1] - ev.t[0])
    search = free.copy()
    search[list(hold)] = False
    if start is not None:
        th0 = np.clip(start.copy(), lo, hi)
        if ev.known:
            th0[[0, 1]] = c0, math.log(w00)
    elif ev.known:
        th0 = _start(ev, dz, dx, c0, w00)
    elif window is not None:
        th0 = _start(ev, dz, dx, *window)
    else:
        th0, _ = scan_windows(ev, dz, dx)
        if th0 is None:
            raise np.linalg.LinAlgError("the evidence could not be evaluated at any window")
    th, v = _maximise(ev, np.clip(th0, lo, hi), search, lo, hi, maxiter=400, ftol=OPT_FTOL,
                      gtol=gtol)
    if th is None:
        raise np.linalg.LinAlgError("the evidence could not be evaluated at the start")
    return th, v, free


def _scan_edges(ev: ContactPrior, th, reach=1.0, step=0.125, value=None):
    """The window's edges, one at a time, over +- ``reach`` [h] at ``step`` with the other
    hyperparameters held: the evidence can have a second maximum in an edge's position (the
    film blurs the edge over ~h) that a local search started on the wrong side does not leave.
    ``value``: the log-evidence at th if known.  Returns (theta, log-evidence) of the best point
    seen."""
    best, bv = th, (ev.evaluate(th) if value is None else value)
    for side in (-1.0, 1.0):
        a, b = best[0] - math.exp(best[1]), best[0] + math.exp(best[1])
        for d in np.arange(-reach, reach + 1e-9, step):
            aa, bb = (a + d, b) if side < 0 else (a, b + d)
            if bb - aa < 4 * ev.dt:
                continue
            t = best.copy()
            t[0], t[1] = 0.5 * (aa + bb), math.log(0.5 * (bb - aa))
            try:
                v = ev.evaluate(t)
            except np.linalg.LinAlgError:
                continue
            if v > bv:
                best, bv = t, v
    return best, bv


def propagate(ev: ContactPrior, theta, free, mean, S, step=1e-3, centre=None):
    """The nodal tractions' mean and covariance with the hyperparameters integrated over.

    Interior hyperparameters: Laplace, S + J Sigma_theta J^T (module docstring).  A length (l_p,
    l_r) at a bound of the search (typically l_p at its cap: the evidence is flat toward an
    infinitely smooth p, where the Laplace width is not defined) is integrated numerically
    instead: a log-uniform prior on a grid of ``BOUND_GRID`` in log l inward from the bound,
    each point's posterior weighted by its evidence (the other hyperparameters held); the
    mixture's mean and covariance (within plus between the points) replace the fixed-l ones.
    Other hyperparameters at a bound are held.  ``centre`` = (log-evidence, gradient) at theta
    (from the caller's evaluation that gave mean and S): then the bound grid's first point is
    theta's own posterior and the Laplace step's differences are one-sided from theta (d
    evaluations instead of 2 d; the step, 1e-3 in the logs, is far below the hyperparameters'
    Laplace sd of 1e-2 ... 1).  Returns (mean, covariance, Sigma_theta over the interior
    hyperparameters, their indices)."""
    lo, hi = _bounds(ev, 1.0)
    # bounds were made for the scaled data: scale 1 is the data's scale in the core
    idx = [k for k in np.nonzero(free)[0]
           if lo[k] + 1e-6 < theta[k] < hi[k] - 1e-6]
    mean_out, S_out = mean.copy(), S.copy()
    for k in (3, 6):
        if not free[k] or k in idx:
            continue
        inward = -1.0 if theta[k] >= hi[k] - 1e-6 else 1.0
        vals = theta[k] + inward * BOUND_GRID
        vals = vals[(vals >= lo[k] - 1e-9) & (vals <= hi[k] + 1e-9)]
        les, ms, Ss = [], [], []
        for v in vals:
            if centre is not None and v == theta[k]:
                les.append(centre[0])
                ms.append(mean)
                Ss.append(S)
                continue
            t = theta.copy()
            t[k] = v
            try:
                le, (mk, Sk, _) = ev.evaluate(t, full=True)
            except np.linalg.LinAlgError:
                continue
            les.append(le)
            ms.append(mk)
            Ss.append(Sk)
        if len(les) < 2:
            continue
        wts = np.exp(np.array(les) - max(les))
        wts /= wts.sum()
        mbar = sum(w * mk for w, mk in zip(wts, ms))
        Smix = sum(w * (Sk + np.outer(mk - mbar, mk - mbar)) for w, mk, Sk in zip(wts, ms, Ss))
        mean_out += mbar - mean
        S_out += Smix - S
    d = len(idx)
    if d == 0:
        return mean_out, S_out, np.zeros((0, 0)), idx
    Hs = np.zeros((d, d))
    J = np.zeros((mean.size, d))
    for a, k in enumerate(idx):
        tp = theta.copy()
        tp[k] += step
        _, gp, (mp, _, _) = ev.evaluate(tp, grad=True, full=True)
        if centre is not None:
            Hs[:, a] = -(gp[idx] - centre[1][idx]) / step
            J[:, a] = (mp - mean) / step
            continue
        tm = theta.copy()
        tm[k] -= step
        _, gm, (mm, _, _) = ev.evaluate(tm, grad=True, full=True)
        Hs[:, a] = -(gp[idx] - gm[idx]) / (2 * step)
        J[:, a] = (mp - mm) / (2 * step)
    Hs = 0.5 * (Hs + Hs.T)
    w, V = np.linalg.eigh(Hs)
    # a direction of non-positive curvature (a flat evidence) carries no Laplace width: drop it
    keep = w > 1e-8 * max(float(w.max()), 1e-300)
    Sig = (V[:, keep] / w[keep]) @ V[:, keep].T
    return mean_out, S_out + J @ Sig @ J.T, Sig, idx


BOUND_GRID = np.arange(0.0, 4.01, 0.5)
"""Steps in log(length) inward from a bound at which ``propagate`` integrates a length."""


COARSE_STEP_H = 0.25
"""Node step [h] of the first pass (the window's search over the whole record)."""
FINE_STEP_H = 1.0 / 16.0
"""Node step [h] of the second pass (the square-root edges want nodes finer than the film's
resolution: h/8 leaves 1-2 % of L2 error and biased windows that h/16 removes)."""
EDGE_SPAN_H = 0.75
"""The second pass's nodes cover the first pass's window widened by this [h] on each side;
the tractions are zero beyond (the contact prior's own statement, bar its nugget)."""


LP_MAX_WIDTH = 2.0
"""p's length l_p is at most this many window half-widths (the contact's width; module
docstring): the first pass's window, or the known support."""


def fit_contact(xh, film, symbols, zs, xs, support=None):
    """Two passes: coarse nodes over the record +- MARGIN_H (the window's search: a scan of
    windows, one local search from the best, an edge scan), then fine nodes on the window +-
    EDGE_SPAN_H from the first pass's optimum (l_p capped at LP_MAX_WIDTH of its half-width):
    a local search from that optimum (l_p held first), an edge scan, a second local search
    from the fine nodes' own scan of windows (the higher maximum kept), and the evidence's
    profile over l_p (``_modes``), whose points ``invert_line`` mixes by evidence.
    Returns (forward map, ContactPrior, [(theta, log-evidence), ...] best first, free mask)."""
    from .inverse_forward import MARGIN_H, LineForward

    if support is not None:
        fwd = LineForward.build(xh, film, symbols, support=support,
                                step=min(FINE_STEP_H, (support[1] - support[0]) / 8))
        ev = ContactPrior(fwd, zs, xs, known=True)
        ev.lp_max = LP_MAX_WIDTH * 0.5 * (support[1] - support[0])
        th, le, free = optimise_contact(ev, zs, xs)
        return fwd, ev, _modes(ev, zs, xs, th, le, free), free
    fwd = LineForward.build(xh, film, symbols, step=COARSE_STEP_H)
    ev = ContactPrior(fwd, zs, xs)
    th, le, free = optimise_contact(ev, zs, xs)
    th, le = _scan_edges(ev, th, reach=1.5, step=0.25, value=le)
    c, w0 = th[0], math.exp(th[1])
    lo = max(c - w0 - EDGE_SPAN_H, xh[0] - MARGIN_H)
    hi = min(c + w0 + EDGE_SPAN_H, xh[-1] + MARGIN_H)
    fwd = LineForward.build(xh, film, symbols, step=FINE_STEP_H, span=(lo, hi))
    ev = ContactPrior(fwd, zs, xs)
    ev.lp_max = LP_MAX_WIDTH * w0
    # the others first at the first pass's l_p (clipped to the cap), then all: a joint search
    # from the coarse optimum jumped, on the solver's noise-free record, to a basin of an
    # enormous amplitude (s_p ~ 400 x the data's peak, mu0 4.4) ~60 nats below this route's
    th, le, free = optimise_contact(ev, zs, xs, start=th, hold=(3,))
    th, le, free = optimise_contact(ev, zs, xs, start=th)
    for _ in range(2):  # leave a wrong side of a bimodal edge
        t2, v2 = _scan_edges(ev, th, value=le)
        if v2 <= le + 0.01:
            break
        th, le, free = optimise_contact(ev, zs, xs, start=t2)
    # a second start on the fine nodes, from their own scan of windows: the first pass's
    # coarse window can hold the search in a basin whose edge lies ~h outside the contact (a
    # varying-mu base record: left edge 0.84 mm out, 6.8 nats below this start's maximum)
    t2, v2, f2 = optimise_contact(ev, zs, xs)
    if v2 > le + 0.01:
        th, le, free = t2, v2, f2
    return fwd, ev, _modes(ev, zs, xs, th, le, free), free


def _modes(ev, zs, xs, th, le, free=None):
    """The maximum (th, le) and the profile of the evidence over log l_p: l_p stepped by
    ``PROFILE_STEP`` in its log both ways from the maximum (to the search's bounds, l_p's cap
    ``LP_MAX_WIDTH`` above, at most
    ``PROFILE_POINTS`` a side, until the evidence falls ``MODE_NATS`` below the best seen),
    the other hyperparameters maximised at each step (warm-started from the previous one).
    These points, on a uniform grid in log l_p, are the quadrature nodes of l_p's integral
    (log-uniform prior: weights exp(log-evidence)); ``invert_line`` mixes their posteriors,
    each with the other hyperparameters' Laplace propagation.  Why: the evidence can be nearly
    flat in l_p over a factor 10 (a rigid p with the shape's detail in the varying-mu part, or
    a flexible p with a smooth mu: the data do not tell them apart), and the window moves with
    l_p (on the varying-mu sensor records by 0.1-0.15 mm, several of its Laplace sd at the
    rigid end): a Laplace step at one maximum, or a grid in l_p with the window held, misses
    that.  Returns [(theta, log-evidence), ...] best first, within MODE_NATS of the best."""
    if free is None:
        free = np.ones(_N, bool)
        free[[5, 7, 8]] = False
        if ev.known:
            free[[0, 1]] = False
    lo, hi = _bounds(ev, 1.0)  # the core's data are scaled to a peak of 1
    fr = free.copy()
    fr[3] = False
    pts = [(th, le)]
    for direction in (1.0, -1.0):
        t = th
        for k in range(1, PROFILE_POINTS + 1):
            v = th[3] + direction * k * PROFILE_STEP
            if not lo[3] - 1e-9 <= v <= hi[3] + 1e-9:
                break
            t0 = t.copy()
            t0[3] = v
            t, val = _maximise(ev, t0, fr, lo, hi, maxiter=200, ftol=OPT_FTOL, gtol=OPT_GTOL)
            if t is None:
                break
            pts.append((t, val))
            if val < max(q[1] for q in pts) - MODE_NATS:
                break
    best = max(q[1] for q in pts)
    return sorted([q for q in pts if q[1] >= best - MODE_NATS], key=lambda q: -q[1])


PROFILE_STEP = 0.5
"""Step of the evidence's profile in log l_p (a factor 1.65)."""
PROFILE_POINTS = 6
"""At most this many profile steps on each side of the maximum."""
MODE_NATS = 5.0
"""Profile points this far below the best (weight e^-5 < 1 %) are dropped."""


def regularisation_record(prior, theta, free, scale, h, hyper):
    """The prior ("contact" or "envelope") and its hyperparameters theta in SI (the JSON's
    ``regularisation`` of ``inverse.invert_line``): scale [Pa] and h [m] the core's units."""
    e = np.exp
    if prior == "contact":
        c, w0 = theta[0] * h, e(theta[1]) * h
        return {"prior": "contact: p = sqrt-edged window x Matern-5/2 process; q = mu0 p + "
                         "sqrt-edged x Matern-5/2 + window x Matern-5/2; white nugget",
                "window_m": [float(c - w0), float(c + w0)] if free[0] else None,
                "amplitude_p_Pa": float(e(theta[2]) * scale), "length_p_m": float(e(theta[3]) * h),
                "mu0": float(theta[4]),
                "amplitude_mu_part_Pa": float(e(theta[2] if TIE_MU_PART else theta[5]) * scale),
                "length_mu_part_m": float(e(theta[6]) * h),
                "amplitude_step_part_Pa": float(e(theta[2]) * scale),
                "nugget_Pa": float(e(theta[9]) * scale),
                "chosen_by": "maximum evidence (marginal likelihood)",
                "hyperparameter_uncertainty": ("propagated (Laplace over the log-hyperparameters)"
                                               if hyper else "not propagated")}
    return {"prior": f"envelope: p, q Matern-{2 * KERNEL_NU:g}/2 Gaussian processes inside an "
                     f"envelope + exponential-correlation process at its edges, zero mean",
            "rough_amplitude_p_Pa": float(e(theta[10]) * scale),
            "rough_amplitude_q_Pa": float(e(theta[11]) * scale),
            "rough_length_m": float(e(theta[12]) * h),
            "length_p_m": float(e(theta[0]) * h), "length_q_m": float(e(theta[1]) * h),
            "amplitude_p_Pa": float(e(theta[2]) * scale), "amplitude_q_Pa": float(e(theta[3]) * scale),
            "amplitude_outside_Pa": float(e(theta[4]) * scale) if free[4] else None,
            "window_m": ([float((theta[7] - e(theta[8])) * h), float((theta[7] + e(theta[8])) * h)]
                         if free[7] else None),
            "window_edge_m": float(e(theta[9]) * h) if free[9] else None,
            "chosen_by": "maximum evidence (marginal likelihood)",
            "hyperparameter_uncertainty": "not propagated"}
