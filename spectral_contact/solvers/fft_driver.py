"""The FFT method's one driver, lines (``solvers.fft``) and surfaces (``solvers.fft3d``).

``run(steps)`` is the resolution control of both: an unloaded scene, else (a shortcut: the
surfaces' open box for small contacts, itself run by this driver) locate the contact on a coarse
generous grid, set the period(s) from it and the decay margin, refine the grid by doublings from
a nested start until the error estimate is below tol (``refine``), and make the result
(``finish``: the surface shear, the base stresses, the info every solve reports, the timings).

The level loop (``refine``) is one for every dimension: the progress line of each level, the
grid, the nested start, the level's solve, the error estimate (``estimate``: the levels'
difference, the viscoelastic film's unresolved edges, the periodic images), the stop at tol, the
stagnation check, the coarsest level that may not settle.  What differs by dimension are the
small methods of ``steps`` (``_LineSolve``, ``_SurfaceSolve``, ``_OpenSolve``):

- ``unloaded``, ``shortcut``, ``locate``, ``period``, ``refine`` (the run's stages);
- ``grid(shape, lengths, center)``, ``start(grid, located, prev)``, ``solve_level(grid,
  p_init, first)`` (a ``Level``), ``difference(levels, cur, prev)`` (the discretisation part
  of the estimate), ``size(q)`` (the contact's size the unresolved edges are relative to),
  ``unfitted_edge_scales()`` (a viscoelastic film's edge structures the edge fits do not
  carry: resolved by the grid, bounded in the estimate), ``image_error(q, lengths)``;
- ``fields(sol, p, shear)`` (the base stresses: counted), ``level_row(shape, q)``,
  ``result(levels, fields, info, wall, plan_time, law_shear)``;
- the attributes ``grid_points`` (a user-fixed grid: stop after its two levels),
  ``MIN_LEVELS`` (levels solved before the estimate may stop the refinement),
  ``RETRY_FINER`` (a coarsest level that does not settle is skipped), ``ALTERNATIVE`` (what
  the stagnation message advises).

``Problem`` is what both share: the setup (the scene's film in the core's units, the contact
friction of the model, the decay margin, the accepted residual, the friction law and the
interface), the one dispatch of a contact solve (Amontons, or a friction law / compliant
interface: an outer fixed point), the work counters summed over every solve, the final surface
shear, the timings and the progress line of each level.
"""
from __future__ import annotations

import logging
import math
import time

from ..errors import ConvergenceError
from ..numerics.contact import solve_contact
from ..numerics.fft import planning_time
from ..numerics.friction import solve_contact_law
from ..physics.friction import ShearLaw

__all__ = ["Problem", "Level", "Levels", "run", "refine", "estimate", "finish",
           "unresolved_edges", "LOCATOR_RTOL", "LOCATOR_ACCEPT", "LOCATOR_SEARCH_RTOL",
           "VISCO_EDGE_CELLS", "VISCO_EDGE_SHARE", "STAGNATION_DOUBLINGS"]

LOCATOR_RTOL = 1e-6
LOCATOR_ACCEPT = 1e-3
LOCATOR_SEARCH_RTOL = 1e-2  # and while its active set is searched (measured: fewer GMRES
# iterations for the same located contact)
VISCO_EDGE_CELLS = 2  # viscoelastic film on surfaces: cells across the edge structure |V| tau_i
VISCO_EDGE_SHARE = 0.25  # an unresolved term moves x_c and a by up to ~0.6 E_i/E_inf |V| tau_i
# (measured, SLS E_1 = E_inf, paper's scene, V tau/h = 1.5e-3: x_c moved by 6e-4 a from 1024
# to 131072 points, with the elastic edge fit); terms above this share of tol are resolved
# from the first level on (the levels' sizes), the others' weight x width / size is added to
# the error estimate (``unresolved_edges``).  Lines no longer do either for terms up to
# E_i/E_inf = 10 (``_LineSolve.LAYER_FITTED_WEIGHT``): they fit the trailing
# edges with their inner layer (``numerics.edges.viscous_gap``; ``unfitted_edge_scales``), which
# leaves a, x_c within ~5e-5 of a resolved solve with one cell across V tau (a_H/h 1, V tau/h
# 5e-3; 4.5e-4 with the elastic fit) and lets the levels' differences see the rest.
# Surfaces likewise where ``fft3d.edges_fitted`` (r = E_inf/E_0 >= 1/11, tol >= 1e-3: verified).
STAGNATION_DOUBLINGS = 3


