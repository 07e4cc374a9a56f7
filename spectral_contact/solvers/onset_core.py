"""The loading and the grid refinement that the onset of sliding runs for lines
(``solvers.onset``) and surfaces (``solvers.onset3d``) alike: one partial-slip driver
(``numerics.partial_slip``), the dimension in a small ``Dimension`` object (the heights, the
first contact, the tangential load's vector, the next step's predicted sets, the measures).

The loading: the normal load first (``loading="frictional"``: in ``loading_steps`` equal steps
with the incremental Coulomb law acting, from the frictionless contact at the first load, all
stuck; a node coming into contact within a step is held from where it touched, predicted from
the last two steps, ``numerics.partial_slip.entry_motion``; ``"frictionless"``: that contact
at the full load, q = 0), then the tangential loads Q/(mu P) of ``path``, each step from the
previous state (the slip history kept), its first sets predicted from the last two steps where
the path goes on in one direction.

The refinement: the whole loading on N/2 and N points (per axis), the per-step estimate 1.5 x
their measures' difference plus the periodic images' bound, doubled while it exceeds tol (at
most ``max_doublings`` times) unless the grid is fixed.
"""
from __future__ import annotations

import numpy as np

from ..numerics.partial_slip import PartialSlipOperator, entry_motion, solve_slip_step

__all__ = ["LOADING_STEPS", "Dimension", "LoadingRun", "refine", "differences", "load_step_estimates",
           "with_load_steps", "step_record", "OnsetBase"]

LEVEL_MARGIN = 1.5  # as solvers.fft's estimate: 1.5 x the difference of the last two levels
LOADING_STEPS = 20
"""Default number of frictional normal loading steps (lines and surfaces).  The loading's
error is about first order in the step (the paper's line, 2048 points: the indentation's
error 3.5e-3 at 10 steps, 1.3e-3 at 20) and its estimate 3 x the difference to half the
steps: with 10 steps the default runs were flagged (the paper's line 1.7e-2, the 1 N sphere
9.3e-3 + the grid's 1.7e-3 against their tol 1e-2); with 20 they meet tol (7.9e-3 and
9.4e-3; studies/README.md, onset)."""


class Dimension:
    """What the loading needs of a line or a surface (subclassed by each solver):
    ``heights(grid)``, ``first_contact(grid, film, P1, accept)`` -> (active, pressure, d,
    fft_pairs), ``unloaded(n)`` and ``state(...)`` (the state type), ``tangential(Q)`` (the
    load's vector), ``predict(s0, s1, f, mu)`` (first sets of the next step, or None),
    ``measure(grid, state, f, mu)`` (a dict), ``rtol(accept)`` (the inner tolerance)."""

    predict_loading = True  # predict the normal loading's steps too
    predict_reversals = False  # predict across a reversal of the path's direction

    def rtol(self, accept: float) -> float:
        """The inner (GMRES) tolerance of the accepted solves: 1e-2 of the accepted residual
        (the loads are held exactly by ``solve_slip_step``'s balance; it was 1e-10, for
        equilibrium to 1e-8 through GMRES: 12 % more FFT pairs on the paper's line, the
        measures the same to ~1e-5 of tol).  Surfaces too since the slip direction's check is
        weighed by p (``numerics.partial_slip``): with the unweighted one, 1e-2 of it left the
        direction at a contact edge node of a sphere (p ~ 1e-3 p_max) off by more than the
        check's 1e-3, and surfaces kept 1e-4 of it (23 % more FFT pairs on the 1 N sphere's
        256^2 level)."""
        return max(1e-10, 1e-2 * accept)


