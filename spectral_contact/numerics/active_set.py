"""The active-set steps' shortcuts of the contact solver (``numerics.contact``): where a plain
primal-dual step would take several steps to shed tensile nodes, predict the set they end with.

- ``_shrunk_ends`` (1D, one body, a cold start): a set that only sheds tensile end nodes has its
  next ends put where the edges extrapolate to, not at the pressure's zero crossings.
- ``_released_tensile`` (2D): the nodes that releasing the tensile ones (and closing the
  penetrated ones) would turn tensile, from the grid's own compliance on small patches
  (``_release_kernel``).

Only the path of the active-set iteration changes: every step's set is checked by the next
solve as before.
"""
from __future__ import annotations

import math

import numpy as np

from .fft import get_rfft

__all__: list[str] = []  # private helpers of numerics.contact (which imports them by name)

_EXTRAP_WEIGHT = 0.7  # the cold start's shrinking steps extrapolate the edges (_shrunk_ends)
_EXTRAP_STEPS = 3  # this many times at most (then plain steps: they cannot cycle through them)
_RELEASE_REACH = 2  # 2D: a step that sheds tensile nodes also sheds the nodes that the
# release (and the step's added nodes) would turn tensile, predicted from the grid's own
# compliance on the (2r+1)^2 nodes around each changed node (_released_tensile; issue 25).
# Measured (sliding sphere mu 1, the public solve at 2048^2, the finest grid's first step: 34
# nodes shed, 2 of their neighbours at p = +1.3e-3 p_max turned tensile, -7.5e-4, on the next
# solve: a third step): predicted within 2e-5 p_max of the next solve's pressures at r = 2, 3
# and 4 (r = 2: 5 x 5 patches)
_RELEASE_STEPS = 3  # this many steps at most (then plain steps, as _EXTRAP_STEPS)
_RELEASE_ROUNDS = 3  # predicted tensile nodes are released in turn this many times at most
_SET_EDGE = 0.5  # a set's continuum edge, in cells beyond its end node.  Measured (cold, rtol
# 1e-10, 72 scenes: N 2^10-2^13, loads 3.5-53, mu 0 and 1, the film and the half-space; active-
# set steps, FFT pairs): plain 179, 2724; weight 0.7 edge 0.5 at most 3 times: 117-120, 1852-1872;
# weight 1: 138, 2129 (more overshoot, two-set cycles undone by the union below); 2 times: 121


def _shrunk_ends(pa: np.ndarray, start: int, min_shed: int = 0):
    """The next active set's first and last nodes when the set [start, start + pa.size) only
    sheds tensile end nodes (None when neither end is tensile).  On a half-space, a set of
    half-width b about the contact's centre holds p = alpha sqrt(b^2 - x^2) + beta /
    sqrt(b^2 - x^2), beta = alpha (a^2 - b^2) / 2 for the contact's half-width a: its zero
    crossings x0 (what the plain step keeps) satisfy x0^2 = (a^2 + b^2) / 2, so each end is
    moved to sqrt(2 x0^2 - b^2) from the set's centre, b its distance to the end node plus
    _SET_EDGE cells.  The film is stiffer at long waves: its plain step sheds more than half
    the excess, the full extrapolation overshoots into the contact, so only _EXTRAP_WEIGHT of
    it is taken (the move is to sqrt(x0^2 - w (b^2 - x0^2))); an end that still lands inside
    the contact is grown back by the next step's penetrated nodes.  An end that sheds at most
    ``min_shed`` nodes is left where the plain step puts it (1 for the half-space guess, exact on a half-space but
    for a node at each end: extrapolated, it would cut one more)."""
    n = pa.size
    neg = pa < 0
    if not (neg[0] or neg[-1]) or neg.all():
        return None
    kl = int(np.argmin(neg))               # first node with p >= 0
    kr = n - 1 - int(np.argmin(neg[::-1]))  # last node with p >= 0
    c = 0.5 * (n - 1)
    b = c + _SET_EDGE
    ends = []
    for k, side in ((kl, -1), (kr, 1)):
        if abs(k - (0 if side < 0 else n - 1)) <= min_shed:  # as the plain step
            ends.append(k)
            continue
        j = k + side  # the tensile node next to the zero crossing
        x0 = k + side * pa[k] / (pa[k] - pa[j])  # linear interpolation (nodes' index units)
        r = abs(x0 - c)
        e = math.sqrt(max(r * r - _EXTRAP_WEIGHT * (b * b - r * r), 0.0))
        ends.append(math.ceil(c - e) if side < 0 else math.floor(c + e))
    lo, hi = max(ends[0], 0), min(ends[1], n - 1)
    if lo > hi or lo > kr or hi < kl:
        return None
    return start + lo, start + hi


