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
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, named
from ..physics.film import Film

__all__ = ["invert", "read_record", "invert_line", "LineInversion", "LineForward", "fit_laws", "base_from_tractions",
           "INVERT_JSON_KEYS", "RESOLVED_Z", "MARGIN_H"]

RESOLVED_Z = 3.0
"""p is resolved where its posterior mean exceeds RESOLVED_Z posterior sd."""
MARGIN_H = 1.5
"""Traction nodes extend this many film thicknesses beyond each end of the record."""
NODE_STEP_H = 0.125
"""Largest node step [h] (the data's step if coarser)."""
LAW_EDGE_GUARD = 2.0
"""The law fits use resolved nodes at least this many resolution lengths inside the contact
interval's edges."""
_FINE_STEP_H = 1.0 / 128.0
_PAD_H = 40.0

INVERT_JSON_KEYS = ("load_N_per_m", "load_sigma_N_per_m", "tangential_load_N_per_m",
                    "tangential_load_sigma_N_per_m", "Q_over_P", "Q_over_P_sigma",
                    "contact_interval_m", "contact_interval_sigma_m", "resolution_length_m",
                    "regularisation", "log_evidence", "noise_sd_zz_Pa", "noise_sd_xz_Pa",
                    "view", "points", "nodes", "positive", "support_m", "laws")


# --- synthetic records: the film's base transfer applied to chosen tractions ----------------

def base_from_tractions(x_m, p_Pa, q_Pa, thickness: float, poisson: float = 0.5):
    """Base stresses (sigma_zz(x, 0), sigma_xz(x, 0)) [Pa] of surface tractions p, q [Pa] given
    on a uniform grid x_m that is one period of a periodic field (pad it with zeros well beyond
    the tractions: the kernels decay as exp(-0.74 |x|/h)).  Signs of the package: p >= 0 in
    compression (sigma_zz(x, h) = -p), q = sigma_xz(x, h); sigma_zz(x, 0) < 0 in compression."""
    from ..numerics.fft import get_rfft
    from ..numerics.grid import Grid

    x = np.asarray(x_m, dtype=float)
    n = x.size
    dx = (x[-1] - x[0]) / (n - 1)
    grid = Grid(n, n * dx / thickness)
    film = Film(1.0, poisson)
    fft = get_rfft(n)
    szz, (sxz,) = film.base_stresses(fft, grid, -np.asarray(p_Pa, float), (np.asarray(q_Pa, float),))
    return szz, sxz


# --- forward map ------------------------------------------------------------------------------

def _hat_transform(k, w):
    """Fourier transform of the hat of half-width w and height 1: w sinc^2(k w / 2)."""
    u = 0.5 * k * w
    s = np.where(np.abs(u) > 1e-8, np.sin(u) / np.where(np.abs(u) > 1e-8, u, 1.0), 1.0)
    return w * s * s


def _half_hat_transform(k, w, side):
    """Transform of the half hat on [0, w] (side=+1: 1 - t/w) or [-w, 0] (side=-1: 1 + t/w)."""
    k = np.asarray(k, dtype=float)
    kw = k * w
    small = np.abs(kw) < 1e-4
    safe = np.where(small, 1.0, kw)
    # Int_0^w (1 - t/w) e^{-ikt} dt = w [ (1 - e^{-ikw})/(ikw)^2 ... ] written out:
    # = 1/(ik) - (1 - e^{-ikw})/(w (ik)^2)
    ik = 1j * safe / w
    val = 1.0 / ik - (1.0 - np.exp(-1j * safe)) / (w * ik * ik)
    series = w * (0.5 - 1j * kw / 6.0 - kw * kw / 24.0)
    val = np.where(small, series, val)
    return val if side > 0 else np.conj(val)


