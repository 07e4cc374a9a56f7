"""Nested starts of a contact solve: a solution on a grid interpolated onto the grid of twice
its points per axis (same periods, node j -> node 2j), with the contact set it starts from.

``refine_nested`` interpolates a nodal field; ``nested_guess`` also sets the first pressure's
support to the coarse contact up to its fitted edges (1D: the runs' edges; 2D: chords along
rows and columns).  Used by ``numerics.contact`` (a cold solve on a large grid starts from the
half-resolution solution) and by the FFT solvers' refinement levels (``solvers.fft``,
``solvers.fft3d``).
"""
from __future__ import annotations

import numpy as np

from .edges import fit_edges

__all__ = ["refine_nested", "nested_guess"]

_EDGE_REACH = 0.15  # nested first set: the fine nodes within this many cells beyond the coarse
# solution's fitted edges.  Measured (active-set steps of the whole chain, summed over 6 scenes,
# loads 5-380 N/m, mu -1...2.6, cold at 2^20): reach 0: 111, 0.08: 105, 0.15: 99, 0.25: 104,
# 0.35: 116
_EDGE_REACH_2D = 0.15  # (the same in 2D, along rows and columns: see nested_guess)


def refine_nested(p: np.ndarray) -> np.ndarray:
    """Linear interpolation of a periodic nodal field onto the grid of twice the points per
    axis (nested: node j becomes node 2j), any number of dimensions; negative values (none
    from a contact solve) are clipped."""
    out = p
    for axis in range(p.ndim):
        shape = list(out.shape)
        shape[axis] *= 2
        fine = np.empty(shape)
        even = [slice(None)] * p.ndim
        odd = [slice(None)] * p.ndim
        even[axis] = slice(0, None, 2)
        odd[axis] = slice(1, None, 2)
        fine[tuple(even)] = out
        if p.ndim == 1:  # np.roll's values, without its overhead
            nxt = np.empty_like(out)
            nxt[:-1] = out[1:]
            nxt[-1:] = out[:1]
        else:
            nxt = np.roll(out, -1, axis=axis)
        fine[tuple(odd)] = 0.5 * (out + nxt)
        out = fine
    return np.maximum(out, 0.0)


def nested_guess(coarse, grid) -> np.ndarray:
    """The first pressure on ``grid`` (a ``Grid``, twice the points per axis of the grid of the
    ``ContactSolution`` ``coarse``, same periods):
    the coarse pressure interpolated (``refine_nested``), its support set to the coarse
    contact up to its fitted edges (+ _EDGE_REACH fine cells).  1D: the runs' edges.  2D: the
    contact boundary is a curve: along every coarse row and column its fitted edges give a
    chord (centre c, half-width w); a fine node is inside when a row chord or a column chord,
    interpolated to its line (c linearly, w^2 linearly: below a convex boundary's), holds it.
    Rows resolve the boundary where it crosses them steeply, columns near the rows' extremes."""
    p0 = refine_nested(coarse.pressure)
    if not coarse.active.any() or grid.ndim > 2:
        return p0
    cg = coarse.grid
    if grid.ndim == 1:
        edges = fit_edges(cg.x, cg.dx, coarse.gap, coarse.pressure, coarse.active)
        x, L, dx = grid.x, grid.length, grid.dx
        inside = np.zeros(grid.n, dtype=bool)
        for left, right in edges:
            lo = left - _EDGE_REACH * dx
            inside |= np.mod(x - lo, L) < (right - left) + 2 * _EDGE_REACH * dx
        return np.where(inside, np.maximum(p0, 1e-12), 0.0)
    gap = coarse.gap
    if not np.all(np.isfinite(gap)):  # (sharp ends: +inf where no body; as measure2d)
        big = np.max(gap[np.isfinite(gap)], initial=1.0)
        gap = np.where(np.isfinite(gap), gap, 10.0 * abs(big) + 1.0)
    inside = np.zeros(grid.shape, dtype=bool)
    for axis in (0, 1):  # rows (chords along x, axis 0) then columns (along y)
        other = 1 - axis
        coord, across = cg.axes[axis], cg.axes[other]
        d = cg.spacing[axis]
        g2, p2, a2 = ((gap, coarse.pressure, coarse.active) if axis == 0 else
                      (gap.T, coarse.pressure.T, coarse.active.T))
        lines = np.flatnonzero(a2.any(axis=0))
        if lines.size < 2 or lines[-1] - lines[0] + 1 != lines.size:
            continue  # a contact across the period or in pieces: the other direction's
        c = np.zeros(lines.size)
        w2 = np.zeros(lines.size)
        one = np.ones(lines.size)  # lines holding one run (a chord)
        for i, j in enumerate(lines):
            runs = fit_edges(coord, d, g2[:, j], p2[:, j], a2[:, j])
            if len(runs) > 1:  # (e.g. columns through a finite cylinder's two wider ends:
                one[i] = 0.0   # left to the rows; their span as one chord cost it 5 steps)
                continue
            lo, hi = runs[0]
            c[i], w2[i] = 0.5 * (lo + hi), (0.5 * (hi - lo)) ** 2
        fine_across = grid.axes[other]
        t = across[lines]
        ok = (fine_across >= t[0]) & (fine_across <= t[-1])
        ok[ok] = np.interp(fine_across[ok], t, one) == 1.0  # between two chords
        cf = np.interp(fine_across[ok], t, c)
        wf = np.sqrt(np.interp(fine_across[ok], t, w2)) + _EDGE_REACH_2D * grid.spacing[axis]
        fine = grid.axes[axis]
        lines_in = (np.abs(fine[:, None] - cf[None, :]) <= wf[None, :])  # [along, across]
        if axis == 0:
            inside[:, ok] |= lines_in
        else:
            inside[ok, :] |= lines_in.T
    if not inside.any():
        return p0
    return np.where(inside, np.maximum(p0, 1e-12), 0.0)