class LoadingRun:
    """The whole loading on one grid: ``loaded`` (after the normal load), ``states`` (one per
    tangential step), ``measures`` (of both), ``counters`` (FFT pairs, iterations)."""

    def __init__(self, dim: Dimension, grid, film, P, mu, path, loading, loading_steps, accept,
                 progress=None):
        self.grid = grid
        op = PartialSlipOperator(grid, film)
        f = dim.heights(grid)
        amu = abs(mu)
        rtol = dim.rtol(accept)
        self.counters = {"fft_pairs": 0, "krylov_iterations": 0, "iterations": 0}
        P1 = P / loading_steps if loading == "frictional" else P
        active, pressure, d0, pairs = dim.first_contact(grid, film, P1, accept)
        self.counters["fft_pairs"] += pairs
        n = grid.size
        if loading == "frictional":
            state = dim.unloaded(n)
            guess = dim.unloaded(n)
            guess.contact, guess.stick = active.copy(), active.copy()
            guess.p, guess.d = pressure.copy(), d0
            before = None
            for k in range(1, loading_steps + 1):
                entry = None
                if k > 1:
                    guess = dim.predict(before, state, f, amu) \
                        if k > 2 and dim.predict_loading else None
                    entry = entry_motion(f, before, state) if k > 2 else None
                new = solve_slip_step(op, f, state, P * k / loading_steps, dim.tangential(0.0),
                                      amu, guess=guess, accept=accept, rtol=rtol, entry=entry)
                before, state = state, self._count(new)
        else:
            q0 = np.zeros_like(dim.unloaded(n).q)
            w, u = op.apply(pressure, q0)
            self.counters["fft_pairs"] += op.m
            state = dim.unloaded(n)
            state.p, state.w, state.u, state.d = pressure.copy(), w, u, d0
            state.contact, state.stick, state.P = active.copy(), active.copy(), P
        self.loaded = state
        self.states = []
        sgn = 1.0 if mu > 0 else -1.0
        for k, r in enumerate(path, start=1):
            guess = None
            if k > 2 and (dim.predict_reversals
                          or (path[k - 1] - path[k - 2]) * (path[k - 2] - path[k - 3]) > 0):
                guess = dim.predict(self.states[-2], state, f, amu)
            state = self._count(solve_slip_step(op, f, state, P, dim.tangential(sgn * amu * P * r),
                                                amu, guess=guess, accept=accept, rtol=rtol))
            self.states.append(state)
            if progress:
                progress(k, len(path), grid.shape[0])
        self.measures = [dim.measure(grid, s, f, amu) for s in [self.loaded] + self.states]

    def _count(self, s):
        self.counters["fft_pairs"] += s.fft_pairs
        self.counters["krylov_iterations"] += s.krylov_iterations
        self.counters["iterations"] += s.iterations
        return s


def differences(fine, coarse, size: str, centre: str, stick):
    """Per step: the largest relative difference of the two runs' contact size (measure
    ``size``: a line's half-width, a surface's radius), centre (``centre``, over the size),
    indentation, peak pressure and tangential displacement (over its largest value); and the
    stick zone's ``stick(mf, mc, size)`` (0 once the stick zone is a single node)."""
    main, sticks = [], []
    dscale = max(max(abs(m["delta"]) for m in fine.measures), 1e-300)
    for mf, mc in zip(fine.measures, coarse.measures):
        a = max(mf[size], 1e-300)
        main.append(max(abs(mf[size] - mc[size]) / a, abs(mf[centre] - mc[centre]) / a,
                        abs(mf["d"] - mc["d"]) / max(abs(mf["d"]), 1e-300),
                        abs(mf["pmax"] - mc["pmax"]) / max(mf["pmax"], 1e-300),
                        abs(mf["delta"] - mc["delta"]) / dscale))
        sticks.append(stick(mf, mc, a) if mf["stick_nodes"] > 1 and mc["stick_nodes"] > 1
                      else 0.0)
    return main, sticks