@dataclass
class LineForward:
    """The linear map from nodal surface tractions (p_j, q_j) to the data (d_zz, d_xz).

    x : data positions [h] (uniform); nodes : node positions [h]; basis : "hat" everywhere, or
    with ``support`` half hats at its two ends.  ``Mzp, Mzq, Mxp, Mxq`` (n x m): the blocks of
    d_zz = Mzp p + Mzq q, d_xz = Mxp p + Mxq q.
    """

    x: np.ndarray
    nodes: np.ndarray
    weights: np.ndarray  # Int of each basis function [h]
    Mzp: np.ndarray
    Mzq: np.ndarray
    Mxp: np.ndarray
    Mxq: np.ndarray
    kinds: np.ndarray = field(default=None)  # 0 hat, +1 right half hat (left end), -1 left half

    @classmethod
    def build(cls, x, film: Film, symbols=None, support=None, step=None):
        """x [h] uniform; film in units of h (thickness 1); symbols: None (no apparatus) or a
        pair of functions k [1/h] -> transform (G_zz, G_xz line symbols); support (a, b) [h]."""
        x = np.asarray(x, dtype=float)
        dx = (x[-1] - x[0]) / (x.size - 1)
        dt = step if step is not None else max(NODE_STEP_H, dx)
        if support is None:
            lo, hi = x[0] - MARGIN_H, x[-1] + MARGIN_H
            m = int(math.ceil((hi - lo) / dt)) + 1
            nodes = lo + dt * np.arange(m)
            kinds = np.zeros(m, dtype=int)
        else:
            a, b = support
            m = max(int(math.ceil((b - a) / dt)), 2) + 1
            nodes = np.linspace(a, b, m)
            dt = nodes[1] - nodes[0]
            kinds = np.zeros(m, dtype=int)
            kinds[0], kinds[-1] = 1, -1
        weights = np.where(kinds == 0, dt, 0.5 * dt)
        # fine periodic grid for the kernels: lags from x_min - t_max to x_max - t_min
        span = max(x[-1] - nodes[0], nodes[-1] - x[0]) + dt
        fine = min(_FINE_STEP_H, dx / 2.0)
        if fine < _FINE_STEP_H:  # dense data: the kernel is smooth on h/128, interpolate
            fine = _FINE_STEP_H
        period = 2.0 * span + _PAD_H
        nf = int(2 ** math.ceil(math.log2(period / fine)))
        fine = period / nf
        k = 2.0 * math.pi * np.fft.rfftfreq(nf, fine)
        coef = film.base_coefficients(k)
        gz, gx = (np.ones_like(k), np.ones_like(k)) if symbols is None else (symbols[0](k),
                                                                              symbols[1](k))

        def kernels(phi):
            # response at the base of p = phi (sigma_zz(h) = -phi) and of q = phi
            szz_p, (sxz_p,) = film.base_transfer((1.0,), k, -phi, (0.0 * phi,), coef)
            szz_q, (sxz_q,) = film.base_transfer((1.0,), k, 0.0 * phi, (phi,), coef)
            out = []
            for spec, g, sign in ((szz_p, gz, -1.0), (szz_q, gz, -1.0), (sxz_p, gx, 1.0),
                                  (sxz_q, gx, 1.0)):
                f = np.fft.irfft(sign * spec * g, nf) / fine
                out.append(np.fft.fftshift(f))  # index nf//2 is lag 0
            return out

        kers = {0: kernels(_hat_transform(k, dt).astype(complex))}
        if support is not None:
            kers[1] = kernels(_half_hat_transform(k, dt, +1))
            kers[-1] = kernels(_half_hat_transform(k, dt, -1))
        n = x.size
        blocks = [np.empty((n, m)) for _ in range(4)]
        for kind, ks in kers.items():
            cols = np.nonzero(kinds == kind)[0]
            if cols.size == 0:
                continue
            lag = x[:, None] - nodes[None, cols]
            pos = lag / fine + nf // 2
            i0 = np.floor(pos).astype(int)
            w1 = pos - i0
            for blk, kern in zip(blocks, ks):
                blk[:, cols] = (1.0 - w1) * kern[i0] + w1 * kern[i0 + 1]
        return cls(x, nodes, weights, *blocks, kinds=kinds)

    def basis_matrix(self, x):
        """Values of the basis functions at x [h] (len(x) x m)."""
        x = np.asarray(x, dtype=float)
        t = self.nodes
        dt = t[1] - t[0]
        u = (x[:, None] - t[None, :]) / dt
        B = np.clip(1.0 - np.abs(u), 0.0, None)
        B[:, self.kinds == 1] *= (u[:, self.kinds == 1] >= 0)
        B[:, self.kinds == -1] *= (u[:, self.kinds == -1] <= 0)
        return B

    def apply(self, p, q):
        return self.Mzp @ p + self.Mzq @ q, self.Mxp @ p + self.Mxq @ q


