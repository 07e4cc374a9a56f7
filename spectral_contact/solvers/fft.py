"""The spectral (FFT) method for one cylinder: resolution chosen from a tolerance.

1. A coarse solve on a generous domain locates the contact (half-width a, centre x_c).
2. The period is set to L = 2a + ln(100/tol)/kappa (+ a small guard), with kappa = 0.739/h the
   slowest decay rate of the film's kernels, so periodic images perturb the solution by
   ~tol/100 (times an amplitude of order 1: measured up to ~1.3 at mu = 10).  A viscoelastic
   film: the free length beyond which its kernel's far field (the elastic poles times R there,
   the relaxation tails shorter than 2.7 h), over the located contact's stiffness |R(1/a)|,
   stays below the elastic film's at its margin (``ViscoelasticFilm.line_margin``); the
   longer tails' images are summed exactly by the operator (numerics.operators.tail_terms).
3. The grid is doubled (N = 2^m, same period, nested nodes, each level started from the previous
   solution) until the estimate from the levels' differences (_discretisation_error) is below
   ``tol``, from the third level on.
4. The edges' error is a zero-mean periodic function of where they fall within a cell (times
   dx; studies/stability shows the curve), so every level is solved on the grid and on the grid
   shifted by half a cell, and a, x_c, d, p_max are the mean of the two: that cancels the odd
   harmonics of the phase error.  The estimate also keeps a quarter of the shift difference,
   so that two levels agreeing by chance cannot stop the refinement early
   (Chebfun-style: the data decide the resolution, and the estimate is returned).

Users may fix ``grid_points`` and/or ``domain_length``; the estimate then compares N with N/2
and adds the shifted-grid term.

The periodic images' error, ~amplitude * exp(-DECAY_RATE (L - 2a)) (amplitude measured <= 1.53
for |mu| <= 10), is part of the estimate; a user-fixed period that cannot bring it below tol/2
is refused.  Above |mu| = 10 or a = 8 h it is measured instead (the final level against the same nodes on
the period 2L) and an automatic period is lengthened until it is below tol/4; so on a
viscoelastic film whose far field is not bounded by the elastic one's (``image_factor``), and
with friction in the contact where that bound times d_el/d (the relaxed film's indentation
over the solve's: d is relative to itself) would pass tol/4 or the estimate tol
(``_LineSolve._friction_images``).  The locator
enlarges its own period when strong friction widens the contact beyond the bounds; the
refinement stops (ConvergenceError) when three doublings take less than 10 % off the estimate.
"""
from __future__ import annotations

import dataclasses
import logging
import math
import time
import warnings

import numpy as np

from ..errors import ConvergenceError, InputError, named
from ..numerics.blas_threads import single_blas_thread
from ..numerics.contact import refine_nested
from ..numerics.edges import fit_edges, peak, peak_odd_even
from ..numerics.fft import get_rfft
from ..numerics.grid import Grid, periodic_interp, pow2_at_least
from ..numerics.interface import solve_exponential_contact
from ..physics.film import Film
from ..physics.scene import Scene, check_positive
from ..result import ContactResult
from .base import check_grid_points
from .fft_driver import VISCO_EDGE_CELLS, VISCO_EDGE_SHARE, Level, Problem, refine, run
from .visco_slow import slow_sliding

__all__ = ["solve_fft", "MIN_POINTS", "MAX_POINTS"]

_log = logging.getLogger(__name__)  # progress (INFO): one line per refinement level

MIN_POINTS = 64
MAX_POINTS = 2**22
_FIRST_ACROSS = 32  # grid points across the contact on the first adaptive level, at least
_EDGE_ERROR = 0.01  # first level: _EDGE_ERROR / tol points across the contact (the averaged
#                     edge error has rms ~0.007 dx, max ~0.02 dx: studies/stability)
_LEVEL_MARGIN = 1.5  # the estimate's margin over the last two levels' difference (_discretisation_error)
_INTERFACE_TOL = 1e-3  # a compliant interface: the estimate verified from this tol down (README)
_SLOW_RATIO_CAP = 0.75  # slow monotone convergence: tail at most 3 x the last difference
_SHIFT_RESIDUAL = 0.25  # averaged phase error <= this fraction of the shift difference (measured)
# corrected edges (the lattice correction): the phase error is gone, what the grid and the
# shifted grid still differ by is not an odd harmonic the average cancels; two independent
# errors e0, e1 leave an average (e0 + e1)/2 as large as (e0 - e1)/2 in distribution: half
_SHIFT_RESIDUAL_CORRECTED = 0.5
# periodic images: relative error of a, x_c, d, p_max ~ amplitude * exp(-DECAY_RATE (L - 2a)).
# Measured amplitude (against tol 1e-5 solves, L - 2a = 6 ... 12 h): 0.5-0.6 at mu 0, 0.6-1.0 at
# mu 2, 1.5 at mu 10; bounded by _IMAGE_AMPLITUDE * max(1, |mu|/10)
_IMAGE_AMPLITUDE = 2.0
# the locator's inner solves (plain Amontons contact): its a and x_c are only good to ~dx anyway
# (fft_driver.LOCATOR_*: measured fewer GMRES iterations, no more active-set steps over P
# 0.09-1773, mu 0-10)
_RTOL_FLOOR, _RTOL_CAP = 1e-10, 1e-9  # the inner solves' relative tolerance: 1e-3 accept, within these


def _locator_guess(g, P, a_bound, mu):
    """The locator's first pressure: a half-space (square-root) profile carrying the load P over
    [-a_bound/2, a_bound/2 (1 + min(|mu|, 1))] (mirrored for mu < 0).  Measured over P 0.09-1773,
    mu 0-10 (a/a_bound 0.64-1.44, the centre shifted by up to 0.55 a toward the sliding
    direction): inside the contact, where the active set grows in one or two steps (a
    penetrated band is added at once), instead of shrinking a node or two per step from the
    wider Hertz guess.  Only the number of active-set steps depends on it, not the solution."""
    lo = -0.5 * a_bound
    hi = 0.5 * a_bound * (1.0 + min(abs(mu), 1.0))
    if mu < 0:
        lo, hi = -hi, -lo
    a, xc = 0.5 * (hi - lo), 0.5 * (hi + lo)
    r = g.x - xc
    p = (2.0 * P / (math.pi * a * a)) * np.sqrt(np.maximum(a * a - r * r, 0.0))
    return p if p.any() else np.where(np.abs(r) <= 0.5 * g.dx, P / g.dx, 0.0)


LATTICE_MAX_DX = 0.1
"""The edge fits are corrected by the collocation's edge error (``numerics.edges.
lattice_error``) on cells up to this size [h]: the fit's farthest node (5 cells out) within
h/2 of the edge, where the kernel at the cell scale is the half-space's.  Measured (studies/
README, viscoelastic, the edges' grid-to-grid noise): the universal error holds to dx/h 0.06
(a_H/h 30: rms 0.022 -> 0.003 cells), half of it at 0.06-0.09 (0.015 -> 0.008), neither
better nor worse at 0.09-0.13 (0.031 -> 0.022; a_H/h 10 at mu 10: 0.056 -> 0.054) nor beyond
(a_H/h 10 at mu 10, dx/h 0.13-0.3: 0.08-0.11 either way)."""


