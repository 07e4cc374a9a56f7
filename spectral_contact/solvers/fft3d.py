"""The spectral method in 3D: an indenter of finite size on the film, the surface a 2D periodic
grid, the same contact solver as in 2D (``numerics.contact.solve_contact``).

Resolution from a tolerance, as in 2D:

1. A coarse solve on a generous domain (the indenter's half-space contact bounds the film's)
   locates the contact.
2. The periods are the contact's extents plus the film's decay margin ln(100/tol)/0.739 h per
   axis (periodic images ~tol/100), centred on the contact.
3. The grid is doubled (same periods, nested nodes, each level started from the previous
   solution) until two successive levels agree to ``tol`` on the contact radius sqrt(A/pi), the
   pressure centroid (relative to the radius), the indentation, the line load at y = 0 and the
   peak pressure.  The last difference is returned as the error estimate: the measures converge
   at least linearly in the cell size, so the difference between N/2 and N bounds the error at
   N (tests/test_three_d.py checks it against finer grids and the axisymmetric reference).
   On a viscoelastic film the radius's part is at least what its two error parts leave
   when they cancel in that difference (``_radius_bound``).
   The contact's x and y extents (envelopes of edges fitted along grid lines, to a few
   hundredths of a cell) are reported with their own level difference,
   ``info["extent_error_estimate"]``, not controlled by tol: at a smooth tip the lines graze
   the boundary and the envelope's error does not fall steadily with the cell.

Why tol = 1e-3 by default in 3D (1e-4 in 2D): each level costs N^2 points, and 1e-4 needs about
3 times finer cells than 1e-3 (10x the points and time); 1e-3 is below what a MEMS
measurement resolves (~1 % here).  The finite cylinder's default is 1e-2 (``default_tol``):
its sharp ends make the pressure singular there, the peak pressure grows with the resolution
(it is reported, not controlled: the line load at y = 0 takes its place in the estimate) and the
other measures converge only at first order in the cell size (measured: the indentation's
level differences halve per doubling, 0.9 % at 512^2 for the paper's slide), so 1e-3 would need
~8192^2 points.

Memory is estimated before any allocation; a scene that would not fit is refused (InputError).
"""
from __future__ import annotations

import functools
import logging
import math
import os
import time

import numpy as np

from ..errors import ConvergenceError, InputError
from ..numerics.contact import nested_guess
from ..numerics.grid import Grid, pow2_at_least
from ..numerics.measure2d import measure_contact_2d
from ..numerics.open_domain import box_of, open_grid
from ..numerics.operators import tail_terms
from ..physics.film import Film
from ..physics.scene import Scene3D, check_positive
from ..result import ContactResult3D
from .base import check_grid_points
from .fft3d_fields import _FAR_CELLS, _far_fields, _open_contact, _output_fields, _touches_box
from .fft_driver import VISCO_EDGE_CELLS, VISCO_EDGE_SHARE, Level, Problem, finish, refine, run

__all__ = ["solve_fft3d", "MIN_POINTS_3D", "MAX_POINTS_3D", "memory_needed", "default_tol"]


def default_tol(scene: Scene3D) -> float:
    """1e-3, or 1e-2 for the finite cylinder (sharp ends: first-order convergence)."""
    return 1e-2 if scene.indenter == "cylinder" else 1e-3