# --- evidence and posterior -------------------------------------------------------------------

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
        self.fwd = fwd
        Mz = np.hstack([fwd.Mzp, fwd.Mzq])
        Mx = np.hstack([fwd.Mxp, fwd.Mxq])
        self.Gz, self.Gx = Mz.T @ Mz, Mx.T @ Mx
        self.bz, self.bx = Mz.T @ dz, Mx.T @ dx
        self.ez, self.ex = float(dz @ dz), float(dx @ dx)
        self.n = dz.size
        self.m = fwd.nodes.size
        self.t = fwd.nodes
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
        H = self.Gz / nz**2 + self.Gx / nx**2
        b = self.bz / nz**2 + self.bx / nx**2
        Lk = np.zeros_like(K)
        Lk[:m, :m] = np.linalg.cholesky(K[:m, :m])
        Lk[m:, m:] = np.linalg.cholesky(K[m:, m:])
        Lp, Lq = Lk[:m, :m], Lk[m:, m:]  # block-diagonal: Lk^T H Lk by blocks
        HL = np.hstack([H[:, :m] @ Lp, H[:, m:] @ Lq])
        B = np.vstack([Lp.T @ HL[:m], Lq.T @ HL[m:]])
        B[np.diag_indices_from(B)] += 1.0
        Lb = np.linalg.cholesky(B)
        beta = Lk.T @ b
        alpha = _cho(Lb, beta)
        mu = Lk @ alpha
        logdet = 2.0 * np.sum(np.log(np.diag(Lb)))
        quad = self.ez / nz**2 + self.ex / nx**2 - beta @ alpha
        n = self.n
        logev = -0.5 * quad - 0.5 * logdet - n * (th[5] + th[6]) - n * math.log(2.0 * math.pi)
        if not (grad or full):
            return logev
        from scipy.linalg import solve_triangular

        Li = solve_triangular(Lb, Lk.T, lower=True)  # posterior covariance S = Li^T Li
        S = Li.T @ Li
        out = [logev]
        if grad:
            g = np.zeros(_NPAR)
            # prior parameters: d logev = 1/2 tr(W dK), W = K^-1 (mu mu^T + S) K^-1 - K^-1
            # = Km Km^T - (K + H^-1)^-1 with Km = K^-1 mu = b - H mu and (Woodbury)
            # (K + H^-1)^-1 = H - H S H: no inverse of the (ill-conditioned) prior covariance
            Km = b - H @ mu
            HS = H @ S
            W = np.outer(Km, Km) - H + HS @ H
            W = 0.5 * (W + W.T)
            ss = s[:, None] * s[None, :]
            ee = e[:, None] * e[None, :]
            g[0] = 0.5 * np.sum(W[:m, :m] * dCp * ss[:m, :m])
            g[1] = 0.5 * np.sum(W[m:, m:] * dCq * ss[m:, m:])
            g[12] = 0.5 * (np.sum(W[:m, :m] * dCr * ee[:m, :m])
                           + np.sum(W[m:, m:] * dCr * ee[m:, m:]))
            WC, WC2 = (W * C) @ s, (W * C2) @ e
            for k, (ds_, de_) in dsd.items():
                g[k] = float(ds_ @ WC + de_ @ WC2)
            # noise: d logev / d log sigma_c = -n + |r_c|^2 / sigma_c^2 + tr(G_c S) / sigma_c^2
            for k, G, bb, ee, sig in ((5, self.Gz, self.bz, self.ez, nz),
                                      (6, self.Gx, self.bx, self.ex, nx)):
                rr = ee - 2.0 * mu @ bb + mu @ G @ mu + np.sum(G * S)
                g[k] = -n + rr / sig**2
            out.append(g)
        if full:
            out.append((mu, S, H))
        return tuple(out)


def _cho(L, y):
    from scipy.linalg import solve_triangular

    return solve_triangular(L.T, solve_triangular(L, y, lower=True), lower=False)


def _cho_inv(L):
    from scipy.linalg import solve_triangular

    Li = solve_triangular(L, np.eye(L.shape[0]), lower=True)
    return Li.T @ Li


def _noise_guess(d):
    """Noise sd from second differences (white noise: var(d2) = 6 sigma^2)."""
    d2 = np.diff(d, 2)
    return max(float(np.median(np.abs(d2))) / 0.6745 / math.sqrt(6.0),
               1e-6 * float(np.max(np.abs(d)) or 1.0))


def _optimise(ev: _Evidence, dz, dx, dt):
    """Maximum of the log-evidence over the hyperparameters (L-BFGS-B with the analytic
    gradient, from the data's amplitude, a noise estimate from second differences and an
    envelope around the data's peak); returns (theta, log-evidence, free mask)."""
    from scipy.optimize import minimize

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

        def f(z, th0=th0):
            th = th0.copy()
            th[free] = z
            try:
                v, g = ev.evaluate(th, grad=True)
            except np.linalg.LinAlgError:
                return 1e300, np.zeros(z.size)
            if not np.isfinite(v):
                return 1e300, np.zeros(z.size)
            return -v, -g[free]

        res = minimize(f, th0[free], jac=True, method="L-BFGS-B",
                       bounds=list(zip(lo[free], hi[free])),
                       options={"maxiter": 300, "ftol": 1e-10, "gtol": 1e-3})
        th = th0.copy()
        th[free] = res.x
        if best is None or -res.fun > best[1]:
            best = (th, -res.fun)
    return best[0], best[1], free


