"""Load-controlled contact on a periodic grid: active set + preconditioned GMRES (dimensionless).

The solver (``solve_complementarity``) knows neither the dimension nor the indenters' shapes: it
takes a Fourier operator H (the surface compliance: sinking w = H p), the height field f of the
indenters above their apexes, which indenter owns each node, and each indenter's load.  The
unknown contact set is found by a primal-dual active-set iteration (a semismooth Newton method
for p >= 0, gap >= 0, p * gap = 0).  For a fixed active set the bordered linear system

    (H p)_j - d_m(j) = -f_j     for active nodes j,
    cell * sum_{j of indenter m} p_j = P_m,

is solved by right-preconditioned GMRES: H is not symmetric when mu != 0, so conjugate gradients
(Polonsky-Keer) do not apply.  The preconditioner is the inverse symbol clipped below
k_c = pi / W (``FourierOperator.preconditioner``), W the extent of the largest contact
((cell count x cell)^(1/ndim): its width in 1D), masked to the active set: it turns the order -1
operator into an order 0 one, so GMRES needs about 10 iterations whatever the grid size.
gap = f - d + w.

``solve_contact`` is the system around it: the film's compliance for friction mu as the
operator, indenters (``physics.indenters``) giving heights and first guesses, each owning the
nodes nearer to its apex than to any other (periodically).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..errors import ConvergenceError
from ..physics.film import Film
from .edges import fit_edges
from .fft import get_rfft
from .grid import Grid
from .krylov import gmres
from .operators import FourierOperator, tail_terms

__all__ = ["ContactSolution", "solve_contact", "solve_complementarity", "compliance_operator",
           "refine_nested", "nested_guess"]


_FILM = Film()  # the default film (frozen: shared)
_SEARCH_STEPS = 8  # active-set steps at most at the loose search_rtol (mu = 30: it wandered)
_NESTED_MIN = {1: 2**13, 2: 64}  # grids of at least twice this per axis start from the
# half-resolution solution (1D: only large grids, so the automatic solver's locators and levels,
# which are small or warm-started, keep their numbers)
_NESTED_FLOOR = {1: 2**13, 2: 64}  # and the chain of halvings goes down to this.  In 1D the
# cold solve's extrapolated edges (_shrunk_ends) take it to ~4 active-set steps (6 GMRES each)
# at any N, about what the three extra levels below 2^13 cost (one step each, and the cold one).
# Measured (paper scene's period and load, frictionless, rtol 1e-10, median CPU ratios in one
# process): floor 2^13 / floor 2^10: film 2^14 0.98 (112 -> 72 FFT pairs), 2^16 0.99
# (140 -> 100), 2^18 0.99 (172 -> 132); half-space 2^14 0.82 (74 -> 44), 2^16 0.98, 2^18 0.99.
# 160 scenes (2^14, 2^16; loads 0.5-300, mu -1...5, three films, L 21.38 and 60): active-set
# steps 2041 -> 1505, FFT pairs 33658 -> 25826.  (Before the extrapolation: 2^10, a cold
# solve then cost ~10 steps at any N.)
_EDGE_REACH = 0.15  # nested first set: the fine nodes within this many cells beyond the coarse
# solution's fitted edges.  Measured (active-set steps of the whole chain, summed over 6 scenes,
# loads 5-380 N/m, mu -1...2.6, cold at 2^20): reach 0: 111, 0.08: 105, 0.15: 99, 0.25: 104,
# 0.35: 116
_EDGE_REACH_2D = 0.15  # (the same in 2D, along rows and columns: see nested_guess)
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


@dataclass
class ContactSolution:
    grid: Grid
    pressure: np.ndarray       # p >= 0 on the grid
    sinking: np.ndarray        # w = H p (surface displacement, positive downward)
    gap: np.ndarray            # f - d + w >= 0
    active: np.ndarray         # bool, contact nodes
    owner: np.ndarray          # int, indenter owning each node
    indentations: np.ndarray   # d_m
    iterations: int            # active-set iterations
    krylov_iterations: int     # GMRES matrix-vector products (one FFT pair each)
    fft_pairs: int             # all FFT pairs (matvecs + preconditioner + residual checks)
    residual: float            # max of the relative residuals below
    residuals: dict = field(default_factory=dict)
    history: list = field(default_factory=list)
    coarse_iterations: int = 0         # active-set iterations of the nested start's coarser grids
    coarse_krylov_iterations: int = 0  # and their GMRES iterations (their FFT pairs are in fft_pairs)
    coarse_fft_pairs: int = 0          # the part of fft_pairs spent on the coarser grids


@lru_cache(maxsize=32)
def compliance_operator(shape: tuple, lengths: tuple, mu: float, film: Film = Film(),
                        slide: tuple = (1.0, 0.0)) -> FourierOperator:
    """The film's surface compliance for friction ``mu`` sliding along ``slide``, on a grid of
    ``shape`` over ``lengths`` (cached: its symbol and preconditioners are reused)."""
    # a viscoelastic film's long relaxation tails (along x): their periodic images summed
    tails = tail_terms(shape, lengths, film.tail_poles(mu * slide[0])) \
        if not any(slide[1:len(shape)]) else ()
    return FourierOperator(Grid(shape, lengths), film.compliance_symbol(mu, slide[:len(shape)]),
                           low_rank=tails)


def solve_complementarity(op: FourierOperator, f: np.ndarray, owner: np.ndarray, loads, *,
                          p_init: np.ndarray, rtol: float = 1e-10, accept: float | None = None,
                          max_outer: int = 200, max_krylov: int = 2000, grid: Grid | None = None,
                          search_rtol: float | None = None, extrapolate: bool = False
                          ) -> ContactSolution:
    """Contact of rigid bodies of heights ``f`` (one field on the grid: each node's height above
    the apex of the body that ``owner`` says it belongs to) pressed with ``loads`` (one per body,
    dimensionless; a body with load 0 is lifted off) on the surface of compliance ``op``.

    p_init : first pressure; its support (within loaded bodies) is the first active set.
    rtol   : relative tolerance (2-norm) of the inner linear solves.
    accept : largest final residual (max-norm, relative: gap, penetration, tension, load)
             accepted; default max(1e3 rtol, 1e-8).  Beyond it ConvergenceError is raised.
    grid   : reported on the solution (default ``op.grid``: the solution's fields have its shape).
    search_rtol : optional looser inner tolerance while the active set is being searched: the
             outer iterations solve to it until the set repeats, then to ``rtol`` (at least one
             more solve, whose set must hold as before).  Only the path changes, not what is
             accepted: for a far first guess (a locator), whose first sets are far off anyway.
    extrapolate : 1D, one body: while the set only sheds tensile end nodes, put its next ends
             where the edges extrapolate to (``_shrunk_ends``) instead of at the pressure's zero
             crossings, which halve the excess per step.  Only the path changes.
    """
    shape = op.grid.shape
    cell = op.grid.cell
    ndim = op.grid.ndim
    f = f.ravel() if isinstance(f, np.ndarray) and f.shape == shape else \
        np.broadcast_to(f, shape).ravel()
    owner = owner.ravel() if isinstance(owner, np.ndarray) and owner.shape == shape else \
        np.broadcast_to(owner, shape).ravel()
    loads = np.asarray(loads, dtype=float)
    n = f.size
    loaded = loads > 0
    M = loads.size
    # +inf: no body there (e.g. beyond sharp ends)
    can_touch = ((np.isfinite(f) if loaded[0] else np.zeros(n, dtype=bool)) if M == 1
                 else loaded[owner] & np.isfinite(f))
    touch_all = bool(can_touch.all())
    add_reduce = np.add.reduce
    nfft = [0]  # FFT pairs
    fft = get_rfft(shape)  # this thread's plan, bound once (op.apply looks it up per call)
    S = op.symbol

    active = (np.asarray(p_init).ravel() > 0) & can_touch
    if M == 1:  # every loaded body needs a foothold
        if loaded[0] and not active.any():
            active[np.argmin(f)] = True
    else:
        for m in np.flatnonzero(loaded):
            if not np.any(active & (owner == m)):
                active[np.flatnonzero(owner == m)[np.argmin(f[owner == m])]] = True

    p = np.where(active, np.asarray(p_init).ravel(), 0.0)
    d = np.zeros(M)
    seen = set()
    history = []
    krylov_total = 0
    rt = max(rtol, search_rtol or rtol)  # the inner tolerance of this outer iteration
    extrapolate = _EXTRAP_STEPS if extrapolate and M == 1 and ndim == 1 else 0
    extrapolated = False  # whether a step was extrapolated (and no cycle met since)
    release = _RELEASE_STEPS if ndim == 2 else 0
    for outer in range(1, max_outer + 1):  # noqa: B007 (the count is reported after the loop)
        idx = active.nonzero()[0]  # (np.flatnonzero of the flat array, without its wrapper)
        own = owner[idx] if M > 1 else None
        ni = idx.size
        # one contiguous run (the common 1D case): a slice gathers and scatters the same
        # elements as the index array, without fancy indexing
        contiguous = bool(ni) and idx[-1] - idx[0] + 1 == ni
        sel = slice(int(idx[0]), int(idx[-1]) + 1) if contiguous else idx
        # weight of each load row: its right-hand side as large as the whole gap block's, so
        # GMRES's 2-norm stopping test controls the load as tightly as the gap
        fi = f[sel]
        gap_norm = math.sqrt(float(fi @ fi))  # np.linalg.norm's operations
        if gap_norm < 1e-150:
            # heights all zero on the set (one node at a smooth apex: a contact smaller than
            # a cell): the load row weighted as the sinking it causes, ~ load / cell^(1 - 1/d)
            # (a weight of 1e-300 let GMRES ignore the load: "residual 1.00e+00 after 1
            # active-set and 1 GMRES iterations", issue 24)
            gap_norm = max(float(np.abs(loads).max()) * cell ** (1.0 / ndim - 1.0)
                           * math.sqrt(max(ni, 1)), 1e-300)
        # preconditioner: inverse symbol clipped below the lowest mode the largest contact holds
        if M == 1 and ndim == 1:  # the same floating-point operations on Python floats
            wload = np.array([gap_norm / loads[0] if loaded[0] else 1.0])
            Hinv = op.preconditioner(math.pi / (max(ni, 1) * cell))
        else:
            extents = (np.array([max(ni, 1)]) if M == 1
                       else np.maximum(np.bincount(own, minlength=M), 1)) * cell
            if ndim > 1:
                extents = extents ** (1.0 / ndim)
            wload = np.where(loaded, gap_norm / np.where(loaded, loads, 1.0), 1.0)
            Hinv = op.preconditioner(np.pi / extents[loaded].max())
        sparse = fft.apply_sparse  # the operators on fields that vanish off the active set
        # the sinking H p of the last matvec: GMRES's last matvec is at the x it returns, so
        # this is H p of the new pressure (the same transform of the same data: no extra pair)
        last_w = [None]
        low = op.low_rank  # a viscoelastic film's long tails (TailTerm)
        if M == 1:  # one body (the common case): no gather by owner, no bincount
            wcell = cell * float(wload[0])

            def matvec(v):
                nfft[0] += 1
                w = last_w[0] = sparse(v[:ni], sel, S)
                for t in low:
                    w += t.field(v[:ni], sel)
                out = np.empty_like(v)
                np.subtract(w[sel], v[ni], out=out[:ni])
                out[ni] = wcell * add_reduce(v[:ni])
                return out
        else:
            def matvec(v):
                nfft[0] += 1
                w = last_w[0] = sparse(v[:ni], sel, S)
                for t in low:
                    w += t.field(v[:ni], sel)
                out = np.empty_like(v)
                out[:ni] = w[sel] - v[ni:][own]
                out[ni:] = cell * np.bincount(own, weights=v[:ni], minlength=M) * wload
                return out

        def psolve(r):
            nfft[0] += 1
            z = np.empty_like(r)
            sparse(r[:ni], sel, Hinv, out=z[:ni])
            z[ni:] = r[ni:]
            return z

        step = None
        if M == 1:
            wstep = np.empty(ni + 1)  # GMRES's w, reused (it is copied into the basis)
            wp = wstep[:ni]
            masked = fft.sparse_applier(sel)
            subtract = np.subtract

            def step(v, z):  # psolve then matvec, the same operations in one call
                nfft[0] += 2
                zp = z[:ni]
                masked(v[:ni], Hinv, zp)
                z[ni] = v[ni]
                masked(zp, S, wp)
                for t in low:
                    np.add(wp, t.at(zp, sel), out=wp)
                subtract(wp, z[ni], out=wp)
                wstep[ni] = wcell * add_reduce(zp)  # (= zp.sum())
                return wstep

        if M == 1:  # the same values as the general concatenations below
            b = np.empty(ni + 1)
            np.negative(fi, out=b[:ni])
            b[ni] = loads[0] * wload[0] if loaded[0] else 0.0
            v0 = np.empty(ni + 1)
            v0[:ni] = p[sel]
            v0[ni] = d[0]
        else:
            b = np.concatenate([-fi, np.where(loaded, loads, 0.0) * wload])
            v0 = np.concatenate([p[idx], d])
        v, its, rel_res = gmres(matvec, psolve, b, v0, rtol=rt, maxiter=max_krylov, step=step)
        if its == 0 and rt > rtol:
            # the start already meets the loose tolerance (a search that has settled): rtol
            # now, on this set, without an active-set step that would only find it unchanged
            rt = rtol
            seen.clear()
            v, its, rel_res = gmres(matvec, psolve, b, v, rtol=rt, maxiter=max_krylov, step=step)
        krylov_total += its
        p = np.zeros(n)
        p[sel] = v[:ni]
        d = v[ni:].copy()
        d[~loaded] = 0.0
        w = last_w[0]
        gap = f - d[0] + w if M == 1 else f - d[owner] + w
        # keep nodes with p >= 0: a node just added by a tiny penetration may keep p = 0
        # exactly when the warm-started GMRES has nothing to do (drop only tensile nodes)
        if contiguous:  # the same sets from slices: inactive nodes off sel, active on it
            new = gap < 0
            new[sel] = p[sel] >= 0
            if not touch_all:
                new &= can_touch
            if extrapolate and ni > 2 and not (new[:sel.start].any() or new[sel.stop:].any()):
                ends = _shrunk_ends(p[sel], sel.start, 1 if outer == 1 else 0)
                if ends is not None:
                    extrapolate -= 1
                    extrapolated = True
                    if not extrapolate:  # the last: then plain steps, whose cycle check
                        seen.clear()     # forgets the extrapolated path
                    new[sel] = False
                    new[ends[0]:ends[1] + 1] = True
                    if not touch_all:
                        new &= can_touch
        else:
            new = ((active & (p >= 0)) | (~active & (gap < 0))) & can_touch
            if release and (active & (p < 0)).any():
                more = _released_tensile(active & ~new, new, p, shape, _release_kernel(op, nfft),
                                         added=new & ~active, gap=gap)
                if more is not None:
                    release -= 1
                    extrapolated = True  # (a cycle through it: the union, as extrapolated steps)
                    if not release:
                        seen.clear()
                    new &= ~more
        history.append((ni, float(rel_res), its))
        key = new.tobytes()
        akey = active.tobytes()
        settled = key == akey
        if rt > rtol and (settled or key in seen or outer >= _SEARCH_STEPS):
            # the search has settled (or cycles, or wanders: strong friction) at the loose
            # tolerance: from here on, rtol
            rt = rtol
            seen.clear()
            if settled:
                continue
        elif settled:
            break
        elif key in seen and extrapolated:
            # a cycle after extrapolated steps (which may have cut into the contact): once,
            # the union of the two sets, from which plain steps shed tensile nodes
            extrapolated = False
            seen.clear()
            new |= active
        elif key in seen:
            # cycling between sets: a degenerate edge node, slightly penetrating when inactive
            # and slightly tensile when active.  Stop here; the residual check below accepts
            # the state only if that violation is negligible, and raises otherwise.
            break
        seen.add(akey)
        for m in (() if M == 1 and new.any() else np.flatnonzero(loaded)):
            if not np.any(new & (owner == m)):
                mine = np.flatnonzero(owner == m)
                new[mine[np.argmin(gap[mine])]] = True
        active = new
    else:
        raise ConvergenceError(
            f"active-set iteration did not settle in {max_outer} iterations "
            f"(last inner residual {history[-1][1]:.2e})",
            residuals=[h[1] for h in history], iterations=max_outer)

    # (sel holds the final active set's nodes: max |.| as max(max, -min), exactly)
    fa, ga = f[sel], gap[sel]
    scale_w = max(float(max(w.max(), -w.min())), float(max(fa.max(), -fa.min())) if ni else 0.0,
                  1e-300)
    pmax = max(p.max(), 1e-300)
    load_res = 0.0
    if M == 1:
        if loaded[0]:
            load_res = abs(cell * p.sum() - loads[0]) / loads[0]
    else:
        for m in np.flatnonzero(loaded):
            load_res = max(load_res, abs(cell * p[owner == m].sum() - loads[m]) / loads[m])
    residuals = {
        "gap": float(max(ga.max(), -ga.min()) / scale_w) if ni else 0.0,
        "penetration": float(max(0.0, -(min(gap[:sel.start].min(initial=0.0),
                                             gap[sel.stop:].min(initial=0.0))
                                         if contiguous and touch_all else
                                         gap[~active & can_touch].min(initial=0.0))) / scale_w),
        "tension": float(max(0.0, -p.min()) / pmax),
        "load": float(load_res),
        "linear": float(history[-1][1]),
    }
    residual = max(residuals.values())
    if residual > (accept if accept is not None else max(1e3 * rtol, 1e-8)):
        raise ConvergenceError(
            f"contact solve ended with relative residual {residual:.2e} "
            f"({', '.join(f'{k} {v:.1e}' for k, v in residuals.items())}) after {outer} "
            f"active-set and {krylov_total} GMRES iterations",
            residuals=[h[1] for h in history], iterations=outer)
    return ContactSolution(grid or op.grid, p.reshape(shape), w.reshape(shape), gap.reshape(shape),
                           active.reshape(shape), owner.reshape(shape), d, outer, krylov_total,
                           nfft[0], residual, residuals, history)


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
    the contact is grown back by the next step's penetrated nodes.  An end that sheds at most ``min_shed`` nodes is
    left where the plain step puts it (1 for the half-space guess, exact on a half-space but
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


def _release_kernel(op: FourierOperator, nfft: list) -> np.ndarray:
    """The grid's compliance between nodes at offsets up to 2 _RELEASE_REACH per axis (the
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


def solve_contact(grid: Grid, mu: float, indenters, *, film: Film | None = None, p_init=None,
                  rtol: float = 1e-10, accept: float | None = None, max_outer: int = 200,
                  max_krylov: int = 2000, search_rtol: float | None = None,
                  extrapolate: bool | None = None) -> ContactSolution:
    """Solve the contact on ``grid`` for friction ``mu`` (sliding toward +x) and the given
    indenters (``physics.indenters``: each gives its height, a first pressure guess and its
    load), on ``film`` (default: the incompressible film of thickness 1, the core's unit).

    p_init : optional initial pressure on the grid (its support is the first active set);
             by default each loaded indenter's own guess (the half-space solution), or on
             large grids the nested start (``_nested_start``).
    extrapolate : as ``solve_complementarity``'s; default: for the cold start (no p_init; on
             a nested grid, its coarsest level's).
    Other options as ``solve_complementarity``.
    """
    film = film or _FILM
    if extrapolate is None:
        extrapolate = p_init is None
    if p_init is None and min(grid.shape) >= 2 * _NESTED_MIN.get(grid.ndim, 64) \
            and all(n % 2 == 0 for n in grid.shape):
        return _nested_start(grid, mu, indenters, film, _NESTED_FLOOR.get(grid.ndim, 64),
                             dict(rtol=rtol, accept=accept, max_outer=max_outer,
                                  max_krylov=max_krylov))
    op = compliance_operator(grid.shape, grid.lengths, float(mu), film)
    if len(indenters) == 1:  # one body owns every node (no distances to compare)
        ind = indenters[0]
        guess = None
        if p_init is None:
            guess = np.broadcast_to(ind.initial_pressure(grid) if ind.load > 0 else 0.0,
                                    grid.shape)
        return solve_complementarity(op, ind.height(grid), np.zeros(grid.shape, dtype=np.intp),
                                     [ind.load], p_init=guess if p_init is None else p_init,
                                     rtol=rtol, accept=accept, max_outer=max_outer,
                                     max_krylov=max_krylov, grid=grid, search_rtol=search_rtol,
                                     extrapolate=extrapolate)
    dist = np.stack([np.broadcast_to(ind.distance(grid), grid.shape) for ind in indenters])
    owner = np.argmin(dist, axis=0)  # nearest apex (periodically); ties to the first
    f = np.zeros(grid.shape)
    guess = np.zeros(grid.shape) if p_init is None else None
    for m, ind in enumerate(indenters):
        mine = owner == m
        f = np.where(mine, ind.height(grid), f)
        if guess is not None and ind.load > 0:
            guess = np.where(mine, ind.initial_pressure(grid), guess)
    return solve_complementarity(op, f, owner, [ind.load for ind in indenters],
                                 p_init=guess if p_init is None else p_init, rtol=rtol,
                                 accept=accept, max_outer=max_outer, max_krylov=max_krylov,
                                 grid=grid, search_rtol=search_rtol)


def nested_guess(coarse: ContactSolution, grid: Grid) -> np.ndarray:
    """The first pressure on ``grid`` (twice ``coarse.grid``'s points per axis, same periods):
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


def _nested_start(grid: Grid, mu: float, indenters, film: Film, floor: int, options: dict
                  ) -> ContactSolution:
    """A cold solve on a large grid: the half-resolution solution (itself nested, down to
    ``floor`` points per axis), interpolated, instead of the half-space guess, whose extra
    nodes cost one active-set step per band of cells (the count then grows with N).  In 1D the
    first active set is the coarse solution's contact up to its fitted edges (+ _EDGE_REACH
    fine cells): mostly one active-set step per level.  The coarse levels'
    work is added to this solve's counters."""
    half = tuple(n // 2 for n in grid.shape)
    coarse_grid = Grid(half, grid.lengths, grid.origin)
    if min(half) >= 2 * floor and all(n % 2 == 0 for n in half):
        coarse = _nested_start(coarse_grid, mu, indenters, film, floor, options)
    else:
        coarse = solve_contact(coarse_grid, mu, indenters, film=film, **options)
    p0 = nested_guess(coarse, grid)
    # (not the coarse indentation: GMRES from it meets rtol sooner, with 10-100x the nodal
    # error at the edge nodes; measured against rtol 1e-14 solves at 2^16-2^20)
    sol = solve_contact(grid, mu, indenters, film=film, p_init=p0, **options)
    sol.fft_pairs += coarse.fft_pairs
    sol.coarse_fft_pairs = coarse.fft_pairs
    sol.coarse_iterations = coarse.iterations + coarse.coarse_iterations
    sol.coarse_krylov_iterations = coarse.krylov_iterations + coarse.coarse_krylov_iterations
    return sol
