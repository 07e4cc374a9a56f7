"""The line inverse's prior, evidence and posterior (issue 21): the Gaussian-process prior
inside an evidence-placed envelope, its log-evidence with the analytic gradient, the
maximisation over the hyperparameters, the positivity mode and the contact interval.
See ``instruments.inverse`` for the model as a whole."""
from __future__ import annotations

import math

import numpy as np

from .inverse_forward import LineForward

__all__ = ["KERNEL_NU", "ENVELOPE_EDGE_MIN_H"]

KERNEL_NU = 0.5
"""Smoothness of the Matern prior (1/2, 3/2 or 5/2)."""
ENVELOPE_EDGE_MIN_H = 0.25
"""Smallest width e [h] of the prior's envelope edges."""


def _matern52(t, length, nu=None):
    """Matern correlation (nu = 1/2, 3/2, 5/2) on nodes t and its derivative with respect to
    log(length)."""
    nu = KERNEL_NU if nu is None else nu
    d = np.abs(t[:, None] - t[None, :]) / length
    if nu == 0.5:
        e = np.exp(-d)
        return e, d * e
    if nu == 1.5:
        r = math.sqrt(3.0) * d
        e = np.exp(-r)
        return (1.0 + r) * e, r * r * e
    r = math.sqrt(5.0) * d
    e = np.exp(-r)
    return (1.0 + r + r * r / 3.0) * e, (r * r * (1.0 + r) / 3.0) * e


def _logistic(u):
    return 0.5 * (1.0 + np.tanh(0.5 * u))


def _statistics(ev, fwd, dz, dx):
    """The record's sufficient statistics for a Gaussian prior on the nodal tractions, set on
    ``ev``: G_c = M_c^T M_c, b_c = M_c^T d_c, e_c = |d_c|^2 (c = z, x), n, the nodes t and m."""
    ev.fwd = fwd
    Mz = np.hstack([fwd.Mzp, fwd.Mzq])
    Mx = np.hstack([fwd.Mxp, fwd.Mxq])
    ev.Gz, ev.Gx = Mz.T @ Mz, Mx.T @ Mx
    ev.bz, ev.bx = Mz.T @ dz, Mx.T @ dx
    ev.ez, ev.ex = float(dz @ dz), float(dx @ dx)
    ev.n = dz.size
    ev.t = fwd.nodes
    ev.m = ev.t.size


# --- the linear-Gaussian core shared by the envelope prior (here) and the contact prior
# (``inverse_prior``): nodal tractions f ~ N(0, Lk Lk^T), data d = M f + white noise of sd
# sigma_c per component c (zz, xz), summarised by H = sum_c M_c^T M_c / sigma_c^2 and
# b = sum_c M_c^T d_c / sigma_c^2.

def _gaussian_evidence(Lk, H, b, quad0, n, log_noise_sum, B=None):
    """log-evidence, the Cholesky factor Lb of B = I + Lk^T H Lk (``B`` if given, without the
    identity) and the posterior mean.  quad0 = sum_c |d_c|^2 / sigma_c^2; n samples per
    component; log_noise_sum = log sigma_zz + log sigma_xz."""
    if B is None:
        B = Lk.T @ H @ Lk
    B[np.diag_indices_from(B)] += 1.0
    Lb = np.linalg.cholesky(B)
    beta = Lk.T @ b
    alpha = _cho(Lb, beta)
    mean = Lk @ alpha
    logdet = 2.0 * np.sum(np.log(np.diag(Lb)))
    logev = (-0.5 * (quad0 - beta @ alpha) - 0.5 * logdet - n * log_noise_sum
             - n * math.log(2.0 * math.pi))
    return logev, Lb, mean


def _posterior_covariance(Lb, Lk):
    """S = Lk B^-1 Lk^T, the posterior covariance of the nodal tractions."""
    from scipy.linalg import solve_triangular

    Li = solve_triangular(Lb, Lk.T, lower=True)
    return Li.T @ Li