LATTICE_CORRECTION = False
"""Off for the elastic film: the edge fits as before.  On, the edges' grid-to-grid noise falls
5-50 times (a, x_c at a fixed grid), the grids are the same or half, and the error estimate
still bounds the true error (studies.error_estimate: 0 of 280 and 0 of 144 below), but it is
then 8-9 times the true error in the median at tol <= 1e-4 (issue 13 asks 3:
tests/test_error_estimate_sweep.py): the estimate's 1.5 x level difference was set for noisy
edges, the corrected quantities converge at order ~3 (true error / level difference
~0.15-0.2).  Left off until the estimate is redesigned for it (studies/README, viscoelastic:
the edges' grid-to-grid noise)."""

VISCO_LATTICE = True
"""A viscoelastic film's lines correct their edge fits (where ``_lattice_edges`` allows) with
the elastic film's estimate unchanged: the noise the correction removes is larger on them
(their contact is the glassy, smaller one in cells; the sliding contact's x_c takes both
edges' independent errors; the trailing edge's layer at |V| tau ~ a cell adds 1.5x:
studies/README, viscoelastic, the edges' grid-to-grid noise), and it is what made their
levels go one doubling past the elastic solve's.  Their estimate (the same rule but half the
shift difference, ``_discretisation_error``) then bounds the true error more loosely, which
issue 23 does not limit (its sweeps over V, all bounded: studies/README, viscoelastic, lines
with corrected edges); the elastic solve, ``--speed 0`` included, is as before."""


def _lattice_edges(prob, exponential=False) -> bool:
    """Whether the line's edges are corrected (LATTICE_CORRECTION; VISCO_LATTICE for a
    viscoelastic film) and are the square-root
    ones the lattice correction was measured on: a rigid interface (no compliance, not the
    exponential law) and no friction coupling at the edge (an incompressible film, or no shear
    in the contact; a compressible film with friction has another edge exponent: its fit's
    error is 0.05-0.15 cells, not the lattice function)."""
    if not (LATTICE_CORRECTION or (VISCO_LATTICE and prob.visco)) or exponential or prob.c:
        return False
    return prob.film.incompressible or (prob.mu_contact == 0.0 and not prob.with_law)


def _contact_window(sol, trailing=None, lattice=False):
    """(a, x_c, edges) of the solution: the envelope of its contact runs (``trailing``: the
    viscoelastic trailing edges' layer, ``fit_edges``; ``lattice``: the fits corrected by the
    collocation's edge error on cells up to LATTICE_MAX_DX)."""
    g = sol.grid
    edges = fit_edges(g.x, g.dx, sol.gap, sol.pressure, sol.active, trailing,
                      lattice and g.dx <= LATTICE_MAX_DX)
    if not edges:
        return 0.0, 0.0, edges
    left = min(e[0] for e in edges)
    right = max(e[1] for e in edges)
    return 0.5 * (right - left), 0.5 * (right + left), edges


EDGE_FRACTION = 0.01
"""Exponential interface: the contact window is where p >= EDGE_FRACTION p_max.  As the
interface stiffens (lambda -> 0) it tends to the rigid window: a square-root edge reaches
1 % of p_max within ~1e-4 of the half-width."""


def _soft_window(sol):
    """(a, x_c, edges) of a contact without sharp edges (exponential interface): the outermost
    crossings of p = EDGE_FRACTION p_max around the peak (linear between nodes)."""
    g = sol.grid
    p = sol.pressure
    n = p.size
    j = int(np.argmax(p))
    thr = EDGE_FRACTION * p[j]
    ends = []
    for side in (+1, -1):
        i = j
        while p[(i + side) % n] >= thr and abs(i + side - j) < n - 1:
            i += side
        p_in, p_out = p[i % n], p[(i + side) % n]
        t = (p_in - thr) / (p_in - p_out) if p_in > p_out else 0.5
        ends.append(g.x[j] + (i - j + side * t) * g.dx)
    right, left = ends
    return 0.5 * (right - left), 0.5 * (right + left), [(left, right)]


def _measure(sol, moment=False, trailing=None, lattice=False):
    """a, x_c, d, p_max (and where), the fitted edges; with ``moment`` (a viscoelastic film) also
    "m", the pressure's centroid (apex frame, in h): the deformation friction is (h/R) m;
    ``trailing``: its trailing edges' inner layer (``Problem.trailing``); ``lattice``: the
    edge fits corrected (``_contact_window``)."""
    a, c, edges = _soft_window(sol) if getattr(sol, "soft", False) else \
        _contact_window(sol, trailing, lattice)
    # (a viscoelastic film: the odd-even grid mode of its unresolved leading edge left out)
    pm, xm = (peak if trailing is None else peak_odd_even)(sol.grid.x, sol.pressure)
    q = {"a": a, "c": c, "d": float(sol.indentations[0]), "pmax": pm, "xmax": xm,
         "edges": edges}
    if moment:
        p = sol.pressure
        q["m"] = float(p @ sol.grid.x) / max(float(np.sum(p)), 1e-300)
    return q


def _steps(q, r):
    """Signed relative changes of a, centre (over a), indentation, peak pressure from r to q
    (the components of ``_difference``)."""
    a = max(abs(q["a"]), 1e-300)
    steps = [(q["a"] - r["a"]) / a, (q["c"] - r["c"]) / a,
             (q["d"] - r["d"]) / max(abs(q["d"]), 1e-300),
             (q["pmax"] - r["pmax"]) / max(q["pmax"], 1e-300)]
    if "m" in q and "m" in r:  # viscoelastic: the centroid (over a), i.e. mu_def
        steps.append((q["m"] - r["m"]) / a)
    return np.array(steps)


def _difference(q, r):
    """Relative difference of two measurements (a, centre, indentation, peak pressure)."""
    return float(np.max(np.abs(_steps(q, r))))


def _average(q0, q1):
    """Mean of the measurements on a grid and on the grid shifted by half a cell.  The edge
    error is a zero-mean periodic function of the edge's position within its cell (times dx):
    averaging two offsets half a cell apart cancels its odd harmonics (3-5x smaller)."""
    out = {k: 0.5 * (q0[k] + q1[k]) for k in ("a", "c", "d", "pmax", "xmax", "m") if k in q0}
    out["edges"] = q0["edges"]
    return out


_EDGE_REACH = 0.25  # (measured) a collocation solve's contact holds the nodes up to ~0.15-0.3
#                   cells beyond the fitted (continuous) edges, not those 0.4-0.5 cells beyond


def _first_set(g, edges, p, reach=_EDGE_REACH):
    """A first pressure on grid ``g`` whose support is the contact set a solve on ``g`` is
    expected to end with: the nodes within _EDGE_REACH cells beyond the envelope of ``edges``
    (fitted on a previous solution); ``p`` (interpolated; or a function of the nodes' x, then
    evaluated there only) inside, floored at 1e-12.  Only the
    number of active-set steps depends on it, not the solution."""
    sl = _set_slice(g, edges, reach)
    out = np.zeros(g.n)
    out[sl] = np.maximum(p[sl] if isinstance(p, np.ndarray) else p(g.x[sl]), 1e-12)
    return out


