"""Contact with a friction law q(p) (``physics.friction``): an outer fixed point around the
contact solver (issue 14).

The surface sinks by w = H0 p + H1 q, H0 the film's normal compliance and H1 its sinking per
unit shear (``Film.surface_compliance(mu=0)``, ``Film.shear_compliance``).  With q = q(p) a
nonlinear local law, write q = m p + s with m a constant (the law's slope dq/dp at the mean
contact pressure of the first guess) and s = q(p) - m p the rest.  Each outer iteration solves
the ordinary complementarity problem (``contact.solve_complementarity``) for the operator
H0 + m H1 (the Amontons operator of friction m, cached) with the rest lagged into the height:

    gap = [f + H1 s_j] - d + (H0 + m H1) p_{j+1},     s_{j+1} = q(p_{j+1}) - m p_{j+1},

Anderson-accelerated (a secant method on s; depth 5).  It stops when two successive pressures
agree to ``law_tol`` (relative, max-norm) and the shear applied is the law's to ``law_tol``
except on the cells next to the contact boundary, where a law with q(0+) != 0 (linear with
tau_0 > 0) has no fixed point on a grid (the edge node flips in and out of contact): there the
applied shear settles between the law's values inside and outside, a sub-cell edge.  The shear
returned is the one applied (consistent with the pressure and the base stresses: equilibrium
holds exactly).  ``ConvergenceError`` after ``max_law_iterations`` (steep laws on compressible
films, e.g. n = 0.9 at nu = 0.3, can fail: the shear's step-like rise at the edge then meets a
logarithmically singular sinking).  A law with q = mu p exactly (Amontons, power with n = 0, linear with
tau_0 = 0) is the plain Amontons solve: bit-identical, no outer iteration.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..errors import ConvergenceError
from ..physics.film import Film
from ..physics.friction import ShearLaw
from .contact import compliance_operator, solve_complementarity, solve_contact
from .grid import Grid
from .operators import FourierOperator

__all__ = ["solve_contact_law"]


def _setup(grid: Grid, indenters):
    """(f, owner, first guess) as ``contact.solve_contact`` builds them."""
    dist = np.stack([np.broadcast_to(ind.distance(grid), grid.shape) for ind in indenters])
    owner = np.argmin(dist, axis=0)
    f = np.zeros(grid.shape)
    guess = np.zeros(grid.shape)
    for m, ind in enumerate(indenters):
        mine = owner == m
        f = np.where(mine, ind.height(grid), f)
        if ind.load > 0:
            guess = np.where(mine, ind.initial_pressure(grid), guess)
    return f, owner, guess


def _boundary(active: np.ndarray) -> np.ndarray:
    """Nodes within one cell (along any axis, periodically) of the contact set's boundary."""
    edge = np.zeros(active.shape, dtype=bool)
    for axis in range(active.ndim):
        for shift in (1, -1):
            edge |= active != np.roll(active, shift, axis=axis)
    return edge


@lru_cache(maxsize=16)
def _with_interface(shape: tuple, lengths: tuple, mu: float, film: Film, c: float):
    """The film's compliance for friction mu plus the interface's c (``op + c``), cached."""
    return compliance_operator(shape, lengths, mu, film) + c