def _evidence_weight(H, b, mean, S):
    """W with d logev = 1/2 tr(W dK) for a change dK of the prior covariance:
    W = K^-1 (mean mean^T + S) K^-1 - K^-1 = Km Km^T - H + H S H, Km = K^-1 mean = b - H mean,
    (K + H^-1)^-1 = H - H S H (Woodbury): no inverse of the (ill-conditioned) prior covariance."""
    Km = b - H @ mean
    W = np.outer(Km, Km) - H + (H @ S) @ H
    return 0.5 * (W + W.T)


def _noise_gradient(g, ks, ev, nz, nx, mean, S):
    """d logev / d log sigma_c = -n + (|d_c - M_c mean|^2 + tr(G_c S)) / sigma_c^2 into g[k]
    for the components (zz, xz) and indices ks of their log sd (statistics of ``ev``)."""
    for k, G, bb, ee, sig in ((ks[0], ev.Gz, ev.bz, ev.ez, nz), (ks[1], ev.Gx, ev.bx, ev.ex, nx)):
        rr = ee - 2.0 * mean @ bb + mean @ G @ mean + np.sum(G * S)
        g[k] = -ev.n + rr / sig**2


def _posterior(ev, Lk, lthl, nz, nx, log_noise_sum, grad, full):
    """log-evidence and, if ``grad`` or ``full``, (mean, S, H, W) (W None without ``grad``) of
    the record's statistics ``ev`` under the prior factor Lk and noise sd (nz, nx);
    ``lthl(H)`` returns Lk^T H Lk (each prior by its own block structure)."""
    H = ev.Gz / nz**2 + ev.Gx / nx**2
    b = ev.bz / nz**2 + ev.bx / nx**2
    logev, Lb, mean = _gaussian_evidence(Lk, H, b, ev.ez / nz**2 + ev.ex / nx**2, ev.n,
                                         log_noise_sum, lthl(H))
    if not (grad or full):
        return logev, None
    S = _posterior_covariance(Lb, Lk)
    return logev, (mean, S, H, _evidence_weight(H, b, mean, S) if grad else None)


# hyperparameters: log l_p, log l_q, log s_p, log s_q, log s_out, log sigma_zz, log sigma_xz,
# c, log hw (envelope centre and half-width, h), log e (envelope edge width, h),
# log r_p, log r_q (amplitudes of the rough edge component), log l_r (its length)
_NPAR = 13