def _set_slice(g, edges, reach=_EDGE_REACH):
    """The nodes lo < x < hi of ``_first_set`` (one slice: the nodes increase)."""
    lo = min(e[0] for e in edges) - reach * g.dx
    hi = max(e[1] for e in edges) + reach * g.dx
    x = g.x
    return slice(int(x.searchsorted(lo, "right")), int(x.searchsorted(hi, "left")))


def _discretisation_error(step, last_step, shift_diff, soft_edges: bool = False,
                          corrected: bool = False):
    """The error estimate of the finest level's (averaged) measurements from the refinement
    history: ``step`` the signed changes from the previous level (``_steps``), ``last_step``
    the ones before (None on the second level), ``shift_diff`` the grid/shifted-grid difference.

    Levels converging at first order leave an error equal to their difference, at second
    order a third of it; measured against the Abel method over 471 pairs of levels
    (studies/error_estimate's sweep), error / difference has median 0.35 but spreads up to ~1.4
    in 95 % of the pairs, because convergence in N is not monotone (the edges move across
    nodes).  So: _LEVEL_MARGIN times the difference, and three guards: a quantity that keeps
    moving the same way by a ratio 1/2 < r = |step| / |last step| < 1 (converging, slower than
    first order: wide contacts on a thin film) leaves the geometric tail |step| r / (1 - r)
    (r capped at 0.75; r >= 1 is the non-monotone noise of the edges, left to the other terms);
    what is left of the phase error after averaging (_SHIFT_RESIDUAL of the shift difference,
    measured); an eighth of the previous difference (two levels that agree by chance).  The
    margin was set on that sweep (estimate above the true error in all its runs) and checked on
    a second one it was not set on (studies.error_estimate.HOLDOUT) and on the tests' sweep.

    ``soft_edges`` (a compliant interface, issue 24): the pressure vanishes smoothly at the
    edges, the sub-cell edge fit (built for the rigid gap's (x - e)^{3/2}) leaves a half-width
    converging at first order or slower, unevenly (C = 1e-9 m/Pa: steps 1.8e-4, 1.8e-4, 3.5e-5
    h over the last three doublings): two levels that agree by chance are common, so the
    previous difference counts whole (first order: the error is about one step), not an eighth
    (studies/interface_estimate.py: the estimate against tol 1e-5 solves).

    ``corrected`` (edges with the lattice correction, ``_lattice_edges``): the shift
    difference counts half (_SHIFT_RESIDUAL_CORRECTED), not a quarter: a viscoelastic two-term
    film (a_H/h 0.3, mu 0.5, 1 mm/s, tol 1e-4) ended 1.2x over its estimate with a quarter,
    x_c converging at first order and the grid and shifted grid 6.5e-5 apart (studies/README,
    viscoelastic, eighth session)."""
    shift = (_SHIFT_RESIDUAL_CORRECTED if corrected else _SHIFT_RESIDUAL) * shift_diff
    diff = float(np.max(np.abs(step)))
    if last_step is None:
        return max(_LEVEL_MARGIN * diff, shift)
    r = np.abs(step) / np.maximum(np.abs(last_step), 1e-300)
    slow = (step * last_step > 0.0) & (r > 0.5) & (r < 1.0)
    r = np.minimum(r, _SLOW_RATIO_CAP)
    tail = float(np.max(np.where(slow, np.abs(step) * r / (1.0 - r), 0.0)))
    previous = float(np.max(np.abs(last_step))) * (_SOFT_PREVIOUS if soft_edges else 1.0 / 8.0)
    return max(_LEVEL_MARGIN * diff, tail, shift, previous)


_SOFT_PREVIOUS = 1.0  # compliant interface: the previous level difference counts whole


_DOMAIN_ATTEMPTS = 3
_D_EL_MARGIN = 1e-2  # d_el for the friction images' bound: the relaxed film's contact on an
# eighth of the final level's points (measured: within 2.2e-4 of its converged d, the paper's
# scene, mu 2, at 256-2048 points; 3.5e-4 on a sixteenth), taken 1 % larger
_MU_IMAGES_MEASURED = 10.0  # |mu| up to which _IMAGE_AMPLITUDE was measured
# and the half-width [h]: amplitude <= 2 up to a = 16 h (mu 10, L - 2a ~ 14 h), but ~300 at
# a = 22 h, mu = 10 (the centre 1 % off at tol 1e-2): wider contacts measure their images
_A_IMAGES_MEASURED = 8.0


