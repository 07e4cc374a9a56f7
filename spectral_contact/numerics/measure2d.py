"""Measuring a contact on a 2D surface grid (the dimension-specific part of the 3D solver).

Edges are located to a small fraction of a cell along every grid line by the 1D edge fit
(``edges.fit_edges``: the gap opens as distance^{3/2}); the area is that of the polygon through
the fitted edge points, each taken from the line (row or column) that crosses the boundary more
steeply (the lines that graze it are poorly fitted): against the axisymmetric reference its
radius error falls steadily, ~dx^2, from 1e-2 to 3e-5 (tests/test_three_d.py); where a line
holds several runs, the mean of the row-wise and column-wise integrals of the chords.  The
extents are the envelopes of the fitted edges, refined across lines by a parabola through the
extreme line and its neighbours.

A viscoelastic film sliding along x (``trailing`` = (side, [(c_j, l_j)]),
``Film.trailing_edge_layer``): behind its trailing edges the gap opens through the film's
memory (``edges.viscous_gap``, the line's inner layer).  At a boundary point whose normal makes
an angle theta with x the inner problem is the line's along the normal n with lengths
l_j |cos theta| (the memory acts along x); along an x row (n = |cos theta| s) the gap is
|cos theta|^{3/2} G_{l}(s): the rows' trailing edges are fitted with the lengths l_j as they
are; along a y column (n = |sin theta| s) it is |sin theta|^{3/2} G_{l |cot theta|}(s), |cot
theta| the slope |dy/dx| of the boundary: the columns' trailing edges are refitted with l_j
times the slope of their first (elastic) fits.
The peak pressure on a viscoelastic film (``trailing`` given) is fitted over 7 nodes along x
with the x-Nyquist (odd-even) mode as an unknown of its own (``edges.peak_odd_even``): with the edge
structure |V| tau narrower than a cell, the discrete contact carries a node-to-node alternating
pressure along x across the contact whose amplitude falls with the cell (measured on a film 11
times stiffer when glassy, 1 mm/s: 0.8 %, 0.35 %, 0.11 % of p_max at 256^2, 512^2, 1024^2;
0.015 % at E_1 = E_inf).  It is a grid mode, not part of the continuum pressure (smooth on the
cell's scale at its peak, away from the edges): the levels should compare the smooth part's
peak, not the mode's sign at the largest node.  Elastic films: the 3-node parabola as before.
Lengths in the grid's unit; arrays indexed [x, y].
"""
from __future__ import annotations

import numpy as np

from .edges import contact_runs, fit_edges, peak, peak_odd_even

__all__ = ["measure_contact_2d"]


def _finite_gap(gap):
    """Edge fits need finite gaps: +inf (no indenter there, e.g. beyond a cylinder's sharp
    end) becomes the largest finite gap, so the fit falls back to the pressure side."""
    if np.all(np.isfinite(gap)):
        return gap
    big = np.max(gap[np.isfinite(gap)], initial=1.0)
    return np.where(np.isfinite(gap), gap, 10.0 * abs(big) + 1.0)


_PRESSURE_NODES = 4  # contact nodes of a trailing edge's pressure-side fit (``_pressure_root``)


def _pressure_root(p_in):
    """Offset (cells, outward, in (-0.25, 1.5)) of an edge from its last contact node, from the
    pressure side: p^2 on the last _PRESSURE_NODES contact nodes (``p_in[k]``: k nodes inward)
    fitted by a least-squares parabola in the inward distance, its root nearest the contact
    (the pressure closes as sqrt(eps) at a trailing edge on any film: ``edges.viscous_gap``);
    None if it has none there."""
    u = np.arange(len(p_in), dtype=float)
    c2, c1, c0 = np.polyfit(u, np.square(p_in), 2)
    if c2 == 0.0 and c1 == 0.0:
        return None
    roots = np.roots((c2, c1, c0)) if c2 != 0.0 else np.array([-c0 / c1])
    inside = [float(z.real) for z in np.atleast_1d(roots)
              if abs(z.imag) <= 1e-12 * max(1.0, abs(z.real)) and -1.5 < z.real < 0.25]
    return -max(inside) if inside else None