class Problem:
    """One FFT solve's setup and bookkeeping (lines and surfaces).

    scene, model, tol : the solve's.  adaptive : the resolution is chosen from tol (not fixed
    by ``grid_points``): the locator's inner solves are then looser.  progress : callable(str)
    told about each level, or a ``logging.Logger`` (its INFO lines, formatted only when that
    level is enabled: the paper scene's three progress lines cost ~1 % of its solve when built
    for nobody), or None (silent).

    Attributes: film (``scene.core_film()``: thickness 1), visco (its symbols depend on the
    sliding), P, mu_contact (mu for the exact model, 0 for Goodman's), margin (the decay margin
    for tol), accept (the residual accepted from each contact solve), friction, law (the law in
    the core's units), with_law, c (the interface compliance), rtol (the inner solves'; set by
    the driver), counters (FFT pairs, outer and inner iterations), law_iterations, trailing
    (``Film.trailing_edge_layer``: the edge fits' shape behind a viscoelastic contact).
    """

    def __init__(self, scene, model: str, tol: float, adaptive: bool = True, progress=None):
        self.t0 = time.perf_counter()
        self.plans0 = planning_time()
        self.scene, self.model, self.tol = scene, model, tol
        self.adaptive = adaptive
        self._logger = progress if isinstance(progress, logging.Logger) else None
        self.progress = progress.info if self._logger is not None else progress
        self.P = scene.P
        self.mu_contact = scene.mu if model == "exact" else 0.0
        self.film = scene.core_film()  # lengths in h: thickness 1 (the scene's film kind)
        self.visco = self.film.moving  # a film whose symbols depend on the sliding
        # its trailing edges' inner layer (the edge fits' shape there), or None
        self.trailing = self.film.trailing_edge_layer()
        self.margin = self.film.domain_margin(tol)  # images ~ tol/100 x O(1)
        # residual (relative displacement / pressure / load) accepted from each contact solve:
        # far below tol, but not below what round-off allows for very wide contacts
        self.accept = max(1e-8, 1e-2 * tol)
        self.rtol = 1e-10
        # a friction law other than Amontons: an outer fixed point around each contact solve
        # (numerics.friction), converged to the same relative accuracy as the contact solves
        self.friction = scene.friction  # (a new FrictionLaw at each access)
        self.law = self.friction.dimensionless(scene.stress_unit, scene.mu)
        self.with_law = model == "exact" and not self.friction.is_amontons
        self.c = scene.interface  # a compliant interface (linear): the operator is H + c
        self.counters = {"transforms": 0, "iterations": 0, "linear_iterations": 0}
        self.law_iterations = 0

    def count(self, sol):
        """Add a contact solve's work to the counters; return it."""
        self.counters["transforms"] += sol.fft_pairs
        self.counters["iterations"] += sol.iterations
        self.counters["linear_iterations"] += sol.krylov_iterations
        return sol

    def tolerances(self, locator: bool):
        """(rtol, accept, search_rtol) of a contact solve: the locator's looser (its contact
        only sizes the period and the grid) on an adaptive solve."""
        if locator and self.adaptive:
            return (max(self.rtol, LOCATOR_RTOL), max(self.accept, LOCATOR_ACCEPT),
                    LOCATOR_SEARCH_RTOL)
        return self.rtol, self.accept, None

    def solve_contact(self, grid, indenters, film, p_init=None, locator=False, d_init=None,
                      extrapolate=None):
        """One contact solve on ``grid`` (Amontons, or the law / interface's fixed point; a
        proportional law stays Amontons bit for bit).  ``d_init``: the first indentations,
        ``extrapolate``: the shrinking sets' ends extrapolated (Amontons; both only change the
        path: ``numerics.contact.solve_complementarity``)."""
        rt, acc, search = self.tolerances(locator)
        if not self.with_law and self.c == 0.0:
            return solve_contact(grid, self.mu_contact, indenters, film=film, p_init=p_init,
                                 rtol=rt, accept=acc, search_rtol=search, d_init=d_init,
                                 extrapolate=extrapolate)
        law = self.law if self.with_law else ShearLaw("amontons", mu=self.mu_contact)
        s_, _, li = solve_contact_law(grid, law, indenters, film=film, interface=self.c,
                                      p_init=p_init, accept=acc, rtol=rt, law_tol=self.accept,
                                      search_rtol=search)
        self.law_iterations += li["law_iterations"]
        return s_

    def surface_shear(self, sol, p):
        """The final surface shear along x: None for Amontons (mu p); the exact model's law
        shear of the coupled solve; Goodman's: the law on the frictionless pressure."""
        if self.friction.is_amontons:
            return None
        return sol.shear if self.with_law else self.law.shear(p)

    def times(self) -> tuple[float, float]:
        """(solve seconds without planning, planning seconds) since the setup."""
        total = time.perf_counter() - self.t0
        plan_time = planning_time() - self.plans0
        return total - plan_time, plan_time

    def say(self, text: str) -> None:
        """A progress line (the locator)."""
        if self.listening():
            self.progress(text)

    def listening(self) -> bool:
        """Whether a progress line would reach anyone (a logger: at INFO now)."""
        if self._logger is not None:
            return self._logger.isEnabledFor(logging.INFO)
        return bool(self.progress)

    def level(self, i: int, shape, lengths, est: float) -> None:
        """The progress line of refinement level ``i`` (from 1): its grid over its period(s),
        the time so far and the estimate so far -- the same line for lines and surfaces."""
        if not self.listening():
            return
        grid = " x ".join(str(n) for n in _axes(shape))
        period = " x ".join(f"{L:.4g}" for L in _axes(lengths))
        so_far = f", estimate so far {est:.1e} (tol {self.tol:.0e})" if est < float("inf") else ""
        self.progress(f"{self.model} model, fft: level {i}: grid {grid} points over {period} h, "
                      f"{time.perf_counter() - self.t0:.1f} s{so_far}")