class _Evidence:
    """Sufficient statistics of a record for the Gaussian model; log-evidence and its gradient.

    Prior, for each traction f in (p, q): the sum of two independent zero-mean Gaussian
    processes, a smooth one D_f C(l_f) D_f (C the Matern-``KERNEL_NU`` correlation) and a
    rough one at the contact's edges E_f C_1/2(l_r) E_f (exponential correlation: continuous,
    nowhere differentiable, as sqrt edges and steps are), with D = diag(s(t)),
    s(t)^2 = s_f^2 w(t) + s_out^2 and E = diag(e(t)), e(t)^2 = r_f^2 4 w(t) (1 - w(t)), where
    w = logistic((t - a)/e) logistic((b - t)/e) is an envelope whose window [a, b] and edge width
    e are hyperparameters: amplitude s_f inside, s_out outside, and the roughness where the
    contact ends (the evidence places the window, so no support is assumed).  With a known
    support w = 1 on it, s_out is not used and the rough part has a uniform amplitude r_f."""

    def __init__(self, fwd: LineForward, dz, dx, envelope=True):
        _statistics(self, fwd, dz, dx)
        self.envelope = envelope
        self.jitter = 1e-8

    def _amplitudes(self, th):
        """Amplitude profiles (s, e) of the smooth and rough parts (p and q stacked) and their
        derivatives {k: (ds/dtheta_k, de/dtheta_k)}."""
        t = self.t
        z = 0.0 * t
        s_in_p, s_in_q, s_out = math.exp(th[2]), math.exp(th[3]), math.exp(th[4])
        r_p, r_q = math.exp(th[10]), math.exp(th[11])
        if not self.envelope:
            one = np.ones_like(t)
            s = np.concatenate([s_in_p * one, s_in_q * one])
            e = np.concatenate([r_p * one, r_q * one])
            zz = np.zeros(2 * t.size)
            return s, e, {2: (np.concatenate([s_in_p * one, z]), zz),
                          3: (np.concatenate([z, s_in_q * one]), zz),
                          10: (zz, np.concatenate([r_p * one, z])),
                          11: (zz, np.concatenate([z, r_q * one]))}
        c, hw, ew = th[7], math.exp(th[8]), math.exp(th[9])
        a, b = c - hw, c + hw
        u, v = (t - a) / ew, (b - t) / ew
        su, sv = _logistic(u), _logistic(v)
        w = su * sv
        sp = np.sqrt(s_in_p**2 * w + s_out**2)
        sq = np.sqrt(s_in_q**2 * w + s_out**2)
        edge = 4.0 * w * (1.0 - w) + 1e-12
        ep, eq = r_p * np.sqrt(edge), r_q * np.sqrt(edge)
        da, db = -w * (1.0 - su) / ew, w * (1.0 - sv) / ew
        dw = {7: da + db, 8: hw * (db - da), 9: -w * ((1.0 - su) * u + (1.0 - sv) * v)}
        zz = np.zeros(2 * t.size)
        d = {2: (np.concatenate([s_in_p**2 * w / sp, z]), zz),
             3: (np.concatenate([z, s_in_q**2 * w / sq]), zz),
             4: (np.concatenate([s_out**2 / sp, s_out**2 / sq]), zz),
             10: (zz, np.concatenate([ep, z])), 11: (zz, np.concatenate([z, eq]))}
        for k, g in dw.items():
            dedge = 4.0 * (1.0 - 2.0 * w) * g
            d[k] = (np.concatenate([0.5 * s_in_p**2 * g / sp, 0.5 * s_in_q**2 * g / sq]),
                    np.concatenate([0.5 * r_p**2 * dedge / ep, 0.5 * r_q**2 * dedge / eq]))
        return np.concatenate([sp, sq]), np.concatenate([ep, eq]), d

    def evaluate(self, th, grad=False, full=False):
        m = self.m
        lp, lq, lr = math.exp(th[0]), math.exp(th[1]), math.exp(th[12])
        nz, nx = math.exp(th[5]), math.exp(th[6])
        Cp, dCp = _matern52(self.t, lp)
        Cq, dCq = _matern52(self.t, lq)
        Cr, dCr = _matern52(self.t, lr, 0.5)
        s, e, dsd = self._amplitudes(th)
        C = np.zeros((2 * m, 2 * m))
        C[:m, :m], C[m:, m:] = Cp, Cq
        C[np.diag_indices_from(C)] += self.jitter
        C2 = np.zeros((2 * m, 2 * m))
        C2[:m, :m] = C2[m:, m:] = Cr
        K = s[:, None] * C * s[None, :] + e[:, None] * C2 * e[None, :]
        Lk = np.zeros_like(K)
        Lk[:m, :m] = np.linalg.cholesky(K[:m, :m])
        Lk[m:, m:] = np.linalg.cholesky(K[m:, m:])
        Lp, Lq = Lk[:m, :m], Lk[m:, m:]  # block-diagonal: Lk^T H Lk by blocks

        def lthl(H):
            HL = np.hstack([H[:, :m] @ Lp, H[:, m:] @ Lq])
            return np.vstack([Lp.T @ HL[:m], Lq.T @ HL[m:]])

        logev, post = _posterior(self, Lk, lthl, nz, nx, th[5] + th[6], grad, full)
        if post is None:
            return logev
        mu, S, H, W = post
        out = [logev]
        if grad:
            g = np.zeros(_NPAR)
            ss = s[:, None] * s[None, :]
            ee = e[:, None] * e[None, :]
            g[0] = 0.5 * np.sum(W[:m, :m] * dCp * ss[:m, :m])
            g[1] = 0.5 * np.sum(W[m:, m:] * dCq * ss[m:, m:])
            g[12] = 0.5 * (np.sum(W[:m, :m] * dCr * ee[:m, :m])
                           + np.sum(W[m:, m:] * dCr * ee[m:, m:]))
            WC, WC2 = (W * C) @ s, (W * C2) @ e
            for k, (ds_, de_) in dsd.items():
                g[k] = float(ds_ @ WC + de_ @ WC2)
            _noise_gradient(g, (5, 6), self, nz, nx, mu, S)
            out.append(g)
        if full:
            out.append((mu, S, H))
        return tuple(out)