MIN_POINTS_3D = 32
MAX_POINTS_3D = 8192     # per axis
_FIRST_ACROSS = 16       # grid points across the contact's smaller extent on the first level
_BYTES_PER_POINT = 8 * 40  # fields, spectra, symbols and preconditioners (measured ~30 arrays)
_BYTES_PER_CONTACT_NODE = 8 * 130  # GMRES: restart 60 -> 2 x 61 vectors of the active set
_OPEN_ABOVE = 512  # a periodic locator that needs more points per axis than this (contacts
# below a/h ~ 0.25 at tol 1e-3): the contact is solved on an open box instead (_solve_open)
_END_ASPECT = 2.0  # the finite cylinder's cells: dx = this x dy (issue 25).  Measured on the
# paper's slide (default tol 1e-2, its automatic periods): at ny = 1024 the indentation and the
# line load at y = 0 move by 1e-5 and 3e-5 between nx = 256 and 1024 (between ny = 512 and
# 1024: 3.9e-3 and 5.3e-3), the contact radius by 1.3e-3; levels (256, 512) -> (512, 1024)
# differ as (512, 512) -> (1024, 1024) do (3.9e-3 vs 3.8e-3 on the indentation)
_OPEN_MARGIN = 1.5  # the open solve's estimate: this times the last two levels' difference
# A viscoelastic film's edge structure |V| tau_i without cells of its own (issue 23's sixth
# session): the trailing edges fitted with their inner layer and p_max with the odd-even mode
# (``measure_contact_2d``), no unresolved-edge bound, where that was verified (studies/README,
# viscoelastic, **sphere**: the sphere's estimate bounded its error against 4 times finer
# cells per axis in 54 of 54 automatic solves at 1e-4 ... 3e-2 m/s, tol 1e-2, 5e-3, 1e-3:
# SLS E_1 = E_inf with mu 0 and 0.5, a two-term series of r = 1/2, mu 0).
# Seventh session: stiffer films, r = E_inf/E_0 < 1/2, had the fitted radius escape its
# estimate (E_1 = 3 E_inf, 3 cm/s: 1.2e-3 against 5.2e-4; E_1 = 10 E_inf, 1 mm/s: 1.4e-3
# against 1.1e-3).  Why: the error was at the trailing edge (rows' left edges and the
# trailing half's columns up to 0.45 cells off on 512 x 256 against 4096 x 2048; the leading
# edge within 1e-4 h): behind it the gap is the glassy r (2/3) s^{3/2} within |V| tau_r, r
# times flatter, so the gap's other terms (which the fit's quadratic in gap^{2/3} does not
# hold) weigh 1/r more in the fitted root, while the pressure there is the elastic A sqrt(eps)
# on any film (``edges.viscous_gap``'s derivation).  So below r = 1/2 the trailing edges are
# fitted from the pressure side (``trailing_from_pressure``; ``measure2d._pressure_root``):
# the radius 2.0e-4, 1.3e-4, 1.3e-5 off at 256^2 ... 1024^2 (E_1 = 10 E_inf, 1 mm/s, against
# 2048^2; the gap fit 1.8e-3, 1.5e-3, 4.2e-4).  Each edge is fitted from the side without a
# layer: at the leading edge R p, not p, is the elastic square root, the gap opens as
# s^{3/2}.  The range down to r = 1/11 is verified (``--parts sphere_beyond``), except where a
# heavy term's leading edge peak may be the pressure maximum (``_leading_peak_terms``): those
# terms keep the grid rule and the bound.  tol below 1e-3: not measured.
_FITTED_MIN_RATIO = 1.0 / 11.0  # r = E_inf/E_0 at least (E_1 = 10 E_inf: verified)
_FITTED_MIN_TOL = 1e-3   # tol at least
_PRESSURE_SIDE_BELOW = 0.5  # r below this: the trailing edges fitted from the pressure side
_PEAK_WEIGHT = 3.51  # E_i/E_inf above which the leading edge's layer has a local maximum:
# p = A [sqrt(eps) + w sqrt(lambda) D(sqrt(eps/lambda))], d/dz (z + w D(z)) = 1 + w (1 - 2 z
# D(z)) vanishes for w > 1/0.2847 (min of 1 - 2 z D(z) = -0.2847 at z = 1.50)


def edges_fitted(film, tol: float) -> bool:
    """Whether a surface's viscoelastic edge structure is left to the edge fits (no grid rule,
    no unresolved-edge bound, but for ``_leading_peak_terms``): r = E_inf/E_0 >=
    _FITTED_MIN_RATIO and tol >= _FITTED_MIN_TOL."""
    r = film.relaxed_young / film.glassy_young
    return r >= _FITTED_MIN_RATIO * (1.0 - 1e-9) and tol >= _FITTED_MIN_TOL * (1.0 - 1e-9)


def trailing_from_pressure(film) -> bool:
    """Whether the trailing edges are fitted from the pressure side (the comment above
    _FITTED_MIN_RATIO): a film more than twice as stiff when glassy, r < _PRESSURE_SIDE_BELOW."""
    return film.relaxed_young / film.glassy_young < _PRESSURE_SIDE_BELOW * (1.0 - 1e-9)


@functools.lru_cache(maxsize=64)
def _peak_factor(w: float) -> float:
    """max over z of z + w D(z) (D Dawson's integral; z = sqrt(eps/lambda)): the leading
    edge layer's local maximum in units of A sqrt(lambda) (w > _PEAK_WEIGHT)."""
    from scipy.optimize import minimize_scalar
    from scipy.special import dawsn
    res = minimize_scalar(lambda z: -(z + w * float(dawsn(z))), bounds=(0.3, 1.5),
                          method="bounded", options={"xatol": 1e-6})
    return -float(res.fun)


def _leading_peak_terms(edge_scales, radius: float, merged=None) -> list:
    """The (|V| tau_i, E_i/E_inf) of the terms whose leading edge peak may be the pressure
    maximum: E_i/E_inf > _PEAK_WEIGHT and that peak, ~A sqrt(lambda_i) _peak_factor(w_i), at
    least the Hertzian centre's A sqrt(a/2) (A the edge's square-root amplitude: p0 sqrt(2
    eps/a)), i.e. sqrt(2 lambda_i/a) _peak_factor(w_i) >= 1.  Unresolved, that peak is missed
    (E_1 = 10 E_inf, 1 cm/s, where the ratio is 1.8: p_max 20.7, 19.0, 17.4, 17.39 at 512 x 256
    ... 4096 x 2048); each term taken with those of nearby tau (``merged``: the film's
    ``merged_weights``; default each alone), its own weight returned."""
    merged = [w for _, w in edge_scales] if merged is None else merged
    return [(lam, w) for (lam, w), m in zip(edge_scales, merged)
            if m > _PEAK_WEIGHT and math.sqrt(2.0 * lam / radius) * _peak_factor(m) >= 1.0]