def _axes(v) -> tuple:
    """A shape or lengths as a tuple (a line's are one number)."""
    return tuple(v) if isinstance(v, (tuple, list)) else (v,)


def _shape_text(shape) -> str:
    """A grid's size in messages: "N = 4096" (a line), "512 x 256" (a surface)."""
    return " x ".join(str(n) for n in shape) if isinstance(shape, tuple) else f"N = {shape}"


def unresolved_edges(edge_scales, size: float, dx: float) -> float:
    """Bound of the error left by the viscoelastic film's Prony terms whose edge structure
    |V| tau_i spans fewer than VISCO_EDGE_CELLS cells of ``dx`` (along the sliding): the sum of
    their E_i/E_inf |V| tau_i / ``size`` (the contact's half-width or radius)."""
    return sum(weight * width / size for width, weight in edge_scales
               if width < VISCO_EDGE_CELLS * dx)


class Level:
    """One refinement level: its grid, its solve ``sol`` (the grid's), the measures ``q`` the
    estimate compares (a line's: averaged over the grid and the grid shifted by half a cell),
    the residual it was accepted with, and what the dimension keeps besides (keywords)."""

    def __init__(self, grid, sol, q, residual, **extra):
        self.grid, self.sol, self.q, self.residual = grid, sol, q, residual
        self.__dict__.update(extra)


class Levels:
    """The refinement so far: ``history`` [(shape, q)] of every level, the estimates ``ests``
    (from the second level on), the finest level ``cur`` and its estimate ``est`` = ``disc``
    (discretisation, with the unresolved edges) + ``image_error``; ``parts`` and
    ``extent_est`` as the dimension's ``difference`` records them; ``domain_diff`` the
    images' measured effect (lines beyond the measured amplitude)."""

    def __init__(self):
        self.history, self.ests, self.cur = [], [], None
        self.image_error = self.disc = self.est = self.extent_est = math.inf
        self.parts, self.domain_diff, self.last_step = {}, 0.0, None


def estimate(steps, lv: Levels, cur: Level, prev: Level, lengths) -> float:
    """The error estimate of level ``cur`` (recorded in ``lv``): the dimension's
    discretisation error from the levels' difference, plus the viscoelastic film's unresolved
    edges (relative to the contact's size; lines fit the trailing edges' inner layer of
    the lighter Prony terms: the steps' ``unfitted_edge_scales``), plus the periodic images'
    (0 where the period's margin keeps them ~tol/100 and out of the estimate: surfaces)."""
    prob = steps.prob
    lv.image_error = steps.image_error(cur.q, lengths)
    disc = steps.difference(lv, cur, prev)
    if prob.visco:  # (the terms the edge fits do not carry)
        disc += unresolved_edges(steps.unfitted_edge_scales(), steps.size(cur.q),
                                 cur.grid.spacing[0])
    lv.disc = disc
    lv.est = disc + lv.image_error
    lv.ests.append(lv.est)
    return lv.est