def _cho(L, y):
    from scipy.linalg import solve_triangular

    return solve_triangular(L.T, solve_triangular(L, y, lower=True), lower=False)


def _noise_guess(d):
    """Noise sd from second differences (white noise: var(d2) = 6 sigma^2)."""
    d2 = np.diff(d, 2)
    return max(float(np.median(np.abs(d2))) / 0.6745 / math.sqrt(6.0),
               1e-6 * float(np.max(np.abs(d)) or 1.0))


def _optimise(ev: _Evidence, dz, dx, dt, ftol=1e-10, gtol=1e-3, noise_floor=None):
    """Maximum of the log-evidence over the hyperparameters (L-BFGS-B with the analytic
    gradient, from the data's amplitude, a noise estimate from second differences and an
    envelope around the data's peak); ``noise_floor`` (zz, xz): the noise sd's lower bounds
    (scaled units; ``inverse_prior.model_error_floor``); returns (theta, log-evidence, free
    mask)."""
    t = ev.t
    scale = max(float(np.max(np.abs(dz))), float(np.max(np.abs(dx))), 1e-300)
    nz0 = min(max(_noise_guess(dz), 1e-4 * scale), 0.3 * scale)
    nx0 = min(max(_noise_guess(dx), 1e-4 * scale), 0.3 * scale)
    # envelope start: where the data exceed half their peak, widened by 1 h
    x = ev.fwd.x
    big = np.abs(dz) > 0.5 * np.max(np.abs(dz))
    a0 = float(x[big].min()) - 1.0 if big.any() else float(t[0])
    b0 = float(x[big].max()) + 1.0 if big.any() else float(t[-1])
    c0, hw0 = 0.5 * (a0 + b0), 0.5 * (b0 - a0)
    lo = np.array([math.log(max(dt, 0.05))] * 2 + [math.log(1e-4 * scale)] * 3
                  + [math.log(1e-7 * scale)] * 2 + [t[0], math.log(max(dt, 0.05)), math.log(max(dt / 2, 0.02))])
    hi = np.array([math.log(20.0)] * 2 + [math.log(1e3 * scale)] * 3
                  + [math.log(10 * scale)] * 2 + [t[-1], math.log(t[-1] - t[0]), math.log(5.0)])
    lo[9] = math.log(max(ENVELOPE_EDGE_MIN_H, dt / 2))
    if noise_floor is not None:  # the model-error floor (scaled units, absolute; zz, xz)
        lo[5], lo[6] = (math.log(f) for f in noise_floor)
    lo = np.concatenate([lo, [math.log(1e-4 * scale)] * 2 + [math.log(max(dt, 0.05))]])
    hi = np.concatenate([hi, [math.log(1e3 * scale)] * 2 + [math.log(20.0)]])
    free = np.ones(_NPAR, bool)
    if not ev.envelope:
        free[[4, 7, 8, 9]] = False
    best = None
    for l0 in (0.8,):
        th0 = np.array([math.log(l0), math.log(l0), math.log(scale), math.log(0.5 * scale),
                        math.log(0.02 * scale), math.log(nz0), math.log(nx0), c0, math.log(hw0),
                        math.log(0.5), math.log(0.2 * scale), math.log(0.2 * scale),
                        math.log(0.3)])
        th0 = np.clip(th0, lo, hi)
        th, v = _maximise(ev, th0, free, lo, hi, maxiter=300, ftol=ftol, gtol=gtol)
        if th is not None and (best is None or v > best[1]):
            best = (th, v)
    if best is None:
        raise np.linalg.LinAlgError("the evidence could not be evaluated at the start")
    return best[0], best[1], free