def refine(run, n: int, tol: float, image: float, differences, *, fixed: bool,
           max_doublings: int, max_points: int):
    """The loading on n/2 and n points (``run(npts)``), doubled while the largest per-step
    estimate (LEVEL_MARGIN x ``differences(fine, coarse)``'s main part + ``image``) exceeds
    tol (not when ``fixed``).  Returns (fine, estimates, stick estimates, met, n, doublings,
    counters of both levels, coarse)."""
    coarse, fine = run(n // 2), run(n)
    doublings = 0
    while True:
        diff, sdiff = differences(fine, coarse)
        est = [LEVEL_MARGIN * e + image for e in diff]
        if fixed or max(est) <= tol or doublings >= max_doublings or 2 * n > max_points:
            break
        coarse, fine, n = fine, run(2 * n), 2 * n
        doublings += 1
    counters = {k: fine.counters[k] + coarse.counters[k] for k in fine.counters}
    return (fine, est, [LEVEL_MARGIN * e for e in sdiff], max(est) <= tol, n, doublings,
            counters, coarse)


def with_load_steps(fine, coarse, run, path, loading, loading_steps, differences, est,
                    stick_est, counters):
    """The per-step estimates with the load steps' share (``load_step_estimates``) added:
    (estimates, stick estimates, the load steps' share, counters with the extra run's)."""
    step, stick_step, extra = load_step_estimates(coarse, run, path, loading, loading_steps,
                                                  differences)
    counters = {k: counters[k] + extra[k] for k in counters}
    return ([e + s for e, s in zip(est, step)], [e + s for e, s in zip(stick_est, stick_step)],
            step, counters)


class _Measures:
    def __init__(self, measures):
        self.measures = measures


def load_step_estimates(coarse, run, path, loading: str, loading_steps: int, differences):
    """The load steps' share of each step's error: the incremental solution depends on the
    step size (first order: the slip of a step is taken at its end).  The loading is solved
    again on the coarse grid with half the steps (every second Q of ``path``, half the
    frictional loading steps; with an odd count, twice the steps instead: the midpoints) and
    compared with ``coarse`` at the common steps.  The stick edges jump between nodes and the
    history's errors add up, so the error falls more slowly than first order in the step:
    measured (studies/onset_steps) 1.5 x the difference to N/2 fell short at 0.75-0.95 of the
    true error in 6 of 42 steps (besides gross sliding); for an order p >= 0.58 the error of N
    steps is at most 2 x the difference to N/2 (3 x that to 2N), used here times LEVEL_MARGIN.
    A step between two compared ones takes the larger of theirs, a step at gross sliding at
    least its predecessor's.  Returns (main, stick) lists
    as ``differences``'s, one per step (0 = loaded), and the extra run's counters."""
    nd = coarse.grid.shape[0]
    even_loading = loading != "frictional" or loading_steps % 2 == 0
    if len(path) % 2 == 0 and len(path) > 1 and even_loading:
        ls = loading_steps // 2 if loading == "frictional" else loading_steps
        alt = run(nd, list(path[1::2]), ls)
        full = _Measures(coarse.measures[::2])
        main, stick = differences(full, alt)
        factor, stride = 2.0 * LEVEL_MARGIN, 2
    else:
        prev = [0.0] + list(path[:-1])
        doubled = [v for a, b in zip(prev, path) for v in (0.5 * (a + b), b)]
        alt = run(nd, doubled, 2 * loading_steps if loading == "frictional" else loading_steps)
        main, stick = differences(coarse, _Measures(alt.measures[::2]))
        factor, stride = 3.0 * LEVEL_MARGIN, 1
    out = []
    for values in (main, stick):
        e = [factor * v for v in values]
        if stride == 2:  # every second step compared: the others take their neighbours' max
            full_e = [0.0] * (len(path) + 1)
            for j, v in enumerate(e):
                full_e[2 * j] = v
            for k in range(1, len(path) + 1, 2):
                full_e[k] = max(full_e[k - 1], full_e[k + 1] if k + 1 <= len(path) else 0.0)
            e = full_e
        out.append(e)
    # gross sliding (|Q| = |mu| P): its state is the limit of the partial slip states (delta
    # set by the last node to stick, the one the step moved furthest along Q, from the state
    # of the step before), so it carries that step's error, which
    # the two runs can share by chance (the 1 N sphere's: 2e-6 on 128^2, against 1.9e-3 from a
    # 4 x finer step on 256^2): at least its predecessor's
    main = out[0]
    for k in range(1, len(path) + 1):
        if abs(path[k - 1]) >= 1.0 - 1e-12:
            main[k] = max(main[k], main[k - 1])
    return out[0], out[1], alt.counters


def step_record(result, k: int, keys: dict) -> dict:
    """The JSON object of step k (SI) of a line's or a surface's onset ``result``: Q/(mu P),
    the dimension's ``keys`` (already in SI, inserted after it), then the indentation, peak
    pressure, tangential displacement and the two estimates."""
    sc, m = result.scene, result.measures[k]
    dU = sc.displacement_unit
    return {"Q_over_muP": float(result.Q_over_muP[k]), **keys,
            "indentation_m": m["d"] * dU,
            "max_pressure_Pa": m["pmax"] * sc.stress_unit,
            "tangential_displacement_m": m["delta"] * dU,
            "error_estimate": result.error_estimates[k],
            "stick_error_estimate": result.stick_error_estimates[k],
            "load_step_error_estimate": result.load_step_estimates[k]}


class OnsetBase:
    """What a line's and a surface's onset results share: the scene, the path's length, the
    loading, tol, the grid, the states (0 = after the normal load) and their measures, the
    per-step estimates (``error_estimates``, ``stick_error_estimates``,
    ``load_step_estimates``), the steady solution, ``tolerance_met``, the wall time, the
    counters, the film and ``Q_over_muP`` (0, then the path)."""

    def __init__(self, scene, path, loading, loading_steps, tol, run, estimates,
                 stick_estimates, steady, tolerance_met, wall_time_s, counters, film,
                 load_step_estimates=None):
        self.scene = scene
        self.n_steps = len(path)
        self.cycle = len(path) > 1 and min(path) < 0.0
        self.loading, self.loading_steps, self.tol = loading, loading_steps, tol
        self.grid = run.grid
        self.states = [run.loaded] + run.states
        self.measures = run.measures
        self.error_estimates = [float(e) for e in estimates]
        self.stick_error_estimates = [float(e) for e in stick_estimates]
        self.load_step_estimates = [float(e) for e in (load_step_estimates
                                                       or [0.0] * len(estimates))]
        self.steady = steady
        self.tolerance_met = bool(tolerance_met)
        self.wall_time_s = wall_time_s
        self.counters = counters
        self.film = film
        self.Q_over_muP = np.array([0.0] + list(path))
