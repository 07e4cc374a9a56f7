"""Sub-grid contact edges and peak of a grid solution.

Near an edge e of a smooth contact the gap opens as (x - e)^{3/2} and the pressure closes as
(e - x)^{1/2}.  The nodal gap, computed from the smoothing operator H, is much more accurate than
the nodal pressure next to the edge, so each edge is located by fitting gap^{2/3} (linear in
x - e, plus a curvature term) on the 2nd..5th nodes outside the contact (the 1st is the most
polluted by the discretisation) and taking its root.  Measured accuracy: a few hundredths of the
grid spacing (studies/stability).  Fallbacks, in order: fewer gap nodes, then p^2 extrapolated
from the last two contact nodes, then the midpoint of the cell.
"""
from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["contact_runs", "fit_edges", "peak"]


def contact_runs(active: np.ndarray):
    """Maximal runs of True in a periodic boolean array, as (first, last) node indices
    (last may be < first when a run wraps around the period)."""
    n = active.size
    if not active.any():
        return []
    if active.all():
        raise InputError("the contact fills the whole periodic domain: enlarge domain_length, "
                         "or the scene is beyond the FFT method's range (contact wider than the period)")
    start = int(np.argmin(active))  # an inactive node: no run wraps past it
    a = np.roll(active, -start)
    d = np.diff(np.concatenate([[0], a.astype(np.int8), [0]]))
    firsts = np.flatnonzero(d == 1)
    lasts = np.flatnonzero(d == -1) - 1
    return [((f + start) % n, (e + start) % n) for f, e in zip(firsts, lasts)]


def _edge(x0, dx, gap_out, p_in, free):
    """Distance (in units of dx, >= 0 outward) from the last contact node to the edge.

    gap_out[i]: gap at the i-th node outside (i = 1, 2, ...; index 0 unused), `free` of them
    available before another contact; p_in = (p at last node, p at the one before)."""
    if free >= 5:
        s = np.arange(2, 6, dtype=float)
        y = np.maximum(gap_out[2:6], 0.0) ** (2.0 / 3.0)
        c = np.polyfit(s, y, 2)
        roots = np.roots(c)
        roots = roots[np.isreal(roots)].real
        roots = roots[(roots > -0.25) & (roots < 1.5)]
        if roots.size:
            return float(roots[np.argmin(np.abs(roots - 0.5))])
    if free >= 3:
        y1, y2 = (max(g, 0.0) ** (2.0 / 3.0) for g in gap_out[1:3])
        if y2 > y1:
            t = 1.0 - y1 / (y2 - y1)
            if -0.25 < t < 1.5:
                return float(t)
    p1, p0 = p_in
    if p0 > p1 > 0:  # p^2 linear in distance to the edge
        return float(min(max(p1 * p1 / (p0 * p0 - p1 * p1), 0.0), 1.0))
    return 0.5


def fit_edges(x, dx, gap, pressure, active):
    """Sub-grid (left, right) edges of each contact run, in the coordinates of x (unwrapped so
    that left < right)."""
    n = x.size
    runs = contact_runs(active)
    out = []
    for first, last in runs:
        edges = []
        for side, node in ((+1, last), (-1, first)):
            # nodes outside, up to 6 of them, until the next contact
            outside = [(node + side * i) % n for i in range(0, 7)]
            free = 0
            for i in range(1, 7):
                if active[outside[i]]:
                    break
                free = i
            g = gap[outside]
            p_in = (pressure[node], pressure[(node - side) % n])
            t = _edge(x[node], dx, g, p_in, free)
            edges.append(x[node] + side * t * dx)
        right, left = edges
        if right < left:  # a run that wraps the period
            right += n * dx
        out.append((left, right))
    return out


def peak(x, p):
    """(p_max, x_max) refined by a parabola through the largest node and its neighbours."""
    j = int(np.argmax(p))
    n = p.size
    pm, p0, pp = p[(j - 1) % n], p[j], p[(j + 1) % n]
    den = pm - 2 * p0 + pp
    if den >= 0:
        return float(p0), float(x[j])
    t = 0.5 * (pm - pp) / den
    return float(p0 - 0.25 * (pm - pp) * t), float(x[j] + t * (x[1] - x[0]))
