"""The film's coupled surface compliance (p, q) -> (w, u) on a periodic line or surface grid,
as the partial-slip solver (``numerics.partial_slip``) applies it: the (1 + D) x (1 + D) symbol
of ``Film.surface_displacement_transfer`` (D = 1 or 2 tangential components) on 1 + D fields in
one batched real FFT (1 + D FFT pairs), and the clipped inverse symbols of its preconditioner.
Dimensionless core (lengths in h, tractions in G h/2R, displacements in h^2/2R).

On a surface the solver's fields vanish outside the contact, a band of rows of the grid (x
from its first to its last node; the sphere's 1 N contact on 256^2: ~48 of 256 rows, the rest
is the kernels' decay margin), and it reads the results on the contact only: ``transform``
with ``rows`` does the transform along y (r2c, and c2r back) on those rows only, the one along
x (c2c) on every column as before: the transform of 3 fields with a band of 48 rows 0.72
against 1.04 ms on 256^2, 0.14 against 0.23 ms on 128^2 with 24 (the symbol product, ~0.26 ms
on 256^2, is the same; studies/README.md, onset).  The other rows of the output are then left
undefined; ``full_output`` completes them (one c2r pass along y on every row, 0.19 ms on
256^2) where the whole field is needed."""
from __future__ import annotations

import math

import numpy as np

from ..physics.film import Film
from .grid import Grid

__all__ = ["PartialSlipOperator", "PartialSlipOperator2D"]

_PLANS: dict = {}
_ROWS: dict = {}
_ROW_PLANS = 64  # band plans kept per grid (one per band of rows: start and height)
_SPARE_BYTES = 2 ** 26  # the band transform's spare spectrum buffer (the backward x-pass out of
# place) up to this size (~1024^2 points, 3 fields); larger grids run that pass in place


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


class _Rows:
    """The row-pruned transform of ``_plan(shape, m)``'s buffers on a 2D grid: along y (the
    last axis) on a band of rows only, along x on every column.  ``a`` holds the forward
    y-pass (zero outside the band: the x-pass reads every row of it); the backward x-pass
    writes ``b`` (out of place: 0.15 against 0.20 ms in place at 256^2, 3 fields; in place,
    ``b`` the product's buffer, beyond ``_SPARE_BYTES``), whose band the y-pass then reads
    without destroying it, so that ``full_output`` can still complete every row."""

    def __init__(self, shape: tuple, m: int):
        import pyfftw

        from . import fft as _fft

        self.r, self.c, self.o = _plan(shape, m)[:3]
        self.a = pyfftw.zeros_aligned(self.c.shape, dtype="complex128")
        self.b = self.o if self.c.nbytes > _SPARE_BYTES else \
            pyfftw.empty_aligned(self.c.shape, dtype="complex128")
        effort = (_fft._PLANNER_EFFORT,)
        self.x_fwd = pyfftw.FFTW(self.a, self.c, axes=(1,), flags=effort).execute
        self.x_bwd = pyfftw.FFTW(self.o, self.b, axes=(1,), direction="FFTW_BACKWARD",
                                 flags=effort).execute
        self.y_all = pyfftw.FFTW(self.b, self.r, axes=(2,), direction="FFTW_BACKWARD",
                                 flags=effort + ("FFTW_DESTROY_INPUT",)).execute
        self.band = None  # the rows of ``a`` that may be nonzero
        self.pending = False  # the last transform was pruned: rows outside it undefined
        self.plans: dict = {}
        self.effort = effort

    def y(self, i0: int, i1: int):
        """The forward and backward y-passes of rows i0:i1 (planned once per band)."""
        import pyfftw

        key = (i0, i1)
        plan = self.plans.get(key)
        if plan is None:
            r, a, b = self.r[:, i0:i1], self.a[:, i0:i1], self.b[:, i0:i1]
            plan = self.plans[key] = (
                pyfftw.FFTW(r, a, axes=(2,), flags=self.effort).execute,
                pyfftw.FFTW(b, r, axes=(2,), direction="FFTW_BACKWARD",
                            flags=self.effort).execute)  # (input preserved: ``full``)
            if len(self.plans) > _ROW_PLANS:
                self.plans.pop(next(iter(self.plans)))
        if self.band != key:
            if self.band is None:
                self.a.fill(0.0)
            else:
                self.a[:, self.band[0]:self.band[1]] = 0.0
            self.band = key
        return plan


def _rows(shape: tuple, m: int) -> _Rows:
    key = (shape, m)
    rows = _ROWS.get(key)
    if rows is None or rows.r is not _plan(shape, m)[0]:
        rows = _ROWS[key] = _Rows(shape, m)
        if len(_ROWS) > 8:
            _ROWS.pop(next(iter(_ROWS)))
    return rows


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
        self._rows = _rows(grid.shape, self.m) if self.ndim == 2 else None
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

    def transform(self, M, rows=None):
        """The symbol ``M`` (``self.M`` or a ``preconditioner``, 1/N folded in) applied to the
        plan's real buffer (filled by the caller, shape (1 + D, *grid.shape)); returns that
        buffer, overwritten by the result (valid until the next call).  ``rows`` (a surface's
        ``band``): the input vanishes outside these rows and the result is computed on them
        only (``full_output`` completes the others)."""
        r, c, o, fwd, bwd = self._plan
        if rows is None:
            fwd()
        else:
            pr = self._rows
            y_fwd, y_bwd = pr.y(*rows)
            y_fwd()
            pr.x_fwd()
        tmp = self._tmp
        for i in range(self.m):
            Mi, oi = M[i], o[i]
            np.multiply(Mi[0], c[0], out=oi)
            for j in range(1, self.m):
                np.multiply(Mi[j], c[j], out=tmp)
                oi += tmp
        if rows is None:
            bwd()
            if self.ndim == 2:
                self._rows.pending = False
        else:
            pr.x_bwd()
            y_bwd()
            pr.pending = True
        return r

    def full_output(self):
        """The last ``transform``'s result on every row (after a pruned one; else nothing to
        do): the buffer ``transform`` returned."""
        if self.ndim == 2 and self._rows.pending:
            self._rows.y_all()
            self._rows.pending = False
        return self._plan[0]

    def band(self, C: np.ndarray):
        """The rows (start, stop) holding the flat nodes ``C`` (sorted; a surface), rounded up
        to 8 rows (fewer band plans)."""
        nx, ny = self.grid.shape
        i0, i1 = int(C[0]) // ny, int(C[-1]) // ny + 1
        nb = min(nx, -(-(i1 - i0) // 8) * 8)
        i0 = min(i0, nx - nb)
        return i0, i0 + nb

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