def _trailing_from_pressure(coord, d, p, active, runs, side):
    """``runs`` (fit_edges' (left, right) per run) with each run's trailing edge (``side`` -1
    the left one) from the pressure side (``_pressure_root``) where its last _PRESSURE_NODES
    nodes are in contact and the fit has a root."""
    n = coord.size
    out = []
    for (first, last), (left, right) in zip(contact_runs(active), runs):
        node = first if side < 0 else last
        inward = [(node - side * k) % n for k in range(_PRESSURE_NODES)]
        if active[inward].all():
            t = _pressure_root(p[inward])
            if t is not None:
                edge = coord[node] + side * t * d
                left, right = (edge, right) if side < 0 else (left, edge)
        out.append((left, right))
    return out


def _chords(coord, d, gap, p, active, trailing=None, from_pressure=False):
    """Per line (axis 1 of the arrays): total chord length, first and last edge (nan if the
    line has no contact); ``trailing``: the lines' trailing edges' layer (``fit_edges``), or
    with ``from_pressure`` their pressure-side fit (``_trailing_from_pressure``)."""
    m = active.shape[1]
    length = np.zeros(m)
    lo = np.full(m, np.nan)
    hi = np.full(m, np.nan)
    for j in np.flatnonzero(active.any(axis=0)):
        runs = fit_edges(coord, d, gap[:, j], p[:, j], active[:, j], trailing)
        if from_pressure and trailing is not None:
            runs = _trailing_from_pressure(coord, d, p[:, j], active[:, j], runs, trailing[0])
        length[j] = sum(r - left for left, r in runs)
        lo[j] = min(left for left, _ in runs)
        hi[j] = max(r for _, r in runs)
    return length, lo, hi


def _column_layer(x, y, dy, gap, p, active, length, bottom, top, trailing, from_pressure=False):
    """The columns' trailing edges refitted with the inner layer (module docstring): a column
    with one run whose bottom (top) edge trails, i.e. its outward normal's x component has
    the sign of the trailing side, and whose boundary slope |dy/dx| (of the first fits) is
    within 1 (the columns the area takes points from), gets that edge from ``fit_edges`` with
    the lengths l_j |dy/dx|; its chord ``length`` follows.  In place."""
    side_x, terms = trailing
    ok = np.flatnonzero(np.isfinite(bottom))
    if ok.size < 3:
        return
    for e, sigma in ((bottom, -1), (top, +1)):
        slope = np.gradient(e[ok], x[ok])
        for i, s in zip(ok, slope):
            # outward normal ~ (-sigma s, sigma): trailing when -sigma s has side_x's sign
            if not (0.0 < -sigma * s * side_x and abs(s) <= 1.0):
                continue
            runs = fit_edges(y, dy, gap[i], p[i], active[i],
                             (sigma, [(c, ell * abs(s)) for c, ell in terms]))
            if from_pressure:
                runs = _trailing_from_pressure(y, dy, p[i], active[i], runs, sigma)
            if len(runs) == 1:
                new = runs[0][0] if sigma < 0 else runs[0][1]
                length[i] += sigma * (new - e[i])
                e[i] = new


def _boundary_area(x, y, left, right, bottom, top):
    """Area of the polygon through the fitted edge points, each taken from the grid line that
    crosses the boundary more steeply (rows where the boundary runs within 45 degrees of y,
    columns elsewhere): grazing lines, whose 1D fits are poor, are left out.  Needs one run per
    line and a contact star-shaped about its centre; returns None otherwise."""
    pts = []
    for coord, lo, hi, along_x in ((y, left, right, True), (x, bottom, top, False)):
        ok = np.flatnonzero(np.isfinite(lo))
        if ok.size < 3:
            return None
        c = coord[ok]
        for e in (lo[ok], hi[ok]):
            slope = np.abs(np.gradient(e, c))  # d(edge)/d(line coordinate)
            keep = slope <= 1.0
            keep[[0, -1]] = False  # the end lines graze the boundary
            pts.extend(zip(e[keep], c[keep]) if along_x else zip(c[keep], e[keep]))
    if len(pts) < 8:
        return None
    pts = np.array(pts)
    xc, yc = pts.mean(axis=0)
    order = np.argsort(np.arctan2(pts[:, 1] - yc, pts[:, 0] - xc))
    px, py = pts[order, 0], pts[order, 1]
    return 0.5 * abs(np.dot(px, np.roll(py, -1)) - np.dot(py, np.roll(px, -1)))


