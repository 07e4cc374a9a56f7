"""The line inverse's forward map (issue 21): nodal surface tractions -> base stresses (or
the sensor view) through the film's public base transfer; synthetic records; the resolution
length.  See ``instruments.inverse`` for the model as a whole.  Lengths in h."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..physics.film import Film

__all__ = ["LineForward", "base_from_tractions", "MARGIN_H", "NODE_STEP_H"]

MARGIN_H = 1.5
"""Traction nodes extend this many film thicknesses beyond each end of the record."""
NODE_STEP_H = 0.125
"""Largest node step [h] (the data's step if coarser)."""
_FINE_STEP_H = 1.0 / 128.0
_PAD_H = 40.0


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
    def build(cls, x, film: Film, symbols=None, support=None, step=None, span=None):
        """x [h] uniform; film in units of h (thickness 1); symbols: None (no apparatus) or a
        pair of functions k [1/h] -> transform (G_zz, G_xz line symbols); support (a, b) [h]:
        nodes on it with half hats at its ends; span (lo, hi) [h]: nodes (hats) on it only,
        the tractions taken as zero beyond (default: the record +- ``MARGIN_H``)."""
        x = np.asarray(x, dtype=float)
        dx = (x[-1] - x[0]) / (x.size - 1)
        dt = step if step is not None else max(NODE_STEP_H, dx)
        if support is None:
            lo, hi = (x[0] - MARGIN_H, x[-1] + MARGIN_H) if span is None else span
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



def _symbols(apparatus, h_m):
    if apparatus is None:
        return None
    gzz, gxz = apparatus
    return (lambda k: np.asarray(gzz.transform(k / h_m), float),
            lambda k: np.asarray(gxz.transform(k / h_m), float))



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