# --- laws -------------------------------------------------------------------------------------

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
    from scipy.stats import chi2 as chi2_dist

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
        rec.update({"chi2": chi2, "dof": dof, "p_value": float(chi2_dist.sf(chi2, dof)),
                    "aic": chi2 + 2 * k})
        out[law] = rec
    fitted = {k: v for k, v in out.items() if "aic" in v}
    out["best"] = min(fitted, key=lambda k: fitted[k]["aic"]) if fitted else None
    return out


# --- the result -------------------------------------------------------------------------------

@dataclass(repr=False, eq=False)
class LineInversion:
    """Tractions at the interface inferred from a line record (all SI at the edge).

    x_m : node positions [m] (the file's frame); pressure_Pa, shear_Pa : posterior means of p
    (>= 0 in compression) and q = sigma_xz(x, h) (> 0 drags the film toward +x);
    pressure_sd_Pa, shear_sd_Pa : posterior sd; mu_local, mu_local_sd : q/p and its sd where
    p > 3 sd (NaN elsewhere); ``summary()``: the JSON record (``INVERT_JSON_KEYS``);
    ``profiles()``: the CSV columns; ``plot()``: a Figure.
    """

    x_m: np.ndarray
    pressure_Pa: np.ndarray
    pressure_sd_Pa: np.ndarray
    shear_Pa: np.ndarray
    shear_sd_Pa: np.ndarray
    mu_local: np.ndarray
    mu_local_sd: np.ndarray
    record: dict
    data: dict
    cov: np.ndarray = None  # nodal covariance [Pa^2], (p, q) stacked

    def summary(self) -> dict:
        return dict(self.record)

    to_dict = summary

    @property
    def laws(self) -> dict:
        return self.record["laws"]

    def profiles(self) -> dict:
        return {"x_m": self.x_m, "pressure_Pa": self.pressure_Pa,
                "pressure_sd_Pa": self.pressure_sd_Pa, "shear_Pa": self.shear_Pa,
                "shear_sd_Pa": self.shear_sd_Pa, "mu_local": self.mu_local,
                "mu_local_sd": self.mu_local_sd}

    def __getattr__(self, name):
        rec = self.__dict__.get("record")
        if rec is not None and name in rec:
            return rec[name]
        raise AttributeError(name)

    def __repr__(self):
        r = self.record
        return (f"<LineInversion: P = {r['load_N_per_m']:.5g} +- {r['load_sigma_N_per_m']:.2g} N/m,"
                f" Q = {r['tangential_load_N_per_m']:.5g} +- "
                f"{r['tangential_load_sigma_N_per_m']:.2g} N/m, Q/P = {r['Q_over_P']:.4g} +- "
                f"{r['Q_over_P_sigma']:.2g}; resolution {r['resolution_length_m'] * 1e3:.3g} mm; "
                f"best law {r['laws'].get('best')}>")

    def plot(self, fig=None):
        """Tractions with 95 % bands, mu_local with its band, the data against the data
        re-predicted from the estimate (with residuals), and the local (p, q) pairs."""
        from matplotlib.figure import Figure

        fig = fig or Figure(figsize=(10, 8), layout="constrained")
        ax = fig.subplots(2, 2)
        mm, kPa = 1e3, 1e-3
        x = self.x_m * mm
        a = ax[0, 0]
        for f, s, c, lab in ((self.pressure_Pa, self.pressure_sd_Pa, "C0", "p"),
                             (self.shear_Pa, self.shear_sd_Pa, "C1", "q")):
            a.fill_between(x, (f - 1.96 * s) * kPa, (f + 1.96 * s) * kPa, color=c, alpha=0.3)
            a.plot(x, f * kPa, c + "-", label=f"{lab} (95 % band)")
        a.axhline(0, color="0.6", lw=0.5)
        a.set_xlabel("x [mm] (file's frame)")
        a.set_ylabel("traction [kPa]")
        a.legend(fontsize=8)
        a.set_title(f"P = {self.record['load_N_per_m']:.4g} +- "
                    f"{self.record['load_sigma_N_per_m']:.2g} N/m, Q/P = "
                    f"{self.record['Q_over_P']:.4g} +- {self.record['Q_over_P_sigma']:.2g}",
                    fontsize=9)
        a = ax[0, 1]
        ok = np.isfinite(self.mu_local)
        a.fill_between(x[ok], (self.mu_local - 1.96 * self.mu_local_sd)[ok],
                       (self.mu_local + 1.96 * self.mu_local_sd)[ok], color="C2", alpha=0.3)
        a.plot(x[ok], self.mu_local[ok], "C2.-", label="mu_local = q/p (p > 3 sd), 95 %")
        a.set_xlabel("x [mm]")
        a.set_ylabel("q / p")
        a.legend(fontsize=8)
        a = ax[1, 0]
        d = self.data
        xd = d["x_m"] * mm
        for key, c, lab in (("zz", "C0", "zz"), ("xz", "C1", "xz")):
            a.plot(xd, d[key] * kPa, c + ".", ms=2, label=f"data {lab}")
            a.plot(xd, d[key + "_fit"] * kPa, "k-", lw=0.8)
            a.plot(xd, (d[key] - d[key + "_fit"]) * kPa, c + "-", lw=0.6, alpha=0.7,
                   label=f"residual {lab}")
        a.set_xlabel("x [mm]")
        a.set_ylabel(("S" if self.record["view"] == "sensor" else "base stress") + " [kPa]")
        a.legend(fontsize=7)
        a = ax[1, 1]
        res = ok
        a.errorbar(self.pressure_Pa[res] * kPa, self.shear_Pa[res] * kPa,
                   xerr=self.pressure_sd_Pa[res] * kPa, yerr=self.shear_sd_Pa[res] * kPa,
                   fmt="k.", ms=3, lw=0.5, label="local (p, q), 1 sd")
        pp = np.linspace(0, max(self.pressure_Pa[res].max() if res.any() else 1.0, 1.0), 50)
        laws = self.record["laws"]
        for law, f in (("amontons", lambda p, r: r["mu"] * p),
                       ("linear", lambda p, r: r["tau0_Pa"] + r["alpha"] * p),
                       ("power", lambda p, r: r["k_Pa"] * (p / r["p_ref_Pa"]) ** r["n"])):
            rec = laws.get(law, {})
            if "aic" in rec:
                a.plot(pp * kPa, f(pp, rec) * kPa, label=f"{law} (AIC {rec['aic']:.1f})")
        a.set_xlabel("p [kPa]")
        a.set_ylabel("q [kPa]")
        a.legend(fontsize=7)
        return fig