def _extreme(values, coord, d, largest):
    """The extreme of per-line values, refined by a parabola through the extreme line and its
    two neighbours (when they have contact)."""
    v = values if largest else -values
    ok = np.isfinite(v)
    if not ok.any():
        return 0.0
    j = int(np.nanargmax(np.where(ok, v, -np.inf)))
    best = v[j]
    if 0 < j < v.size - 1 and ok[j - 1] and ok[j + 1]:
        a, b, c = v[j - 1], v[j], v[j + 1]
        den = a - 2 * b + c
        if den < 0:
            best = b - 0.125 * (a - c) ** 2 / den
    return float(best if largest else -best)


def measure_contact_2d(grid, pressure, gap, active, trailing=None, from_pressure=False) -> dict:
    """Contact measures of a 2D solution: ``area``, ``x_min``, ``x_max``, ``y_min``,
    ``y_max`` (envelope of the fitted edges), ``pmax`` and its position (``xmax``, ``ymax``),
    the pressure centroid ``xc`` (= Int x p / Int p), ``load`` (= Int p) and ``line_load_y0``
    (Int p(x, y0) dx on the grid line nearest y = 0).  ``trailing``: a viscoelastic film's
    trailing edges' inner layer, (side along x, [(c_j, l_j)]) in the grid's unit (module
    docstring)."""
    x, y = grid.axes
    dx, dy = grid.spacing
    gap = _finite_gap(gap)
    if not active.any():
        return {"area": 0.0, "x_min": 0.0, "x_max": 0.0, "y_min": 0.0, "y_max": 0.0, "pmax": 0.0,
                "xmax": 0.0, "ymax": 0.0, "xc": 0.0, "load": 0.0, "line_load_y0": 0.0}
    # rows: lines along x at each y; columns: lines along y at each x
    len_x, left, right = _chords(x, dx, gap, pressure, active, trailing, from_pressure)
    len_y, bottom, top = _chords(y, dy, gap.T, pressure.T, active.T)
    if trailing is not None:
        _column_layer(x, y, dy, gap, pressure, active, len_y, bottom, top, trailing,
                      from_pressure)
    area = 0.5 * (len_x.sum() * dy + len_y.sum() * dx)
    single = np.allclose(len_x[np.isfinite(left)], (right - left)[np.isfinite(left)]) and \
        np.allclose(len_y[np.isfinite(bottom)], (top - bottom)[np.isfinite(bottom)])
    polygon = _boundary_area(x, y, left, right, bottom, top) if single else None
    i, j = np.unravel_index(int(np.argmax(pressure)), pressure.shape)
    px, xm = peak(x, pressure[:, j]) if trailing is None else \
        peak_odd_even(x, pressure[:, j], wrap=False)  # (the column's increment below: the mode
    py, ym = peak(y, pressure[i, :])            # is the same sign along it, it cancels)
    load = float(pressure.sum() * dx * dy)
    j0 = int(np.argmin(np.abs(y)))
    return {
        "area": float(area if polygon is None else polygon),
        "x_min": _extreme(left, y, dy, largest=False),
        "x_max": _extreme(right, y, dy, largest=True),
        "y_min": _extreme(bottom, x, dx, largest=False),
        "y_max": _extreme(top, x, dx, largest=True),
        "pmax": float(px + py - pressure[i, j]),
        "xmax": float(xm),
        "ymax": float(ym),
        "xc": float((pressure.sum(axis=1) * x).sum() * dx * dy / load) if load > 0 else 0.0,
        "load": load,
        "line_load_y0": float(pressure[:, j0].sum() * dx),
    }
