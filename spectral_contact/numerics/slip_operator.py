"""The film's coupled surface compliance (p, q) -> (w, u) on a periodic line or surface grid,
as the partial-slip solver (``numerics.partial_slip``) applies it: the (1 + D) x (1 + D) symbol
of ``Film.surface_displacement_transfer`` (D = 1 or 2 tangential components) on 1 + D fields in
one batched real FFT (1 + D FFT pairs), and the clipped inverse symbols of its preconditioner.
Dimensionless core (lengths in h, tractions in G h/2R, displacements in h^2/2R)."""
from __future__ import annotations

import math

import numpy as np

from ..physics.film import Film
from .grid import Grid

__all__ = ["PartialSlipOperator", "PartialSlipOperator2D"]

_PLANS: dict = {}


def _plan(shape: tuple, m: int):
    """A batched real FFT of ``m`` fields on ``shape`` (pyfftw, the package's planner
    effort): (real buffer (m, *shape), the forward transform's complex output, the backward
    transform's complex input (a second buffer: the symbol product is written into it without
    copies), forward, backward)."""
    import pyfftw

    from . import fft as _fft

    key = (shape, m)
    plan = _PLANS.get(key)
    if plan is None:
        kshape = shape[:-1] + (shape[-1] // 2 + 1,)
        axes = tuple(range(-len(shape), 0))
        r = pyfftw.empty_aligned((m,) + shape, dtype="float64")
        c = pyfftw.empty_aligned((m,) + kshape, dtype="complex128")
        o = pyfftw.empty_aligned((m,) + kshape, dtype="complex128")
        effort = _fft._PLANNER_EFFORT
        fwd = pyfftw.FFTW(r, c, axes=axes, direction="FFTW_FORWARD", flags=(effort,))
        bwd = pyfftw.FFTW(o, r, axes=axes, direction="FFTW_BACKWARD",
                          flags=(effort, "FFTW_DESTROY_INPUT"))
        plan = _PLANS[key] = (r, c, o, fwd.execute, bwd.execute)
        if len(_PLANS) > 8:
            _PLANS.pop(next(iter(_PLANS)))
    return plan


def _scaled(M, scale: float):
    """The symbol ``M`` (nested tuples of complex arrays) as one contiguous array per entry,
    times ``scale`` (the inverse transform's 1/N, folded in)."""
    return tuple(tuple(np.ascontiguousarray(scale * np.asarray(m, dtype=complex)) for m in row)
                 for row in M)


class PartialSlipOperator:
    """The film's coupled surface compliance (p, q) -> (w, u) on a periodic 1D or 2D ``grid``
    (1 + D fields, D = grid.ndim tangential components) and the clipped inverse symbols of its
    preconditioner."""

    def __init__(self, grid: Grid, film: Film | None = None):
        if grid.ndim not in (1, 2):
            raise ValueError("PartialSlipOperator takes 1D (lines) or 2D (surfaces) grids")
        self.grid = grid
        self.film = film or Film()
        self.ndim = grid.ndim
        self.m = 1 + grid.ndim
        self.size, self.cell = grid.size, grid.cell
        self._scale = 1.0 / grid.size
        self.M = _scaled(self._symbols(grid.kmag), self._scale)
        self._pre: dict = {}
        self._plan = _plan(grid.shape, self.m)
        self._tmp = np.empty(grid.kshape, dtype=complex)

    def _symbols(self, kmag):
        """M[i][j]: output i (w, u_x[, u_y]) of the unit input j (p, q_x[, q_y]),
        alias-averaged on the grid."""
        g, film, m = self.grid, self.film, self.m
        one, zero = np.ones(g.kshape), np.zeros(g.kshape)

        def evaluate(n):
            cols = []
            for j in range(m):
                src = [one if i == j else zero for i in range(m)]
                u, w = film.surface_displacement_transfer(n, kmag, src[0], tuple(src[1:]))
                cols.append((w,) + tuple(u))
            return tuple(tuple(np.broadcast_to(cols[j][i], g.kshape).astype(complex)
                               for j in range(m)) for i in range(m))

        return g.alias_average(evaluate)

    def transform(self, M):
        """The symbol ``M`` (``self.M`` or a ``preconditioner``, 1/N folded in) applied to the
        plan's real buffer (filled by the caller, shape (1 + D, *grid.shape)); returns that
        buffer, overwritten by the result (valid until the next call)."""
        r, c, o, fwd, bwd = self._plan
        fwd()
        tmp = self._tmp
        for i in range(self.m):
            Mi, oi = M[i], o[i]
            np.multiply(Mi[0], c[0], out=oi)
            for j in range(1, self.m):
                np.multiply(Mi[j], c[j], out=tmp)
                oi += tmp
        bwd()
        return r

    def preconditioner(self, k_cut: float):
        """The inverse symbol for |k| >= k_cut, its value at |k| = k_cut (same direction)
        below, 1/N folded in.  The inverse at |k| >= k_cut is computed once; each cut-off
        inverts only its low wavenumbers (no Nyquist aliases there)."""
        P = self._pre.get(k_cut)
        if P is None:
            g, m = self.grid, self.m
            if not hasattr(self, "_inv"):  # (k = 0 is singular, and always below the cut)
                A = np.stack([np.stack(row, axis=-1) for row in self.M], axis=-2)
                A[g.kmag == 0] = np.eye(m)
                self._inv = np.linalg.inv(A) * (self._scale ** 2)
            low = g.kmag < k_cut
            dirs = tuple(np.broadcast_to(c, g.kshape)[low] for c in g.direction)
            kk = np.full(int(low.sum()), float(k_cut))
            one, zero = np.ones(kk.size), np.zeros(kk.size)
            A = np.empty((kk.size, m, m), dtype=complex)
            for j in range(m):
                src = [one if i == j else zero for i in range(m)]
                u, w = self.film.surface_displacement_transfer(dirs, kk, src[0], tuple(src[1:]))
                for i, v in enumerate((w,) + tuple(u)):
                    A[:, i, j] = v
            inv = self._inv.copy()
            inv[low] = np.linalg.inv(A) * self._scale
            P = tuple(tuple(np.ascontiguousarray(inv[..., i, j]) for j in range(m))
                      for i in range(m))
            if len(self._pre) > 16:
                self._pre.clear()
            self._pre[k_cut] = P
        return P

    def cut(self, C: np.ndarray) -> float:
        """The preconditioner's k_c = pi / W for the contact nodes ``C`` (flat indices): W the
        contact's extent on a line, sqrt of its area on a surface, rounded to 1/16 (1/8) of an
        octave (the cut-off need not be exact, and its inverse is then reused)."""
        g = self.grid
        if self.ndim == 1:
            return math.pi / 2.0 ** (round(16.0 * math.log2(
                max(C[-1] - C[0] + 1, 1) * g.dx)) / 16.0)
        return math.pi / 2.0 ** (round(8.0 * math.log2(math.sqrt(max(C.size, 1) * g.cell)))
                                 / 8.0)

    def self_compliance(self) -> float:
        """The tangential displacement of a node under a unit tangential force on it (the
        symbol's mean: the operator's diagonal), dimensionless."""
        if not hasattr(self, "_a0"):
            r = self._plan[0]
            r.fill(0.0)
            r[(1,) + (0,) * self.ndim] = 1.0
            self._a0 = float(self.transform(self.M)[(1,) + (0,) * self.ndim])
        return self._a0

    def apply(self, p: np.ndarray, q: np.ndarray):
        """(w, u) of the tractions (p, q) (flat fields; q and u (D, n), or (n,) on a line)."""
        r = self._plan[0]
        flat = r.reshape(self.m, -1)
        flat[0] = p
        flat[1:] = np.reshape(q, (self.ndim, -1))
        out = self.transform(self.M).reshape(self.m, -1)
        u = out[1:].copy()
        return out[0].copy(), (u[0] if self.ndim == 1 else u)


PartialSlipOperator2D = PartialSlipOperator
