"""The FFT method's one driver, lines (``solvers.fft``) and surfaces (``solvers.fft3d``).

``run(steps)`` is the resolution control of both: an unloaded scene, else (a shortcut: the
surfaces' open box for small contacts) locate the contact on a coarse generous grid, set the
period(s) from it and the decay margin, refine the grid by doublings from a nested start until
the error estimate is below tol, and make the result (base stresses, info, counters).  What
differs by dimension are the steps of ``steps`` (``_LineSolve``, ``_SurfaceSolve``): small
methods ``unloaded``, ``shortcut``, ``locate``, ``period``, ``refine``, ``result``.

``Problem`` is what both share: the setup (the scene's film in the core's units, the contact
friction of the model, the decay margin, the accepted residual, the friction law and the
interface), the one dispatch of a contact solve (Amontons, or a friction law / compliant
interface: an outer fixed point), the work counters summed over every solve, the final surface
shear, the timings and the progress line of each level.
"""
from __future__ import annotations

import time

from ..numerics.contact import solve_contact
from ..numerics.fft import planning_time
from ..numerics.friction import solve_contact_law
from ..physics.friction import ShearLaw

__all__ = ["Problem", "run", "LOCATOR_RTOL", "LOCATOR_ACCEPT", "LOCATOR_SEARCH_RTOL"]

LOCATOR_RTOL = 1e-6
LOCATOR_ACCEPT = 1e-3
LOCATOR_SEARCH_RTOL = 1e-2  # and while its active set is searched (measured: fewer GMRES
# iterations for the same located contact)


class Problem:
    """One FFT solve's setup and bookkeeping (lines and surfaces).

    scene, model, tol : the solve's.  adaptive : the resolution is chosen from tol (not fixed
    by ``grid_points``): the locator's inner solves are then looser.  progress : callable(str)
    told about each level (None: silent).

    Attributes: film (``scene.core_film()``: thickness 1), visco (its symbols depend on the
    sliding), P, mu_contact (mu for the exact model, 0 for Goodman's), margin (the decay margin
    for tol), accept (the residual accepted from each contact solve), friction, law (the law in
    the core's units), with_law, c (the interface compliance), rtol (the inner solves'; set by
    the driver), counters (FFT pairs, outer and inner iterations), law_iterations.
    """

    def __init__(self, scene, model: str, tol: float, adaptive: bool = True, progress=None):
        self.t0 = time.perf_counter()
        self.plans0 = planning_time()
        self.scene, self.model, self.tol = scene, model, tol
        self.adaptive, self.progress = adaptive, progress
        self.P = scene.P
        self.mu_contact = scene.mu if model == "exact" else 0.0
        self.film = scene.core_film()  # lengths in h: thickness 1 (the scene's film kind)
        self.visco = self.film.moving  # a film whose symbols depend on the sliding
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

    def solve_contact(self, grid, indenters, film, p_init=None, locator=False):
        """One contact solve on ``grid`` (Amontons, or the law / interface's fixed point; a
        proportional law stays Amontons bit for bit)."""
        rt, acc, search = self.tolerances(locator)
        if not self.with_law and self.c == 0.0:
            return solve_contact(grid, self.mu_contact, indenters, film=film, p_init=p_init,
                                 rtol=rt, accept=acc, search_rtol=search)
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
        if self.progress:
            self.progress(text)

    def level(self, i: int, shape, lengths, est: float) -> None:
        """The progress line of refinement level ``i`` (from 1): its grid over its period(s),
        the time so far and the estimate so far -- the same line for lines and surfaces."""
        if not self.progress:
            return
        grid = " x ".join(str(n) for n in shape)
        period = " x ".join(f"{L:.4g}" for L in lengths)
        so_far = f", estimate so far {est:.1e} (tol {self.tol:.0e})" if est < float("inf") else ""
        self.progress(f"{self.model} model, fft: level {i}: grid {grid} points over {period} h, "
                      f"{time.perf_counter() - self.t0:.1f} s{so_far}")


def run(steps):
    """The resolution control of the FFT method, lines and surfaces (module docstring):
    ``steps`` holds the ``Problem`` (``steps.prob``) and the dimension's steps."""
    if steps.prob.P == 0.0:
        return steps.unloaded()
    done = steps.shortcut()
    if done is not None:
        return done
    return steps.result(steps.refine(steps.period(steps.locate())))