def solve_contact_law(grid: Grid, law: ShearLaw, indenters, *, film: Film | None = None,
                      interface: float = 0.0, p_init=None, accept: float | None = None,
                      rtol: float = 1e-10, law_tol: float = 1e-8, max_law_iterations: int = 100,
                      depth: int = 5, search_rtol: float | None = None):
    """Contact on ``grid`` under the friction law ``law`` (dimensionless, sliding toward +x).

    interface : c >= 0, a linear interface compliance (dimensionless: displacement h^2/2R per
        stress unit): the interface closes by c p, so the gap is f - d + w + c p and the
        contact operator is H + c (``FourierOperator.__add__``).  c = 0 is the rigid interface
        (the plain solve, bit for bit).
    search_rtol : as ``solve_complementarity``'s, for the first contact solve (a proportional
        law: the only one).

    Returns (solution, q, info): the ``ContactSolution`` (its ``sinking`` is the film's, shear
    part included, without the interface's closure c p; ``solution.shear`` is q too), the
    surface shear field q and {"law_iterations", "law_change"}.
    """
    film = film or Film()
    c = float(interface)
    if law.proportional and c == 0.0:
        sol = solve_contact(grid, law.mu, indenters, film=film, p_init=p_init, accept=accept,
                            rtol=rtol, search_rtol=search_rtol)
        sol.shear = law.mu * sol.pressure
        return sol, sol.shear, {"law_iterations": 0, "law_change": 0.0}
    f, owner, guess = _setup(grid, indenters)
    p = guess if p_init is None else np.asarray(p_init, dtype=float)
    loads = [ind.load for ind in indenters]
    if law.proportional:
        op = _with_interface(grid.shape, grid.lengths, float(law.mu), film, c)
        sol = solve_complementarity(op, f, owner, loads, p_init=p, rtol=rtol, accept=accept,
                                    grid=grid, search_rtol=search_rtol)
        sol.sinking = sol.sinking - c * sol.pressure
        sol.shear = law.mu * sol.pressure
        return sol, sol.shear, {"law_iterations": 0, "law_change": 0.0}
    inside = p > 0
    m = law.slope(float(np.mean(p[inside])) if inside.any() else 1.0)
    op = (compliance_operator(grid.shape, grid.lengths, float(m), film) if c == 0.0 else
          _with_interface(grid.shape, grid.lengths, float(m), film, c))
    H1 = FourierOperator(grid, film.shear_compliance_symbol((1.0, 0.0)[:grid.ndim]))
    s = law.shear(p) - m * p
    history_s, history_g = [], []  # Anderson: iterates and their residuals g = T(s) - s
    change = np.inf
    fft_pairs = krylov = outer = 0
    for it in range(1, max_law_iterations + 1):  # noqa: B007 (reported after the loop)
        sol = solve_complementarity(op, f + H1.apply(s), owner, loads, p_init=p, rtol=rtol,
                                    accept=accept, grid=grid)
        fft_pairs += sol.fft_pairs + 1
        krylov += sol.krylov_iterations
        outer += sol.iterations
        p_new = sol.pressure
        q = law.shear(p_new)
        s_new = q - m * p_new
        scale_p = max(np.max(np.abs(p_new)), 1e-300)
        scale_q = max(np.max(np.abs(q)), 1e-300)
        # the shear applied (s) and the law's (s_new) must agree away from the contact's
        # boundary cells; on them the applied shear may settle between the law's values
        # inside and outside (a law with q(0+) != 0 has no fixed point on a grid otherwise:
        # the edge node flips in and out; the settled fraction is the sub-cell edge)
        edge = _boundary(sol.active)
        change = max(np.max(np.abs(p_new - p)) / scale_p,
                     np.max(np.abs(np.where(edge, 0.0, s_new - s))) / scale_q)
        p = p_new
        if change <= law_tol:
            q = s + m * p  # the shear applied in the last solve
            break
        # Anderson mixing on s (type II, least squares over the last ``depth`` residuals)
        g = (s_new - s).ravel()
        history_s.append(s.ravel().copy())
        history_g.append(g)
        if len(history_s) > depth + 1:
            history_s.pop(0)
            history_g.pop(0)
        if len(history_g) > 1:
            dG = np.stack([history_g[i + 1] - history_g[i] for i in range(len(history_g) - 1)], 1)
            dS = np.stack([history_s[i + 1] - history_s[i] for i in range(len(history_s) - 1)], 1)
            gamma = np.linalg.lstsq(dG, g, rcond=None)[0]
            s = (s.ravel() + g - (dS + dG) @ gamma).reshape(s.shape)
        else:
            s = s_new
    else:
        raise ConvergenceError(
            f"friction-law iteration did not settle in {max_law_iterations} iterations "
            f"(relative change {change:.1e} > {law_tol:.1e})", residuals=[change],
            iterations=max_law_iterations)
    # the final state: the shear of the final pressure, and the sinking it causes
    sinking = op.apply(p) + H1.apply(s) - c * p
    sol.sinking = sinking
    sol.fft_pairs = fft_pairs + 2
    sol.krylov_iterations = krylov
    sol.iterations = outer
    sol.shear = q
    return sol, q, {"law_iterations": it, "law_change": float(change)}