def _maximise(ev, th0, free, lo, hi, maxiter, ftol, gtol):
    """The log-evidence ``ev.evaluate`` maximised over theta[free] within (lo, hi) from th0
    (L-BFGS-B with the analytic gradient; a point where the evidence cannot be evaluated counts
    as -inf).  Returns (theta, value) of the best point evaluated ((None, -inf) if none)."""
    from scipy.optimize import minimize

    seen = [None, -np.inf]

    def f(z):
        th = th0.copy()
        th[free] = z
        try:
            v, g = ev.evaluate(th, grad=True)
        except np.linalg.LinAlgError:
            return 1e300, np.zeros(z.size)
        if not np.isfinite(v):
            return 1e300, np.zeros(z.size)
        if v > seen[1]:
            seen[:] = [th, v]
        return -v, -g[free]

    minimize(f, th0[free], jac=True, method="L-BFGS-B", bounds=list(zip(lo[free], hi[free])),
             options={"maxiter": maxiter, "ftol": ftol, "gtol": gtol})
    return seen[0], seen[1]


def _positive(mean, cov, m):
    """Posterior mode under p >= 0 (bounded least squares) and the covariance of the free nodes
    given the active ones (sd 0 there)."""
    from scipy.optimize import lsq_linear

    n2 = 2 * m
    if np.all(mean[:m] >= 0):
        return mean, cov, np.zeros(n2, bool)
    # precision A = inv(cov); minimise 1/2 f A f - f (A mean)  <=>  ||R (f - mean)||^2
    A = np.linalg.inv(cov)
    A = 0.5 * (A + A.T)
    R = np.linalg.cholesky(A).T
    lo = np.concatenate([np.zeros(m), np.full(m, -np.inf)])
    sol = lsq_linear(R, R @ mean, bounds=(lo, np.full(n2, np.inf)), method="bvls", tol=1e-12)
    f = sol.x
    active = np.zeros(n2, bool)
    active[:m] = f[:m] <= 1e-12 * max(1.0, float(np.abs(f).max()))
    free = ~active
    c2 = np.zeros_like(cov)
    c2[np.ix_(free, free)] = np.linalg.inv(A[np.ix_(free, free)])
    f[active] = 0.0
    return f, c2, active


def _contact_interval(t, p, Cpp, sd, draws, seed):
    """Edges of the region around the peak of p above 2 * median sd, over posterior draws."""
    level = 2.0 * float(np.median(sd))

    def edges(f):
        j = int(np.argmax(f))
        if f[j] <= level:
            return np.nan, np.nan
        i = j
        while i > 0 and f[i - 1] > level:
            i -= 1
        k = j
        while k < f.size - 1 and f[k + 1] > level:
            k += 1
        left = t[i] if i == 0 else t[i - 1] + (level - f[i - 1]) / (f[i] - f[i - 1]) * (t[i] - t[i - 1])
        right = t[k] if k == f.size - 1 else t[k] + (f[k] - level) / (f[k] - f[k + 1]) * (t[k + 1] - t[k])
        return left, right

    rng = np.random.default_rng(seed)
    w, V = np.linalg.eigh(0.5 * (Cpp + Cpp.T))
    Ls = V * np.sqrt(np.maximum(w, 0.0))
    z = rng.standard_normal((draws, p.size))
    samples = p[None, :] + z @ Ls.T
    e = np.array([edges(s) for s in samples])
    e0 = edges(p)
    ok = np.all(np.isfinite(e), axis=1)
    if not ok.any() or not np.all(np.isfinite(e0)):
        return [float("nan"), float("nan")], [float("nan"), float("nan")]
    sd_e = np.std(e[ok], axis=0)
    return [float(e0[0]), float(e0[1])], [float(sd_e[0]), float(sd_e[1])]