def _release_kernel(op, nfft: list) -> np.ndarray:
    """The grid's compliance (of the ``FourierOperator`` ``op``) between nodes at offsets up to
    2 _RELEASE_REACH per axis (the
    response at node offset (i, j) to a unit nodal pressure: the inverse transform of the
    symbol), cached on the operator; computing it counts as one FFT pair in ``nfft``."""
    key = (_RELEASE_REACH, op.grid.shape)
    cached = getattr(op, "_release_kernel", None)
    if cached is not None and cached[0] == key:
        return cached[1]
    nfft[0] += 1
    full = get_rfft(op.grid.shape).backward(op.symbol)
    r2 = 2 * _RELEASE_REACH
    ix = np.arange(-r2, r2 + 1) % op.grid.shape[0]
    iy = np.arange(-r2, r2 + 1) % op.grid.shape[1]
    kern = full[np.ix_(ix, iy)].copy()  # [offset_x + r2, offset_y + r2]
    op._release_kernel = (key, kern)
    return kern


def _released_tensile(shed: np.ndarray, keep: np.ndarray, p: np.ndarray, shape: tuple,
                      kern: np.ndarray, added: np.ndarray | None = None,
                      gap: np.ndarray | None = None):
    """2D: the nodes of ``keep`` (the next active set, flat) that releasing the tensile nodes
    ``shed`` (flat, p < 0 there, to p = 0) would turn tensile (None when none would).

    A released node no longer pulls the surface to the indenter; its active neighbours carry
    the difference (and a node ``added`` with gap < 0 takes load from them as its gap closes).
    Around each released or added node c, on the (2r+1)^2 nodes within r = _RELEASE_REACH
    cells, the pressures of the next set's nodes u change by dp with their sinking changed by
    dw_u = 0 (kept nodes) or -gap_u (added nodes): K_uu dp_u = dw_u + K_us p_s (K the grid's
    nodal compliance ``kern``, s the released nodes there; the nodes beyond the patch and the
    indentation held).  A node covered by several patches takes the prediction of the one whose
    centre is nearest.  Nodes predicted p + dp < 0 are released in turn, or not added
    (_RELEASE_ROUNDS times at most).  Only the path changes: the next solve checks every node
    as before."""
    nx, ny = shape
    r = _RELEASE_REACH
    o = np.arange(-r, r + 1)
    ox, oy = (a.ravel() for a in np.meshgrid(o, o, indexing="ij"))
    # the patch's compliance matrix: K[a, b] = kern[offset_a - offset_b]
    K = kern[(ox[:, None] - ox[None, :]) + 2 * r, (oy[:, None] - oy[None, :]) + 2 * r]
    ring = np.maximum(np.abs(ox), np.abs(oy))
    eye = np.eye(ox.size)
    if added is None or not added.any():
        added, dw_all = np.zeros(p.size, dtype=bool), None
    else:
        dw_all = np.where(added, -gap, 0.0)
    extra = np.zeros(p.size, dtype=bool)
    found = False
    for _ in range(_RELEASE_ROUNDS):
        released = shed | extra
        kept = keep & ~extra
        cx, cy = np.divmod(np.flatnonzero(released | added), ny)
        nodes = ((cx[:, None] + ox) % nx) * ny + (cy[:, None] + oy) % ny  # [centre, offset]
        k = kept[nodes]
        src = np.where(released[nodes], p[nodes], 0.0)
        rhs = src @ K.T
        if dw_all is not None:
            rhs += dw_all[nodes]
        A = np.where(k[:, :, None] & k[:, None, :], K, 0.0) + np.where(k, 0.0, 1.0)[:, :, None] * eye
        dp = np.linalg.solve(A, np.where(k, rhs, 0.0)[:, :, None])[:, :, 0]
        # each kept node once, from its nearest centre
        flat, dist, pred = nodes[k], np.broadcast_to(ring, k.shape)[k], (p[nodes] + dp)[k]
        order = np.lexsort((dist, flat))
        first = np.unique(flat[order], return_index=True)[1]
        pick = flat[order][first]
        tensile = pick[pred[order][first] < 0]
        if not tensile.size:
            break
        extra[tensile] = True
        found = True
    return extra if found else None