# --- the inversion ----------------------------------------------------------------------------

def _symbols(apparatus, h_m):
    if apparatus is None:
        return None
    gzz, gxz = apparatus
    return (lambda k: np.asarray(gzz.transform(k / h_m), float),
            lambda k: np.asarray(gxz.transform(k / h_m), float))


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
    _check_span(x, h)
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
        lo, hi = x[0] - MARGIN_H * h, x[-1] + MARGIN_H * h  # where the tractions are modelled
        if a < lo or b > hi:
            raise InputError(f"{named('support')} {a:g} {b:g}: the known contact must lie within "
                             f"the record extended by {MARGIN_H:g} thicknesses, [{lo:.6g}, "
                             f"{hi:.6g}] m")
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


def _resolution_length(fwd, symbols, film, noise_sd, n, peak, h):
    """Resolution length [m]: pi / k_c, k_c the largest wavenumber at which a sinusoidal
    traction of the peak pressure's amplitude still shows in the data at 3 noise sd: its base
    (or sensor) amplitude max(|A g_zz|, |C g_xz|, |B g|) times the peak exceeds 3 sigma
    sqrt(2/n) (the sd of a sinusoid's amplitude fitted to n samples of white noise sigma).
    What the film (A, B, C), the apparatus (g) and the noise allow; the posterior's own
    smoothing is at least this."""
    k = np.linspace(0.0, 60.0, 6001)[1:]
    A, iB, _, C, _ = film.base_coefficients(k)
    gz, gx = (1.0, 1.0) if symbols is None else (symbols[0](k), symbols[1](k))
    T = np.maximum.reduce([np.abs(A * gz), np.abs(C * gx), np.abs(iB * gz), np.abs(iB * gx)])
    seen = T * peak >= 3.0 * noise_sd * math.sqrt(2.0 / n)
    if not seen.any():
        return float("inf")
    kc = float(k[np.nonzero(seen)[0].max()])
    return math.pi / kc * h


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