def memory_needed(nx: int, ny: int, contact_fraction: float = 0.25) -> float:
    """Bytes a contact solve on an nx x ny grid needs (estimate, within ~2x)."""
    n = nx * ny
    return n * _BYTES_PER_POINT + contact_fraction * n * _BYTES_PER_CONTACT_NODE


def _available_memory() -> float:
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return 8e9


def _check_size(shape, what: str) -> None:
    nx, ny = shape
    if max(nx, ny) > MAX_POINTS_3D:
        raise InputError(f"{what} needs a {nx:.3g} x {ny:.3g} grid (> {MAX_POINTS_3D} per axis): "
                         f"raise tol, or the contact is too small for the film (use model hertz)")
    need = memory_needed(nx, ny)
    have = _available_memory()
    if need > 0.8 * have:
        raise InputError(f"{what} needs a {nx} x {ny} grid, ~{need / 1e9:.1f} GB, more than the "
                         f"{have / 1e9:.1f} GB available: raise tol or fix smaller grid_points")


def _radius(q) -> float:
    """The contact radius sqrt(A/pi) of a level's measures ``q``."""
    return math.sqrt(max(q["area"], 0.0) / math.pi)


def _difference(q, r, singular_peak: bool = False) -> float:
    """Relative difference of two levels' controlled measures: contact radius sqrt(A/pi),
    pressure centroid (relative to the radius), indentation, line load at y = 0 and peak
    pressure (left out where it is singular: sharp ends)."""
    rad = max(_radius(q), 1e-300)
    r_rad = _radius(r)
    out = max(abs(rad - r_rad) / rad, abs(q["xc"] - r["xc"]) / rad,
              abs(q["indentation"] - r["indentation"]) / max(abs(q["indentation"]), 1e-300),
              abs(q["line_load_y0"] - r["line_load_y0"]) / max(abs(q["line_load_y0"]), 1e-300))
    if not singular_peak:
        out = max(out, abs(q["pmax"] - r["pmax"]) / max(q["pmax"], 1e-300))
    return out


# A viscoelastic surface's radius (tenth session, studies/README, viscoelastic: the surfaces'
# estimate and the far-field period).  Its error has two parts of different order: the
# polygon's chord deficit (inward, ~dx^2) and the edge fits' sub-cell bias (~dx, either sign);
# where they cancel in the last two levels' difference, that difference is no bound.
# (a) With a third nested level: neither part falls faster than second order, so the
# radius's difference d_k (its relative change from the previous level) is at least
# |d_(k-1)|/4 unless its parts cancel; the radius's part of the estimate is at least that,
# |d_(k-1)|/_CANCELLED.  A heuristic, measured, not a guarantee: the two-part model u dx +
# v dx^2 with d_k = 0 exactly has the error |d_(k-1)|/3, and its worst case (u = -4v: level
# errors 0, -4, -3) is 3 times max(|d_k|, |d_(k-1)|/4); /3 was tried and sends 1.25 N SLS
# spheres at tol 1e-3 a level finer (studies/README).  On the recorded levels /4 bounds 104
# of 104 rows (at most 0.74 of the estimate) and 67 of 67 on the earlier periods.  Measured:
# the two-term film (tol 1e-3, 3 mm/s) 7.0e-5 off under a difference of 3.4e-7
# (d_(k-1) 6.0e-4), E_1 = 10 E_inf (tol 1e-3, 1 mm/s) 5.4e-4 under 1.3e-4 (d_(k-1) 2.9e-3).
_CANCELLED = 4.0
# (b) With two levels only and the trailing edges fitted from the pressure side
# (``trailing_from_pressure``): that fit's bias does not fall from 128^2 to 256^2 (the
# radius's error in cells against 4x the cells, E_1 = 3 and 10 E_inf, 0.8 ... 1.5 N, mu 0 and
# 0.5, 1e-4 ... 3e-2 m/s, tol 1e-2 ... 1e-3: -0.041 ... +0.044 at 128^2, -0.025 ... +0.027 at
# 256^2), so the difference misses it (E_1 = 3 E_inf, 1 N, tol 1e-2, 1 mm/s: 7.5e-4 off under
# 5.6e-4); the radius's part is at least _PRESSURE_FIT_CELLS cells over the radius (measured,
# not derived: the largest error of a final two-level grid was 0.0265 cells, in 152 of them).
_PRESSURE_FIT_CELLS = 0.03