def _level_sizes(L, a, tol, grid_points, domain_length, edge_scales=(), layer_scales=()):
    """The grid sizes of the refinement levels on the period L (in h).  A viscoelastic film's
    edge structure |V| tau_i of a term the trailing-edge fits carry (``numerics.edges.
    viscous_gap``) needs no cells of its own; before, every term's width was spanned by
    VISCO_EDGE_CELLS cells on the third level, grids 4-16 times the elastic one's at V tau/h
    5e-4 - 1.6e-2 (studies/README, viscoelastic, **edge layer**).  ``edge_scales`` ((|V|
    tau_i, E_i/E_inf) per term): the terms the fits do not carry
    (``_LineSolve.unfitted_edge_scales``: the heavier ones, or every one in ``solve_fft``'s
    fallback); such a term that moves the contact by more than VISCO_EDGE_SHARE tol (weight x
    width / a) has its width spanned by VISCO_EDGE_CELLS cells on the third level (the first
    that may stop; half that on the second, a quarter on the first).  ``layer_scales``: the
    fitted terms whose trailing edge keeps an offset while |V| tau_i spans fewer than
    ``_LineSolve.LAYER_CELLS`` cells (``_LineSolve.layer_bias``); one whose bound on coarse
    cells (LAYER_SUBCELL weight x width / 2a) is above VISCO_EDGE_SHARE tol has the third level's
    cell at most its retardation length (1 + weight) width over ``_LineSolve.layer_cells`` (at
    most l_i itself: from there the bound falls at least as dx; the levels do not stagnate on
    its constant part below a tenth of a cell)."""
    if grid_points:
        return [grid_points // 2, grid_points]
    across = max(_FIRST_ACROSS, _EDGE_ERROR / tol)
    n1 = pow2_at_least(L / (2 * a / across), MIN_POINTS)
    why = None  # the viscoelastic structure that sets the grid, if one does (messages)
    for width, weight in edge_scales:
        if weight * width / a > VISCO_EDGE_SHARE * tol:
            n_edge = pow2_at_least(VISCO_EDGE_CELLS * L / (2 * width), MIN_POINTS)
            if n_edge > n1:
                n1, why = n_edge, (f"the viscoelastic edge structure |V| tau = {width:.2g} h (a "
                                   f"Prony term heavier than E_i/E_inf = "
                                   f"{_LineSolve.LAYER_FITTED_WEIGHT:g})")
    for width, weight in layer_scales:
        cells = _LineSolve.layer_cells(VISCO_EDGE_SHARE * tol * 2 * a / (weight * width))
        if cells > 0.0:
            n_layer = pow2_at_least(cells * L / (2 * (1.0 + weight) * width), MIN_POINTS)
            if n_layer > n1:
                n1, why = n_layer, (f"the trailing-edge offset of a Prony term E_i/E_inf = "
                                    f"{weight:.3g} (cells down to "
                                    f"{(1.0 + weight) * width / cells:.2g} h; its retardation "
                                    f"length {(1.0 + weight) * width:.2g} h)")
    # the third level (2 n1), the first whose estimate may stop the refinement, must fit: say
    # so before allocating anything (a grid of 2^21 used to run two levels for ~15 s and stop
    # with exit 3, its estimate below tol but one level short)
    needed = 2 * n1
    if needed > MAX_POINTS and why is not None:
        raise InputError(
            f"{why} needs ~{needed:.1e} grid points on the period {L:.3g} h at tol {tol:g} (> "
            f"{MAX_POINTS} = 2^22): raise tol, or change the speed or the Prony series")
    if needed > MAX_POINTS and domain_length is not None:
        raise InputError(
            f"domain_length {domain_length:.4g} h needs ~{needed:.1e} grid points to resolve "
            f"this contact (half-width {a:.2g} h) at tol {tol:g} (> 2^22): shorten "
            f"domain_length, or leave it automatic")
    if needed > MAX_POINTS:
        raise InputError(
            f"tol {tol:g} needs ~{needed:.1e} grid points for a contact of half-width {a:.2g} h "
            f"(> {MAX_POINTS} = 2^22): raise tol, or use method abel or model hertz")
    n1 = max(n1, 2 * MIN_POINTS)  # two distinct levels to compare from the start
    sizes = [n1 // 2, n1]
    while sizes[-1] < MAX_POINTS:
        sizes.append(sizes[-1] * 2)
    return sizes


_BYTES_PER_POINT = 400  # peak Python-side memory of a fixed-N solve (tracemalloc, N = 2^14..2^18)


def _check_fixed(grid_points, domain_length):
    """A user-fixed N (even, MIN_POINTS ... MAX_POINTS) and period [h] (> 0) of a line, each
    one number (None passes through); InputError naming the option otherwise (before
    allocating anything: a too-large N says the memory it would need)."""
    if np.ndim(grid_points) or np.ndim(domain_length):
        raise InputError("grid_points and domain_length are single numbers for a line "
                         "indenter (pairs [nx, ny], [Lx, Ly] are for 3D indenters)")
    shown = f"[{MIN_POINTS}, {MAX_POINTS}] (2^22)"
    big = check_grid_points(grid_points, MIN_POINTS, 2**62, "fft grid points", even=True,
                            shown=shown) \
        if isinstance(grid_points, (int, float)) and grid_points > MAX_POINTS else None
    if big is not None:
        raise InputError(
            f"{named('grid_points')} (fft grid points) must be in {shown}; {big} would need "
            f"~{big * _BYTES_PER_POINT / 1e9:.1f} GB")
    grid_points = check_grid_points(grid_points, MIN_POINTS, MAX_POINTS, "fft grid points",
                                    even=True, shown=shown)
    if domain_length is not None:
        domain_length = check_positive("domain_length", domain_length, "h")
    return grid_points, domain_length


# (the GMRES bases' products, the centroid's dot: numerics.blas_threads; numpy's build, no
# import of scipy.linalg for its own: the line solve uses none of it)
@single_blas_thread(load_scipy=False)
def solve_fft(scene: Scene, model: str = "exact", tol: float = 1e-4, grid_points: int | None = None,
              domain_length: float | None = None, progress=None) -> ContactResult:
    """Solve ``scene`` with the spectral method.

    model : "exact" (Amontons friction coupled into the contact) or "goodman" (frictionless
            pressure and window; friction only loads the base).
    tol : relative accuracy target for a, x_c, d and p_max (0 < tol < 0.1).
    grid_points : fix N (power of two advised; >= 64); domain_length : fix L [in h].
    progress : optional callable(str), told about each level (default: this module's INFO
        log, as the surfaces' ``solve_fft3d``).
    """
    grid_points, domain_length = _check_fixed(grid_points, domain_length)
    prob = Problem(scene, model, tol, adaptive=not grid_points,
                   progress=_log if progress is None else progress)
    if prob.visco and grid_points is None and domain_length is None:
        # slow sliding: the relaxed elastic solve + the first-order correction (visco_slow)
        slow = slow_sliding(scene, prob.film, model, tol, solve_fft)
        if slow is not None:
            return slow
    # the inner (GMRES) solves: 1e-10 costs ~10 % more iterations than 1e-9 for nothing at
    # these tolerances (the results keep their residual below 1e-8); the locator's a and x_c
    # only size the period and the grid: its inner solves are looser
    # this and the first active sets from fitted edges (_first_set) only speed the adaptive
    # path: a user-fixed grid keeps 1e-10 and its earlier first sets (its results stay those
    # of earlier versions to round-off: golden values; either moves them by ~1e-11)
    # 1e-3 accept: tol 1e-5 keeps 1e-10 (at 2^21 points, 1e-9 moved a by 4e-6 = 0.4 tol)
    prob.rtol = (min(max(_RTOL_FLOOR, 1e-3 * prob.accept), _RTOL_CAP) if prob.adaptive
                 else _RTOL_FLOOR)
    if prob.c and tol > _INTERFACE_TOL:
        warnings.warn(
            f"compliant interface: the half-width converges slowly and unevenly from coarse "
            f"grids and the error estimate may be below the true error at tol {tol:g} (measured "
            f"0.6 times at tol 1e-2); use tol <= {_INTERFACE_TOL:g}", UserWarning, stacklevel=3)
    steps = _LineSolve(prob, grid_points, domain_length)
    try:
        return run(steps)
    except ConvergenceError as exc:
        if not (prob.visco and prob.adaptive
                and len(steps.unfitted_edge_scales()) < len(prob.film.edge_scales())):
            raise  # (no term was left to the layer fit: the retry would be the same solve)
        first = exc
    # a viscoelastic line whose levels stagnate with a term's edge structure |V| tau left to
    # the layer fit: solved again with every term resolved (VISCO_EDGE_CELLS cells across it
    # on the third level, its bound in the estimate: the rule lines used before the
    # trailing-edge layer fit), the first attempt's work counted.  A safety net: not seen
    # within LAYER_FITTED_WEIGHT (10 since the seventh session); seen on films 4-11 times
    # stiffer when glassy at V tau/h ~ 5e-4 - 1.6e-3, tol 1e-4, with the fits before that
    # session (the trailing fit's plain iteration leaving its range, the peak taking the
    # unresolved leading edge's odd-even mode: tests/test_viscoelastic.py)
    _log.info("viscoelastic line: the levels stagnate with the edge structure unresolved; "
              "solving again with it resolved")
    retry = Problem(scene, model, tol, adaptive=True, progress=prob.progress)
    retry.rtol = prob.rtol
    retry.counters = dict(prob.counters)
    try:
        return run(_LineSolve(retry, grid_points, domain_length, resolve_edges=True))
    except (ConvergenceError, InputError):  # (InputError: the resolved grid passes 2^22)
        raise first from None  # (its message names the stagnation and what to change)


class _LineSolve:
    """The line's steps of the one driver (``fft_driver``; module docstring, steps 1-4)."""

    MIN_LEVELS = 3  # the estimate uses the previous difference: from the third level on
    RETRY_FINER = True
    # the viscoelastic trailing edges are fitted with their inner layer (``_measure``): the
    # edge structure of a Prony term up to this weight E_i/E_inf needs no cells of its own
    # (``unfitted_edge_scales``; terms heavier than LAYER_BIAS_WEIGHT with the residual of
    # ``layer_bias``).  A stated range, the one verified: up to 1 in the sixth session
    # (studies/README, viscoelastic, edge layer: SLS E_1 = E_inf and two terms E_inf each, 126
    # automatic solves bounded); up to 10 in the seventh (**heavy Prony terms on lines**:
    # E_1 = 3, 10 E_inf and three terms 3 E_inf each), once the trailing fit's fixed point was
    # bracketed (``numerics.edges._trailing_root``: the plain iteration left its range on
    # films 4-11 times stiffer when glassy) and p_max fitted with the odd-even grid mode
    # (``edges.peak_odd_even``: the unresolved leading-edge layer's mode made p_max converge
    # as N^-2 from ~1e-3, what stopped the widened fit before: p_max 1.5e-3 off under an
    # estimate of 6.8e-4, E_1 = 3 E_inf, a_H/h 0.3, mu 0.5, 0.32 mm/s, tol 1e-3).  Not beyond
    # 10: 30 and 100 tried in the ninth session (**rubber-like films on lines**): the leading
    # edge's glassy spike (above the outer peak from |V| tau_i / a ~ 2 / w^2 on; a local
    # maximum of height ~ the outer peak x sqrt(2 |V| tau_i / a) (w/2 + O(1))) is then narrower
    # than the fitted grids' cells, which do not see it: p_max 2-38 % off under estimates of
    # 5e-4 - 8e-3 at tol 1e-2 and 1e-3 (w = 10: the spike comes up at |V| tau_i >= 0.02 a,
    # where the grids resolve it); and the trailing offset passes LAYER_OFFSET min(1, dx/l_i)
    # (up to 3.4 times at w = 30; 0.2-0.55 cells at w = 100)
    LAYER_FITTED_WEIGHT = 10.0
    LAYER_BIAS_WEIGHT = 1.0
    # measured (seventh session: fixed grids against 2^19-2^20 points on the same period,
    # E_1 = 1, 3, 10 E_inf on a_H/h 0.3 (mu 0, 0.5) and the paper's scene, 2.5e-5 - 2e-4 m/s;
    # studies/README, **heavy Prony terms on lines**): while |V| tau_i spans less than a cell
    # (LAYER_CELLS) the fitted trailing edge sits inward of the true one by f delta_i (delta_i
    # = E_i/E_inf |V| tau_i, the term's first-order shift of that edge), f a function of
    # l_i/dx (l_i = (1 + E_i/E_inf) |V| tau_i, the retardation length): 0.09 (w = 1, l/dx 0.1),
    # 0.06-0.07 (w = 3, 10 at 0.14-0.2), 0.03-0.04 (0.3-0.6), 0.015-0.033 (1.2), 0.009 (2.3),
    # 0.005 (4.7); the leading edge within 0.005 delta (the tenth session: +0.05 ... +0.06
    # delta far below a cell, at every phase).  One sign over the levels: the levels'
    # differences miss it.  Bounded by LAYER_OFFSET min(1, dx/l_i) (``layer_bias``) until the
    # tenth session, which measured below a cell and beyond (``layer_offset``)
    LAYER_OFFSET = 0.1  # the bound at l_i = dx (``layer_offset``)
    LAYER_CELLS = 1.0
    # tenth session (studies/README, **the trailing offset below a cell**): the sum of both
    # edges' offsets over delta_i, as a change from the same grid at l/dx = 1e-5 (the fits'
    # own sub-cell noise cancelled) against 2^19-2^21 points on the period (or the slow-sliding
    # theory where those do not resolve l), E_1 = 3, 10 E_inf on a_H/h 0.1, 0.3, 1, 3 (mu 0,
    # 0.5) and the paper's scene, l/dx 1e-4 ... 11, the edge's phase in its cell swept by the
    # period (16 phases, 64 below a cell) on five scenes.  As l/dx -> 0 the offset does not
    # vanish: it tends to delta_i times a function of the edge's phase (the grid sees R(k) =
    # 1 + i k delta_i, the collocation's compliance translated by a fraction of a cell, and
    # the fits' error moves with that translation): trailing -0.10 ... +0.19, leading +0.05
    # ... +0.06 (0.09 at one phase), their sum up to 0.25 (l/dx 0.01 and 0.001 alike; 0.18
    # at 0.1, 0.17 at 0.2, 0.11 at 0.5, 0.084 at 1), past the old 0.1 below l/dx 0.2.  Beyond
    # a cell it falls faster than dx/l: 0.060 (l/dx 1.4), 0.039 (2), 0.023 (2.8), 0.013 (4),
    # 0.0062 (5.6), 0.0030 (8), 0.0016 (11).  LAYER_SUBCELL below LAYER_OFFSET (l/dx)^-1/2,
    # then LAYER_OFFSET dx/l up to LAYER_FALL_FROM cells, then (LAYER_OFFSET /
    # LAYER_FALL_FROM) (LAYER_FALL_FROM dx/l)^LAYER_FALL: 1.16-1.5 times the largest measured
    # sum at every l/dx from 1 on, 1.2 below a tenth of a cell
    LAYER_SUBCELL = 0.3
    LAYER_FALL_FROM = 2.0
    LAYER_FALL = 1.75

    @classmethod
    def layer_offset(cls, cells: float) -> float:
        """Bound of the sum of a fitted term's two edges' offsets over its delta_i, at
        ``cells`` = l_i/dx (tenth session's measurement, class comment)."""
        if cells <= 1.0:
            return min(cls.LAYER_SUBCELL, cls.LAYER_OFFSET / math.sqrt(max(cells, 1e-300)))
        if cells <= cls.LAYER_FALL_FROM:
            return cls.LAYER_OFFSET / cells
        return (cls.LAYER_OFFSET / cls.LAYER_FALL_FROM
                * (cls.LAYER_FALL_FROM / cells) ** cls.LAYER_FALL)

    @classmethod
    def layer_cells(cls, allowed: float) -> float:
        """The l_i/dx from which ``layer_offset`` is at most ``allowed``, up to 1 (the third
        level's cell; from there the levels' own refinement lowers it): 0 when it never passes
        ``allowed``."""
        if allowed >= cls.LAYER_SUBCELL:
            return 0.0
        return min(1.0, (cls.LAYER_OFFSET / allowed) ** 2)

    def unfitted_edge_scales(self) -> list:
        """The viscoelastic film's edge structures (|V| tau_i, E_i/E_inf) that the grid resolves
        (``_level_sizes``) and the estimate bounds where it does not (``fft_driver.estimate``):
        the terms heavier than LAYER_FITTED_WEIGHT with those of nearby tau
        (``ViscoelasticFilm.merged_weights``), or every term in ``solve_fft``'s fallback; none
        on an elastic film."""
        if not self.prob.visco:
            return []
        film = self.prob.film
        scales = film.edge_scales()
        # (heavier: by the weight of the terms of nearby tau together, ``merged_weights``)
        return scales if self.resolve_edges else [
            s for s, merged in zip(scales, film.merged_weights())
            if merged > self.LAYER_FITTED_WEIGHT]

    def layer_scales(self) -> list:
        """(|V| tau_i, E_i/E_inf) of the fitted terms heavier than LAYER_BIAS_WEIGHT: their
        fitted edges keep offsets up to ``layer_offset``(l_i/dx) delta_i (both edges' sum)
        while |V| tau_i spans fewer than LAYER_CELLS cells (``layer_bias``; the cells refined
        by ``_level_sizes`` where that would take more than VISCO_EDGE_SHARE tol)."""
        if not self.prob.visco or self.resolve_edges:
            return []
        film = self.prob.film
        return [(w, wt) for (w, wt), merged in zip(film.edge_scales(), film.merged_weights())
                if self.LAYER_BIAS_WEIGHT < wt and merged <= self.LAYER_FITTED_WEIGHT]

    def layer_bias(self, a: float, dx: float) -> float:
        """Bound of the fitted edges' offsets (both edges' sum) on a grid of spacing ``dx`` relative to
        the half-width ``a`` (a and x_c move by half an edge's offset each): the sum of
        ``layer_offset``(l_i/dx) delta_i / (2 a) over ``layer_scales`` with |V| tau_i <
        LAYER_CELLS dx (delta_i = E_i/E_inf |V| tau_i, l_i = (1 + E_i/E_inf) |V| tau_i)."""
        return sum(self.layer_offset((1.0 + weight) * width / dx) * weight * width / (2.0 * a)
                   for width, weight in self.layer_scales() if width < self.LAYER_CELLS * dx)

    @property
    def ALTERNATIVE(self) -> str:  # noqa: N802 (the driver's class-level name, fft_driver)
        """What to try when the levels stagnate: method abel where it takes the scene
        (incompressible, Amontons, rigid interface, elastic film: ``AbelMethod.solve``)."""
        s = self.scene
        if (s.poisson == 0.5 and s.friction.is_amontons and s.interface_compliance == 0.0
                and s.interface_law == "linear" and not self.prob.visco):
            return "try method abel"
        return "raise tol"

    def __init__(self, prob: Problem, grid_points, domain_length, resolve_edges=False):
        self.prob, self.scene = prob, prob.scene
        self.resolve_edges = resolve_edges  # ``solve_fft``'s fallback: every term resolved
        self.grid_points, self.domain_length = grid_points, domain_length
        # the exponential law p = p0 exp(-g/lambda): no contact set (numerics.interface)
        self.exponential = self.scene.interface_law == "exponential"
        # the edge fits corrected by the collocation's edge error (``_lattice_edges``)
        self.lattice = _lattice_edges(prob, self.exponential)
        self.friction_images = None  # the friction images' bound, where taken (info)
        self.indenter = None  # the cylinder, or a height function (made when loaded)
        self.image_amplitude = _IMAGE_AMPLITUDE * max(1.0, abs(prob.mu_contact) / 10.0)
        # the images' effect against the elastic film's (a viscoelastic film: None where it
        # is not bounded, or where the bound on the period's margin would pass tol/4, the
        # measured images' acceptance, or with friction in the contact: then measured in
        # ``refine``, or bounded with d_el/d, ``_friction_images``).  Friction: the
        # indentation d, relative to itself in the estimate, can
        # fall far below the elastic film's on a viscoelastic one (E_1 = 10 E_inf, 0.32 m/s,
        # mu 2: d = 0.11 against 1.67; 0.1 m/s: d < 0), where the images' offset of d was 5.6
        # exp(-kappa free) of d against the elastic film's 1.0: 1.6 times the bound
        # (studies/README, viscoelastic, images); frictionless, d stays within the 1/r.
        self._set_margin(None)

    def _set_margin(self, size) -> None:
        """The period's margin and the images' factors (a viscoelastic film: its margin from
        its far field against the stiffness of a contact of half-width ``size``, None: the
        relaxed film's, for the locator; ``ViscoelasticFilm.line_margin``)."""
        prob = self.prob
        self.image_factor = prob.film.image_factor() if prob.mu_contact == 0.0 or \
            not prob.visco else None
        # with friction: the same factor, times max(1, d_el/d) once the solve's d is known
        # (``_friction_images``); else measured
        self.friction_factor = prob.film.image_factor() if prob.visco and \
            prob.mu_contact != 0.0 else None
        if prob.visco:  # the long relaxation tails' images are summed exactly (tail_terms);
            # the far field of the rest relative to the contact's stiffness as small as the
            # elastic film's at its margin
            prob.margin = prob.film.line_margin(prob.tol, prob.mu_contact, size)
            decay = math.exp(-prob.film.decay_rate * prob.margin)
            if self.image_factor is not None and self.image_amplitude * self.image_factor * \
                    decay > 0.25 * prob.tol:
                self.image_factor = None
            if self.friction_factor is not None and self.image_amplitude * \
                    self.friction_factor * decay > 0.25 * prob.tol:
                self.friction_factor = None

    def unloaded(self) -> ContactResult:
        """P = 0: no contact, zero fields."""
        prob = self.prob
        L = self.domain_length or prob.margin
        g = Grid.centered(self.grid_points or MIN_POINTS, L)
        z = np.zeros(g.n)
        return ContactResult(prob.scene, prob.model, "fft", g.x, z, z.copy(), z.copy(), 0.0, 0.0,
                             0.0, 0.0, 0.0, g.n, L, 0, 0.0, 0.0, time.perf_counter() - prob.t0,
                             0.0, {"fft_pairs": 0})

    def shortcut(self):
        """None: a line has no other path (surfaces: the open box)."""
        return None

    def period(self, located):
        """A user-fixed period checked against the located contact; the automatic one is set
        by ``refine`` (it may be lengthened: the images' effect, measured)."""
        self.check_period(located[1])
        return located

    def contact(self, grid, p_init=None, locator=False, d_init=None):
        prob, scene = self.prob, self.scene
        if self.exponential:
            s_ = solve_exponential_contact(grid, prob.mu_contact, self.indenter[0],
                                           scene.interface_p0, scene.interface_lambda,
                                           film=prob.film, p_init=p_init, rtol=prob.accept)
            s_.soft = True
            return s_
        return prob.solve_contact(grid, self.indenter, prob.film, p_init, locator, d_init)

    def _a_bound(self) -> float:
        """An upper bound of the frictionless half-width.  Both the Hertz half-space width
        (P = 2 pi a^2) and the thin-layer width (w = -p''/3: P = 4 a^5 / 15) bound it
        (studies/stability); the smaller one sizes the first grid."""
        P, film = self.prob.P, self.prob.film
        a_bound = min(math.sqrt(P / (2 * math.pi)), (3.75 * P) ** 0.2)
        if not film.incompressible:
            # compressible: Hertz with E* = 2G/(1 - nu) (P = pi a^2/(1 - nu)); a thin
            # compressible layer is a Winkler foundation of compliance H(0) (P = 4 a^3 /
            # (3 H(0))), wider than the incompressible thin layer: the larger of the two
            a_bound = min(math.sqrt(P * (1.0 - self.scene.poisson) / math.pi),
                          max((3.75 * P) ** 0.2, (0.75 * film.uniform_compliance * P) ** (1.0 / 3.0)))
        if self.scene.height is not None:  # a user's line indenter: the bound it was given
            a_bound = self.indenter[0].extent_bound()
        return a_bound

    def locate(self):
        """1. the contact on a coarse, generous grid.  Strong friction widens the contact
        beyond the bounds (a = 29 h against a bound of 10 h at P = 2.7e4, mu = 30): a locator
        whose contact fills its period is redone on a period twice as long, with the same
        spacing.  The locator never uses a user-fixed period."""
        prob, gp = self.prob, self.grid_points
        self.indenter = [self.scene.indenter_object()]
        a_bound = self._a_bound()
        L0 = 4.0 * a_bound + prob.margin
        n0 = gp // 4 if gp else pow2_at_least(L0 / (2 * a_bound / _FIRST_ACROSS), MIN_POINTS)
        n0 = max(MIN_POINTS, n0)
        while True:
            if n0 > MAX_POINTS:  # say so before allocating anything
                raise InputError(
                    f"the contact of this scene ({self.scene.extreme_parameter()}: half-width "
                    f"~{a_bound:.2g} h) is too small for the FFT method's "
                    f"periodic grid over {L0:.3g} h (~{n0:.1e} points > 2^22): use model hertz "
                    f"or method abel")
            g0 = Grid.centered(n0, L0)
            guess = _locator_guess(g0, prob.P, a_bound, prob.mu_contact) \
                if prob.adaptive and not self.exponential else None
            try:
                sol = prob.count(self.contact(g0, locator=True, p_init=guess))
            except ConvergenceError:
                if not prob.visco:
                    raise
                # a film much stiffer when glassy whose coarse locator grid does not settle
                # (E_1 = 100 E_inf at 3.2 mm/s: the set wanders over 200 steps): the relaxed
                # elastic film's contact, which holds the viscoelastic one (its trailing edge
                # moves in, the leading one stays), sizes the period and the first cells
                sol = prob.count(prob.solve_contact(g0, self.indenter, Film(
                    poisson=self.scene.poisson), guess, True))
            if not sol.active.all():
                return sol, _measure(sol, prob.visco, prob.trailing)  # (sizes only)
            L0, n0 = 2.0 * L0, 2 * n0

    def check_period(self, q) -> None:
        """A user-fixed period must hold the contact plus the decay length of its images."""
        dl, tol = self.domain_length, self.prob.tol
        if dl is None:
            return
        need = 2.0 * q["a"] + math.log(2.0 * self.image_amplitude * (self.image_factor or 1.0)
                                       / tol) / self.prob.film.decay_rate
        if dl < need:
            L_unit = self.scene.length_unit
            raise InputError(
                f"domain_length {dl * L_unit:.4g} m ({dl:.4g} h) is too short for this contact "
                f"at tol {tol:g}: the period must hold the contact (2a = {2 * q['a']:.3g} h) plus "
                f"{need - 2 * q['a']:.3g} h for its periodic images to decay below tol/2: use at "
                f"least {need:.4g} h (= {need * L_unit:.4g} m), raise tol, or leave "
                f"domain_length automatic")

    def refine(self, located):
        """2.-4. the period (contact plus the decay margin, centred on the contact) and the
        grid levels on it (``fft_driver.refine``); beyond the friction where the images'
        amplitude was measured (|mu| <= _MU_IMAGES_MEASURED), their effect is measured
        instead: strong friction amplifies it far beyond the kernels' exp(-0.739 s) (mu = 30,
        a = 29 h, tol 1e-3: a 1.5 % off with 16.8 h of free period), and an automatic period
        is lengthened until it is below tol/4.  Returns the ``Levels``."""
        sol, q = located
        prob, tol = self.prob, self.prob.tol
        guard = 4 * sol.grid.dx
        if prob.visco and self.domain_length is None:  # the margin for this contact's size
            self._set_margin(q["a"])
        L = self.domain_length or (2 * q["a"] + prob.margin + guard)
        center = q["c"] if self.domain_length is None else 0.0
        # (a viscoelastic film: its images are measured too unless its far field is bounded
        # by the elastic one's, ``image_factor``: every tail short or summed)
        check_images = (abs(prob.mu_contact) > _MU_IMAGES_MEASURED or q["a"] > _A_IMAGES_MEASURED
                        or self.image_factor is None)
        domain_diff = 0.0
        for _attempt in range(_DOMAIN_ATTEMPTS):
            sizes = _level_sizes(L, q["a"], tol, self.grid_points, self.domain_length,
                                 self.unfitted_edge_scales(), self.layer_scales())
            self._L, self._center = L, center
            lv = refine(self, sizes, L, center, located)
            if not check_images or self._friction_images(lv, q, L):
                return lv
            # 4. the images' effect, measured: the final level's nodes on the period 2L
            fine = lv.cur
            g2 = Grid.centered(2 * fine.grid.n, 2 * L, center)
            # (from the final level's pressure and indentation: GMRES starts from the
            # images' change, not from the whole gap: 12 against 16 FFT pairs on 2N points at
            # a_H/h 1, 0.1 m/s, tol 1e-4; tests/test_line_pairs.py)
            # (g2's node n + k is the final grid's node n/2 + k, both centred on ``center``
            # with the same cells: the pressure placed by index; interpolated, the round-off
            # of the nodes' positions left values above 0 beside an edge, an active-set step
            # more: 30 against 12 pairs at a_H/h 1, 0.1 m/s, as the fitted centre's last bits
            # moved)
            n = fine.grid.n
            p_far = np.zeros(2 * n)
            p_far[n // 2: n // 2 + n] = fine.sol.pressure
            far = prob.count(self.contact(g2, p_init=p_far, d_init=fine.sol.indentations))
            domain_diff = _difference(_measure(far, prob.visco, prob.trailing, self.lattice), fine.q0)
            lv.image_error = max(lv.image_error, domain_diff)
            lv.est = lv.disc + lv.image_error
            lv.domain_diff = domain_diff
            if self.domain_length is not None or domain_diff <= 0.25 * tol:
                return lv
            L = 2 * q["a"] + 2 * (L - 2 * q["a"])  # twice the free length
        raise ConvergenceError(
            f"the periodic images still change the solution by {domain_diff:.1e} > tol/4 with a "
            f"period of {L / 2:.4g} h (contact {2 * q['a']:.3g} h): the scene is beyond the FFT "
            f"method's range at tol {tol:g}", residuals=[domain_diff], iterations=_DOMAIN_ATTEMPTS)

    def _friction_images(self, lv, q, L) -> bool:
        """A viscoelastic film with friction in the contact, its tails short or summed (the
        frictionless bound's range, ``image_factor``), an automatic period: bound the images
        instead of measuring them (step 4), when the bound keeps the estimate within tol and
        the images within tol/4.  The images shift the sinking over the contact by an absolute
        amount, bounded as on a frictionless film by the elastic film's times the factor; the
        elastic model is relative to the elastic film's d (d_el), the estimate to the solve's
        own d, which friction can take far below d_el (E_1 = 10 E_inf, mu 2, 0.32 m/s: d =
        0.11 against 1.67; the images' change of d 5.6 exp(-kappa free) of d there, 1.6 times
        the factor's bound): so the bound is the frictionless one times max(1, d_el/d), d_el
        the relaxed film's contact solved on an eighth of the final level's points (one contact
        solve, counted), taken _D_EL_MARGIN larger.
        Returns True when the bound was taken (``lv``'s image term set)."""
        prob = self.prob
        if (self.friction_factor is None or self.domain_length is not None or self.grid_points
                or abs(prob.mu_contact) > _MU_IMAGES_MEASURED or q["a"] > _A_IMAGES_MEASURED):
            return False
        d = lv.cur.q["d"]
        if not d > 0.0:
            return False
        fine = lv.cur.grid
        g = Grid.centered(max(fine.n // 8, MIN_POINTS), L, self._center)
        relaxed = dataclasses.replace(self.scene, speed=0.0, prony=()).core_film()
        try:
            # (from the solve's pressure, narrower than the relaxed film's: a band is added at
            # once, then end nodes shed, extrapolated: 2048 -> 1558 FFT pairs over 32 solves
            # of four friction scenes at 1e-3 - 10 m/s, d_el the same to 8 digits)
            el = prob.count(prob.solve_contact(
                g, self.indenter, relaxed,
                periodic_interp(g.x, fine.x, lv.cur.sol.pressure, L), False, extrapolate=True))
        except ConvergenceError:
            return False  # (measured instead)
        ratio = max(1.0, float(el.indentations[0]) * (1.0 + _D_EL_MARGIN) / d)
        bound = self.image_error(lv.cur.q, L) * self.friction_factor * ratio
        if not (bound <= 0.25 * prob.tol and lv.disc + bound <= prob.tol):
            return False
        lv.image_error = bound
        lv.est = lv.disc + bound
        self.friction_images = {"d_ratio": ratio, "factor": self.friction_factor}
        return True

    def grid(self, n, L, center):
        return Grid.centered(n, L, center)

    def start(self, g, located, prev):
        """The nested start of a level: the locator's pressure (first level) or the previous
        level's, refined, with the first active set from the fitted edges."""
        adaptive = self.prob.adaptive
        if prev is None:
            sol, q = located

            def located_p(x, s0=sol):  # (np.interp is elementwise: only where it is kept)
                return periodic_interp(x, s0.grid.x, s0.pressure, s0.grid.length)
            return (_first_set(g, q["edges"], located_p) if adaptive and not self.exponential
                    and q["edges"] else located_p(g.x))
        refined = refine_nested(prev.sol.pressure)
        # exponential interface: no contact set, the whole refined pressure
        return refined if self.exponential else _first_set(
            g, prev.q["edges"], refined, _EDGE_REACH if adaptive else 0.0)

    def solve_level(self, g, p_init, first=False):
        """A level: the grid and the grid shifted by half a cell (4.), their measures averaged
        (``Level``: also q0, the grid's own, and shift_diff, the two grids' difference)."""
        visco = self.prob.visco
        cur = self.contact(g, p_init=p_init)
        gs = Grid.centered(g.n, self._L, self._center + 0.5 * g.dx)
        ps = cur.pressure.copy()  # 0.5 (p + np.roll(p, -1)), without np.roll's overhead
        ps[:-1] += cur.pressure[1:]
        ps[-1] += cur.pressure[0]
        ps *= 0.5
        q0 = _measure(cur, visco, self.prob.trailing, self.lattice)
        if self.prob.adaptive and not self.exponential and q0["edges"]:
            # the first active set from cur's fitted edges (the midpoint beyond an edge has
            # p > 0 but is mostly out of contact: one active-set step less)
            ps = _first_set(gs, q0["edges"], ps)
        shifted = self.contact(gs, p_init=ps)
        q1 = _measure(shifted, visco, self.prob.trailing, self.lattice)
        self.prob.count(cur)
        self.prob.count(shifted)
        return Level(g, cur, _average(q0, q1), max(cur.residual, shifted.residual), q0=q0,
                     shift_diff=_difference(q0, q1))

    def difference(self, lv, cur, prev):
        """The discretisation error of level ``cur``: convergence in N is not monotone (edges
        move across nodes): also the previous difference, halved as first order predicts, and
        what is left of the phase error after averaging (a quarter of the shift difference,
        measured): ``_discretisation_error``.  Records the estimate's parts."""
        step = _steps(cur.q, prev.q)
        diff = float(np.max(np.abs(step)))
        last_step = lv.last_step
        disc = _discretisation_error(step, last_step, cur.shift_diff,
                                     soft_edges=bool(self.prob.c), corrected=self.lattice)
        lv.parts = {"level_difference": diff, "shift_difference": cur.shift_diff,
                    "previous_difference": (float(np.max(np.abs(last_step)))
                                            if last_step is not None else 0.0)}
        bias = self.layer_bias(cur.q["a"], cur.grid.dx) if self.prob.visco else 0.0
        if bias:  # (heavy fitted terms, |V| tau below LAYER_CELLS cells)
            lv.parts["layer_bias"] = bias
        lv.last_step = step
        return disc + bias

    def size(self, q) -> float:
        """The half-width (the unresolved viscoelastic edges are relative to it)."""
        return q["a"]

    def image_error(self, q, L) -> float:
        """The periodic images' error, amplitude x exp(-decay rate x free period)."""
        return self.image_amplitude * (self.image_factor or 1.0) * math.exp(
            -self.prob.film.decay_rate * max(L - 2.0 * q["a"], 0.0))

    def fields(self, sol, p, shear):
        """The base stresses (sigma_zz, sigma_xz) of the pressure and its shear (2 FFT pairs)."""
        szz, (sxz,) = self.prob.film.base_stresses(get_rfft(sol.grid.shape), sol.grid, -p,
                                                   (shear,))
        self.prob.counters["transforms"] += 2
        return szz, sxz

    def level_row(self, n, q):
        return (n, q["a"], q["c"], q["d"], q["pmax"])

    def result(self, lv, fields, info, wall, plan_time, shear) -> ContactResult:
        """The final level's ContactResult."""
        prob, scene = self.prob, self.scene
        fine, q = lv.cur, lv.cur.q
        sol, (szz, sxz) = fine.sol, fields
        info.update({
            "fft_pairs": prob.counters["transforms"],
            "krylov_iterations": prob.counters["linear_iterations"],
            "edges": q["edges"],
            "poisson": scene.poisson,
            "image_error": lv.image_error,
            "estimate_parts": lv.parts,
            "domain_difference": lv.domain_diff,
            # a viscoelastic film: an edge structure |V| tau resolved (a term heavier than
            # LAYER_FITTED_WEIGHT, or every term in ``solve_fft``'s fallback)
            **({"edge_structure_resolved": True} if self.unfitted_edge_scales() else {}),
        })
        if prob.visco:  # the averaged centroid (the error estimate covers it: _steps)
            info["pressure_centroid"] = q["m"]
            if self.friction_images is not None:
                info["friction_images_bound"] = self.friction_images
        if prob.c:
            info["interface_compliance"] = prob.c
        if self.exponential:
            info["width_definition"] = (f"exponential interface: no sharp edges; the contact "
                                        f"window is where p >= {EDGE_FRACTION:g} p_max")
        return ContactResult(
            scene=scene, model=prob.model, method="fft", x=sol.grid.x, pressure=sol.pressure,
            base_sigma_zz=szz, base_sigma_xz=sxz, half_width=q["a"], center=q["c"],
            indentation=q["d"], max_pressure=q["pmax"], max_pressure_x=q["xmax"],
            grid_points=sol.grid.n, domain_length=sol.grid.length, iterations=sol.iterations,
            residual=fine.residual, error_estimate=lv.est, wall_time_s=wall,
            plan_time_s=plan_time, info=info, counters=dict(prob.counters), shear=shear)