def check_stagnation(steps, ests, shape, est, levels: int) -> None:
    """First order divides the estimate by ~2 per doubling: three doublings that take off less
    than 10 % mean the levels have stopped converging (seen on lines at |mu| >= 30: the
    estimate settles at 1.9e-3 or 4.5e-2, the grid and the shifted grid holding different
    solutions)."""
    k, tol = STAGNATION_DOUBLINGS, steps.prob.tol
    if len(ests) > k and ests[-1] > 0.9 * ests[-k - 1]:
        coarse = tuple(n >> k for n in shape) if isinstance(shape, tuple) else shape >> k
        raise ConvergenceError(
            f"grid refinement stagnates: error estimate {ests[-k - 1]:.1e} at "
            f"{_shape_text(coarse)} and still {est:.1e} at {_shape_text(shape)} > tol "
            f"{tol:.1e}; the scene is beyond the FFT method's range at this tol "
            f"({steps.ALTERNATIVE})", residuals=ests, iterations=levels)


def refine(steps, shapes, lengths, center, located=None) -> Levels:
    """3. the grid levels ``shapes`` on the period(s) ``lengths`` centred on ``center``, each
    started from the previous one (nested; the first from ``located``), until the error
    estimate is below tol (a user-fixed grid: its two levels N/2 and N).  Returns the
    ``Levels``; ConvergenceError when the finest allowed level is not below tol or the
    estimate stagnates."""
    prob, tol = steps.prob, steps.prob.tol
    lv = Levels()
    prev = None
    est = math.inf
    for i, shape in enumerate(shapes):
        prob.level(i + 1, shape, lengths, est)
        g = steps.grid(shape, lengths, center)
        try:
            cur = steps.solve_level(g, steps.start(g, located, prev), prev is None)
        except ConvergenceError:
            # the coarsest automatic level may not settle (strong friction: mu = 30 at
            # a = 29 h on 64 points); start the comparison one level finer instead
            if (steps.RETRY_FINER and prev is None and not steps.grid_points
                    and i + 2 < len(shapes) and i < 2):
                continue
            raise
        lv.cur = cur
        lv.history.append((shape, cur.q))
        if prev is not None:
            est = estimate(steps, lv, cur, prev, lengths)
            if steps.grid_points or (est <= tol and i + 1 >= steps.MIN_LEVELS):
                return lv
            check_stagnation(steps, lv.ests, shape, est, len(lv.history))
        prev = cur
    if est <= tol:  # (below tol, but too few levels for the estimate to count)
        raise ConvergenceError(
            f"grid refinement reached the largest grid, {_shape_text(shapes[-1])} points, "
            f"after {len(lv.history)} levels, fewer than the {steps.MIN_LEVELS} its error "
            f"estimate needs; raise tol or set grid_points", residuals=lv.ests or [est],
            iterations=len(lv.history))
    raise ConvergenceError(
        f"grid refinement reached {_shape_text(shapes[-1])} points with error estimate "
        f"{est:.1e} > tol {tol:.1e}; raise tol or set grid_points", residuals=lv.ests or [est],
        iterations=len(lv.history))


def finish(steps, lv: Levels):
    """The result of the final level: the surface shear (Amontons mu p, or the law's), the
    base stresses and other output fields (``steps.fields``, counted), the timings and the
    info every solve reports (the levels, the final level's residuals and work, whether the
    estimate is within tol, the decay margin, the friction law's iterations, the viscoelastic
    tail); the dimension's result."""
    prob, scene = steps.prob, steps.prob.scene
    sol = lv.cur.sol
    p = sol.pressure
    law_shear = prob.surface_shear(sol, p)
    fields = steps.fields(sol, p, scene.mu * p if law_shear is None else law_shear)
    wall, plan_time = prob.times()
    info = {
        "levels": [steps.level_row(shape, q) for shape, q in lv.history],
        "residuals": sol.residuals,
        "domain_margin": prob.margin,
        "final_level_active_set_iterations": sol.iterations,
        "final_level_krylov_iterations": sol.krylov_iterations,
        # False only on a user-fixed grid (an automatic one refines to tol or raises)
        "tolerance_met": bool(lv.est <= prob.tol),
    }
    if not prob.friction.is_amontons:
        info["friction_law_iterations"] = prob.law_iterations
    if prob.visco:
        info["tail_length"] = prob.film.tail_length
    return steps.result(lv, fields, info, wall, plan_time, law_shear)


def run(steps):
    """The resolution control of the FFT method, lines and surfaces (module docstring):
    ``steps`` holds the ``Problem`` (``steps.prob``) and the dimension's steps."""
    if steps.prob.P == 0.0:
        return steps.unloaded()
    done = steps.shortcut()
    if done is not None:
        return done
    return finish(steps, steps.refine(steps.period(steps.locate())))