def _radius_bound(history, cur, from_pressure: bool) -> float:
    """A viscoelastic surface's lower bound of the radius's estimate (the comments above
    _CANCELLED and _PRESSURE_FIT_CELLS): ``history`` the levels [(shape, q)], its last
    ``cur``'s; 0 where neither applies."""
    rad = max(_radius(cur.q), 1e-300)
    if len(history) >= 3 and tuple(history[-3][0]) == tuple(n // 2 for n in history[-2][0]) \
            and tuple(history[-2][0]) == tuple(n // 2 for n in history[-1][0]):
        return abs(_radius(history[-2][1]) - _radius(history[-3][1])) / rad / _CANCELLED
    if from_pressure:
        return _PRESSURE_FIT_CELLS * max(cur.grid.spacing) / rad
    return 0.0


def _extent_difference(q, r) -> float:
    """Largest change of the contact's extents between two levels, relative to the radius."""
    rad = max(_radius(q), 1e-300)
    return max(abs(q[k] - r[k]) for k in ("x_min", "x_max", "y_min", "y_max")) / rad


def _measure(sol, ind, trailing=None, from_pressure=False) -> dict:
    """The measures of ``measure_contact_2d`` (``trailing``: a viscoelastic film's trailing
    edges' inner layer, ``Problem.trailing``; ``from_pressure``: those edges fitted from the
    pressure side) and the indentation."""
    q = measure_contact_2d(sol.grid, sol.pressure, sol.gap, sol.active, trailing, from_pressure)
    q["indentation"] = float(sol.indentations[0])
    end = getattr(ind, "half_length", None)
    if end is not None:  # a sharp end is the contact's edge: the fit cannot pass it
        q["y_min"], q["y_max"] = max(q["y_min"], -end), min(q["y_max"], end)
    return q


def _check_fixed(grid_points, domain_length):
    """(nx, ny) and (Lx, Ly) from one value or a pair each (None passes through)."""
    if grid_points is not None:
        gp = tuple(grid_points) if np.ndim(grid_points) else (grid_points, grid_points)
        if len(gp) != 2:
            raise InputError(f"grid_points (3D) must be one even integer in [{MIN_POINTS_3D}, "
                             f"{MAX_POINTS_3D}] or a pair [nx, ny] of them; got {grid_points!r}")
        grid_points = tuple(check_grid_points(n, MIN_POINTS_3D, MAX_POINTS_3D,
                                              "3D, points per axis", even=True) for n in gp)
    if domain_length is not None:
        dl = tuple(domain_length) if np.ndim(domain_length) else (domain_length, domain_length)
        if len(dl) != 2:
            raise InputError(f"domain_length (3D) must be > 0 (one value or [Lx, Ly]); got "
                             f"{domain_length!r}")
        domain_length = tuple(check_positive("domain_length", v, "h") for v in dl)
    return grid_points, domain_length


def solve_fft3d(scene: Scene3D, model: str = "exact", tol: float = 1e-3, grid_points=None,
                domain_length=None, progress=None) -> ContactResult3D:
    """Solve a 3D ``scene`` with the spectral method.

    model : "exact" (friction coupled into the contact) or "goodman" (frictionless contact;
            friction loads the base only).
    tol : relative accuracy target of the contact radius, x extents, centroid, indentation and
          peak pressure.
    grid_points : fix (nx, ny) (or one N for both) instead of refining from ``tol``;
    domain_length : fix the periods (Lx, Ly) [in h].
    progress : optional callable(str), told about each level (default: the INFO log of this
        module, which the command line shows on a terminal once a command passes 2 s).
    """
    # issue 14: any nu (nu = 1/2: the incompressible path); issue 23: a viscoelastic film in
    # steady sliding (its relaxation tail lengthens the period along x only, up to 2.7 h:
    # longer tails have their images summed, numerics.operators.tail_terms).  The locator's
    # inner solves are looser on every path (adaptive=True: its contact only sizes the period
    # and the grid).
    prob = Problem(scene, model, tol, adaptive=True,
                   progress=logging.getLogger(__name__) if progress is None else progress)
    grid_points, domain_length = _check_fixed(grid_points, domain_length)
    # the inner (GMRES) solves to 1e-4 of the accepted residual (issue 25: 1e-10 before; one
    # to two GMRES iterations per active-set step for digits no measure keeps; 1e-3 left the
    # surface 1.6e-7 d off the indenter at tol 3e-3, 1e-4 2e-9)
    prob.rtol = max(1e-10, 1e-4 * prob.accept)
    return run(_SurfaceSolve(prob, grid_points, domain_length))


class _SurfaceSolve:
    """The surface's steps of the one driver (``fft_driver``)."""

    MIN_LEVELS = 2  # the estimate is the last two levels' difference
    RETRY_FINER = True
    ALTERNATIVE = "raise tol"

    def __init__(self, prob: Problem, grid_points, domain_length):
        self.prob, self.scene = prob, prob.scene
        self.grid_points, self.domain_length = grid_points, domain_length
        self.ind = self.scene.indenter_object()
        # a user grid on a user period (issue 25): no locator, whose contact would only be
        # checked against the period (~4-6 FFT-pair times of 512^2); the first level's is
        self.fixed_box = bool(grid_points) and domain_length is not None
        if prob.visco:  # the long relaxation tails' images are summed exactly (tail_terms)
            prob.margin = prob.film.domain_margin(prob.tol, tails_corrected=True)
        # no unresolved-edge bound (``unfitted_edge_scales``) nor grid rule when the fits
        # carry the edge structure
        self.EDGE_LAYER_FITTED = prob.visco and edges_fitted(prob.film, prob.tol)
        self.radius = None  # the located contact's (``level_shapes``)
        self.TRAILING_FROM_PRESSURE = prob.visco and trailing_from_pressure(prob.film)

    def unloaded(self) -> ContactResult3D:
        """P = 0: no contact, zero fields."""
        prob = self.prob
        Lx, Ly = self.domain_length or (prob.margin, prob.margin)
        g = Grid.centered(self.grid_points or (MIN_POINTS_3D, MIN_POINTS_3D), (Lx, Ly))
        z = np.zeros(g.shape)
        q = measure_contact_2d(g, z, z, z > 0) | {"indentation": 0.0}
        return ContactResult3D(prob.scene, prob.model, "fft", g.axes[0], g.axes[1], z, z, z, z, z,
                               z, z, q, g.shape, g.lengths, 0, 0.0, 0.0,
                               time.perf_counter() - prob.t0, 0.0, counters=prob.counters)

    def shortcut(self):
        """A small contact (issue 24): cells sized from the contact on an open box (the result),
        when the periodic locator would need more than _OPEN_ABOVE points per axis; else None."""
        prob = self.prob
        self.n0, self.L0 = self.locator_grid()
        if not self.grid_points and self.domain_length is None and not prob.with_law \
                and not prob.visco and max(self.n0) > _OPEN_ABOVE:
            steps = _OpenSolve(prob, self.ind)
            return finish(steps, steps.refine(steps.period(steps.locate())))
        return None

    def locate(self):
        """1. the contact on the locator's grid: (sol, q); None on a fixed box (issue 25)."""
        if self.fixed_box:
            return None
        _check_size(self.n0, "locating the contact")
        self.prob.say(f"locating the contact on a {self.n0[0]} x {self.n0[1]} grid")
        sol = self.contact(Grid.centered(self.n0, self.L0), locator=True)
        return sol, _measure(sol, self.ind, self.prob.trailing, self.TRAILING_FROM_PRESSURE)

    def refine(self, period):
        """3. the levels on the periods (``fft_driver.refine``)."""
        L, center, widths = period
        return refine(self, self.level_shapes(L, widths), L, center)

    def contact(self, grid, p_init=None, locator=False):
        prob, film = self.prob, self.prob.film
        if prob.visco and p_init is None:  # the indenter's own guess, not the nested
            # start: its coarse grids on a long period held the contact on a node or two
            # (measured: the sphere at V = 10 m/s, tau 10 ms failed on the load residual, 5 %)
            p_init = np.broadcast_to(self.ind.initial_pressure(grid), grid.shape).copy()
        return prob.count(prob.solve_contact(grid, [self.ind], film, p_init, locator))

    def locator_grid(self):
        """1. the locator's grid (n0, L0): the indenter's extent bound and the decay margin
        (never a user period, nor the viscoelastic tail's margin: it only locates)."""
        prob, film = self.prob, self.prob.film
        ex, ey = self.ind.extent_bound()
        if not (ex > 0 and ey > 0 and math.isfinite(ex) and math.isfinite(ey)):
            raise InputError(f"the indenter's contact extent bound ({ex:g}, {ey:g}) h is not "
                             f"usable")
        m0 = Film.domain_margin(film, prob.tol) if prob.visco else prob.margin
        L0 = (4.0 * ex + m0, 4.0 * ey + m0)
        d0 = 2.0 * min(ex, ey) / _FIRST_ACROSS
        if self.grid_points:
            n0 = tuple(max(MIN_POINTS_3D, n // 4 // 2 * 2) for n in self.grid_points)
        else:
            n0 = tuple(pow2_at_least(L / d0, MIN_POINTS_3D) for L in L0)
        return n0, L0

    def check_period(self, q) -> None:
        """A user period must hold the contact plus the decay of its images to tol/2."""
        tol, dl = self.prob.tol, self.domain_length
        width_x, width_y = q["x_max"] - q["x_min"], q["y_max"] - q["y_min"]
        free = math.log(2.0 / tol) / self.prob.film.decay_rate
        need = (width_x + free, width_y + free)
        visco = self.prob.visco
        if visco:  # and along x the relaxation tail behind the contact (issue 23)
            need = (need[0] + self.margin_x(width_x, width_y)
                    - Film.domain_margin(self.prob.film, tol), need[1])
        if any(L < n for L, n in zip(dl, need)):
            raise InputError(
                f"domain_length ({dl[0]:.4g}, {dl[1]:.4g}) h is too short "
                f"for this contact at tol {tol:g}: the periods must hold the contact "
                f"({width_x:.3g} x {width_y:.3g} h) plus {free:.3g} h for its images to decay "
                f"below tol/2{' (along x also the relaxation tail behind it)' if visco else ''}: "
                f"at least ({need[0]:.4g}, {need[1]:.4g}) h, or leave it automatic")

    def margin_x(self, width_x: float, width_y: float) -> float:
        """A viscoelastic film's margin along x, the sliding direction: the kernel's far field
        as on lines (``ViscoelasticFilm.line_margin``: the elastic poles times R there, the
        tails shorter than 2.7 h, the longer ones' images summed; relative to the contact's
        |R(1/radius)|, radius (width_x + width_y)/4), not the elastic margin plus the tail's
        (``ViscoelasticFilm.domain_margin``; before the tenth session): the decays do not
        add.  The images on that period: studies/README, viscoelastic, eighth session (tried
        there); the size is the mean radius, measured on spheres (a contact elongated along
        y gets a shorter margin than its half-width along x would give)."""
        return self.prob.film.line_margin(self.prob.tol, self.prob.mu_contact,
                                          size=0.25 * (width_x + width_y))

    def period(self, located):
        """2. the periods: the contact plus the decay margin, centred on the contact (a fixed
        box: the user's).  (L, center, (width_x, width_y) or None)."""
        prob, dl = self.prob, self.domain_length
        if located is None:
            return dl, (0.0, 0.0), None
        sol, q = located
        width_x = q["x_max"] - q["x_min"]
        width_y = q["y_max"] - q["y_min"]
        if dl is not None:
            self.check_period(q)
        guard = 4.0 * max(sol.grid.spacing)
        if prob.visco and dl is None:
            prob.margin = self.margin_x(width_x, width_y)
        # the tail is along x
        margin_y = Film.domain_margin(prob.film, prob.tol) if prob.visco else prob.margin
        L = dl or (width_x + prob.margin + guard, width_y + margin_y + guard)
        center = (0.5 * (q["x_max"] + q["x_min"]), 0.0) if dl is None else (0.0, 0.0)
        return L, center, (width_x, width_y)

    def level_shapes(self, L, widths):
        """The grids (nx, ny) to refine through: the user's N/2 and N, or doublings from cells
        of the contact's smaller width / _FIRST_ACROSS up to MAX_POINTS_3D."""
        if self.grid_points:
            return [tuple(n // 2 for n in self.grid_points), self.grid_points]
        tol = self.prob.tol
        width_x, width_y = widths
        d1 = min(width_x, width_y) / _FIRST_ACROSS
        # sharp ends (finite cylinder): cells _END_ASPECT times longer across the cylinder
        # (x) than along it: the ends' singularity sets the error, through the cells along y
        stretch = (_END_ASPECT, 1.0) if self.ind.singular_peak else (1.0, 1.0)
        dx1 = d1 * stretch[0]
        radius = self.radius = 0.25 * (width_x + width_y)
        for width, weight in self.unfitted_edge_scales():
            # as in 2D (solvers.fft._level_sizes): resolve the edge structure |V| tau_i (along
            # x, the sliding direction) of a term that moves the contact by more than a share
            # of tol (issue 23)
            if weight * width / radius > VISCO_EDGE_SHARE * tol:
                dx1 = min(dx1, width / VISCO_EDGE_CELLS)
        n1 = (pow2_at_least(L[0] / dx1, MIN_POINTS_3D),
              pow2_at_least(L[1] / (d1 * stretch[1]), MIN_POINTS_3D))
        if dx1 < d1 * stretch[0] and n1[0] > MAX_POINTS_3D:
            raise InputError(
                f"the viscoelastic film's edge structure (|V| tau down to "
                f"{dx1 * VISCO_EDGE_CELLS:.2g} h) needs ~{L[0] / dx1:.2g} points along x at tol "
                f"{tol:g} (> {MAX_POINTS_3D}): raise --tol, or change --speed")
        levels = [n1]
        while max(levels[-1]) < MAX_POINTS_3D:
            levels.append(tuple(2 * n for n in levels[-1]))
        return levels

    def grid(self, shape, L, center):
        _check_size(shape, f"tol {self.prob.tol:g}")
        return Grid.centered(shape, L, center)

    def start(self, g, located, prev):
        """The previous level's pressure, refined (nested), else the indenter's own guess."""
        if prev is not None and prev.grid.shape == tuple(n // 2 for n in g.shape):
            return nested_guess(prev.sol, g)
        return None

    def solve_level(self, g, p_init, first=False):
        """A level's solve and measures; a fixed box's first level checks the user's period."""
        cur = self.contact(g, p_init=p_init)
        q = _measure(cur, self.ind, self.prob.trailing, self.TRAILING_FROM_PRESSURE)
        if self.radius is None and q["area"] > 0.0:  # a user grid: no located contact
            self.radius = math.sqrt(q["area"] / math.pi)
        if self.fixed_box and first:
            self.check_period(q)
        return Level(g, cur, q, cur.residual)

    def difference(self, lv, cur, prev):
        """The levels' difference of the controlled measures (``_difference``); the extents'
        own is recorded (``extent_error_estimate``)."""
        lv.extent_est = _extent_difference(cur.q, prev.q)
        out = _difference(cur.q, prev.q, self.ind.singular_peak)
        if self.prob.visco:  # the radius's parts that cancel (``_radius_bound``)
            out = max(out, _radius_bound(lv.history, cur, self.TRAILING_FROM_PRESSURE))
        return out

    def unfitted_edge_scales(self) -> list:
        """The edge scales ``fft_driver.estimate`` bounds as unresolved: where the fits carry
        them (``edges_fitted``) only the terms whose leading edge peak may be the pressure
        maximum (``_leading_peak_terms``, on the located contact's radius), else every
        term's."""
        scales = self.prob.film.edge_scales()
        if not self.EDGE_LAYER_FITTED:
            return scales
        return _leading_peak_terms(scales, self.radius, self.prob.film.merged_weights()) \
            if self.radius else []

    def size(self, q) -> float:
        """The contact radius sqrt(A/pi) (the unresolved viscoelastic edges are relative to it)."""
        return _radius(q)

    def image_error(self, q, lengths) -> float:
        """0: the periods' decay margin keeps the images ~tol/100, not part of the estimate."""
        return 0.0

    def level_row(self, shape, q):
        return (shape, q["area"], q["x_min"], q["x_max"], q["indentation"], q["pmax"])

    def fields(self, sol, p, shear):
        """The final grid's base tractions and surface displacements (FFT pairs counted)."""
        prob, scene, film = self.prob, self.scene, self.prob.film
        if prob.visco:  # the elastic film's multipliers, the displacements' times R(k)
            # (``fft3d_fields._multipliers``, cached per grid as the elastic film's; Amontons
            # only on a Prony film); the surface displacements with the long tails' images
            # summed as in the contact (numerics.operators.tail_terms)
            szz, sxz, syz, ux, uy, delta = _output_fields(film, sol.grid, p, scene.mu, shear)
            g, flat = sol.grid, p.ravel()

            def summed(field, poles):
                for t in tail_terms(g.shape, g.lengths, poles):
                    field = field + t.field(flat, slice(None)).reshape(p.shape)
                return field
            delta = summed(delta, film.tail_poles(scene.mu))
            tails = film.tail_displacement_poles(scene.mu)
            ux = summed(ux, [(length, bx) for length, bx, _ in tails])
            uy = summed(uy, [(length, by) for length, _, by in tails])
            prob.counters["transforms"] += 5
            return szz, sxz, syz, ux, uy, delta
        # (a law with q = mu p exactly, e.g. power with n = 0: the Amontons fields, bit for bit)
        law = prob.law
        prop = scene.mu if scene.friction.is_amontons else law.mu if law.proportional else None
        out = _output_fields(film, sol.grid, p, prop, shear)
        prob.counters["transforms"] += 4
        return out

    def deformation_friction(self, sol, p) -> float:
        """mu_def = Int p df/dx / P on every film (Q_over_P = Int q / P + mu_def, issue 23),
        df/dx = (h/2R) d f_core / d x_core (central differences, exact for quadratic heights),
        over the contact nodes."""
        scene = self.scene
        f = np.asarray(self.ind.height(sol.grid), dtype=float)
        with np.errstate(invalid="ignore"):  # inf - inf beyond a finite cylinder's ends, off contact
            dfdx = (np.roll(f, -1, axis=0) - np.roll(f, 1, axis=0)) / (2.0 * sol.grid.spacing[0])
        on = p > 0
        return (float(np.sum(p[on] * dfdx[on]) / np.sum(p[on])) * scene.thickness
                / (2.0 * scene.radius) if on.any() else 0.0)

    def result(self, lv, fields, info, wall, plan_time, law_shear) -> ContactResult3D:
        prob, scene = self.prob, self.scene
        sol, q = lv.cur.sol, lv.cur.q
        p = sol.pressure
        szz, sxz, syz, ux, uy, delta = fields
        info.update(_surface_info(lv))
        info["deformation_friction"] = self.deformation_friction(sol, p) + 0.0
        x, y = sol.grid.axes
        return ContactResult3D(
            scene=scene, model=prob.model, method="fft", x=x, y=y, pressure=p,
            base_sigma_zz=szz, base_sigma_xz=sxz, base_sigma_yz=syz, surface_ux=ux,
            surface_uy=uy, surface_uz=-delta, measures=q, grid_points=sol.grid.shape,
            domain_length=sol.grid.lengths, iterations=sol.iterations, residual=sol.residual,
            error_estimate=lv.est, wall_time_s=wall, plan_time_s=plan_time, info=info,
            counters=prob.counters, shear=law_shear)


def _surface_info(lv) -> dict:
    """The ``info`` entries of a surface besides the driver's (periodic grid or open box)."""
    sol, q = lv.cur.sol, lv.cur.q
    return {
        "load_on_grid": q["load"],
        "extent_error_estimate": lv.extent_est,
        "extent_note": "contact x and y extents are envelopes of edges fitted along grid lines "
                       "(a few hundredths of a cell); not controlled by tol: their level "
                       "difference is extent_error_estimate",
        # the finest grid's own work (its nested start's coarser grids excluded), issue 25
        "final_level_fft_pairs": sol.fft_pairs - sol.coarse_fft_pairs,
    }


class _OpenSolve(_SurfaceSolve):
    """A contact much smaller than the film's decay margin (issue 24), the surface's shortcut:
    solved on an open box (``numerics.open_domain``: the film's kernel in real space,
    non-periodic), cells sized from the contact, refined by the driver's levels until two
    agree to ``tol`` (1.5 x their difference); the base fields from the film's period
    (``_far_fields``).  The reported grid is the box."""

    MIN_LEVELS = 2
    RETRY_FINER = False  # a contact reaching its box's border is not helped by finer cells

    def __init__(self, prob: Problem, ind):
        self.prob, self.scene, self.ind = prob, prob.scene, ind
        self.grid_points = self.domain_length = None
        self.fixed_box = False
        self.solved = 0  # levels

    def contact(self, grid, p_init=None, locator=False):
        prob = self.prob
        return prob.count(_open_contact(grid, self.ind, prob.mu_contact, prob.film, prob.c,
                                        prob.accept, p_init))

    def locate(self):
        """The contact on an open box of 4x the indenter's extent bound, doubled while the
        contact reaches its border."""
        ex, ey = self.ind.extent_bound()
        apex = float(getattr(self.ind, "apex", 0.0))
        box = (4.0 * ex, 4.0 * ey)
        d0 = 2.0 * min(ex, ey) / _FIRST_ACROSS
        for _ in range(6):  # the locator's box doubled while the contact reaches its border
            nb = tuple(pow2_at_least(B / d0, MIN_POINTS_3D) for B in box)
            g0 = open_grid(nb, box, (apex, 0.0))
            _check_size(g0.shape, "locating the contact")
            self.prob.say(f"locating the contact on an open {nb[0]} x {nb[1]} box")
            sol = self.contact(g0)
            if not _touches_box(sol):
                break
            box = (2.0 * box[0], 2.0 * box[1])
        return sol, _measure(sol, self.ind)

    def period(self, located):
        """The box: the contact plus 8 cells of the first level each side (the edge fits need
        6), in multiples of 8 cells (FFT-friendly sizes); cells d1 exactly: the levels share the
        box.  (first shape, box, center)."""
        _, q = located
        width = (q["x_max"] - q["x_min"], q["y_max"] - q["y_min"])
        center = (0.5 * (q["x_max"] + q["x_min"]), 0.0)
        d1 = min(width) / _FIRST_ACROSS
        n1 = tuple(max(MIN_POINTS_3D, 8 * math.ceil((w / d1 + 16.0) / 8.0)) for w in width)
        return n1, tuple(n * d1 for n in n1), center

    def refine(self, period):
        """The levels on the box: doublings while the padded grid stays within MAX_POINTS_3D."""
        n1, box, center = period
        shapes = [n1]
        while 4 * max(shapes[-1]) <= MAX_POINTS_3D:
            shapes.append(tuple(2 * n for n in shapes[-1]))
        self.box, self.center = box, center
        return refine(self, shapes, box, center)

    def grid(self, shape, box, center):
        g = open_grid(shape, box, center)
        _check_size(g.shape, f"tol {self.prob.tol:g}")
        return g

    def start(self, g, located, prev):
        return nested_guess(prev.sol, g) if prev is not None else None

    def solve_level(self, g, p_init, first=False):
        cur = self.contact(g, p_init)
        self.solved += 1
        if _touches_box(cur):
            raise ConvergenceError(f"the open box ({self.box[0]:.3g} x {self.box[1]:.3g} h) does "
                                   "not hold the contact: raise tol or fix grid_points",
                                   residuals=[cur.residual], iterations=self.solved)
        return Level(g, cur, _measure(cur, self.ind), cur.residual)

    def difference(self, lv, cur, prev):
        """1.5 x the level difference (as the line solver's _LEVEL_MARGIN): the measures
        converge at first order here (the difference halves per level), where the bare
        difference was measured 0.9x the error against the axisymmetric reference."""
        lv.extent_est = _extent_difference(cur.q, prev.q)
        return _OPEN_MARGIN * _difference(cur.q, prev.q, self.ind.singular_peak)

    def fields(self, sol, p, shear):
        """The base tractions and surface displacements at the box's nodes, from the film's
        period (``_far_fields``); Amontons: its shear mu p made there."""
        sl = box_of(sol.grid)
        pb = np.ascontiguousarray(p[sl])
        gbox = Grid.centered(pb.shape, self.box, self.center)
        law = None if self.prob.friction.is_amontons else np.ascontiguousarray(shear[sl])
        return _far_fields(self.prob.film, gbox, pb, self.scene.mu, self.prob.margin, law)

    def result(self, lv, fields, info, wall, plan_time, law_shear) -> ContactResult3D:
        prob, box = self.prob, self.box
        sol, q = lv.cur.sol, lv.cur.q
        sl = box_of(sol.grid)
        x, y = (a[s] for a, s in zip(sol.grid.axes, sl))
        p = np.ascontiguousarray(sol.pressure[sl])
        uz = -np.ascontiguousarray(sol.sinking[sl])
        szz, sxz, syz, ux, uy, _ = fields
        info.update(_surface_info(lv))
        info["deformation_friction"] = self.deformation_friction(sol, sol.pressure) + 0.0
        info["open_box"] = True
        info["open_box_note"] = (
            "a contact much smaller than h: solved on an open (non-periodic) box of "
            f"{box[0]:.4g} x {box[1]:.4g} h around it (the film's kernel in real space); the "
            "maps cover that box only; the base tractions come from the film's period (exact), "
            f"the surface ux, uy are resolved at h/{_FAR_CELLS} only (u_z and the pressure at "
            "the box's cells)")
        return ContactResult3D(
            scene=self.scene, model=prob.model, method="fft", x=x, y=y, pressure=p,
            base_sigma_zz=szz, base_sigma_xz=sxz, base_sigma_yz=syz, surface_ux=ux,
            surface_uy=uy, surface_uz=uz, measures=q, grid_points=p.shape, domain_length=box,
            iterations=sol.iterations, residual=sol.residual, error_estimate=lv.est,
            wall_time_s=wall, plan_time_s=plan_time, info=info, counters=prob.counters,
            shear=None if law_shear is None else np.ascontiguousarray(law_shear[sl]))
