"""The onset of sliding: partial slip under a growing tangential load (Cattaneo-Mindlin on the
film), for a line indenter (plane strain).

``solve_onset(scene, steps)``: the normal load P is applied first, then the tangential load Q
is raised from 0 to mu P in ``steps`` equal steps (Q/(mu P) = 1/N, ..., 1), quasi-static and
incremental: each step starts from the previous one's state (Coulomb's law in incremental form,
``numerics.partial_slip``), so the slip history is kept.  The last step, Q = mu P, is gross
sliding: the steady state that ``solve`` computes (q = mu p everywhere).

Loading.  The normal load is applied with friction acting (``loading="frictional"``, the
default, as in reality): in ``loading_steps`` equal steps from P/loading_steps to P, with the
incremental Coulomb law of every step (a node coming into contact slips along its motion
relative to the indenter, and sticks from the step where that slip stops).  On an incompressible
half-space this changes nothing (normal and tangential decouple); on the bonded film a pressure
moves the surface tangentially (the F1 coupling), so the loading leaves a self-equilibrated
shear (odd in x, Int q = 0) in the contact: measured up to 0.17 |mu| p_max on the paper's
scene with 10 loading steps (a saw-tooth, one tooth per loading step near the edges, whose
peak falls slowly with the step: 0.19 / 0.14 / 0.13 for 5 / 20 / 40 steps; studies/README.md,
onset), and 2.6 % of p_max at a/h = 0.05, mu = 0.5.  ``loading="frictionless"`` applies P without friction
(q = 0 after the loading: a lubricated approach), the classical Cattaneo-Mindlin start.

Signs (the package's): mu > 0 pulls the indenter toward +x; the tangential load Q and the
surface shear q = sigma_xz(h) then drag the film toward +x; the stick zone is where the slip
increment vanishes.  Positions are from the indenter's apex (the tangential displacement of the
indenter, a displacement ~h^2/2R, is not a geometric shift: small strains, as in ``solve``).

Resolution.  The grid is that of ``solve`` for the same scene and ``tol`` (its spacing), on a
period holding both the centred normal contact and the shifted sliding one plus the kernels'
decay margin.  The whole loading is run on N/2 and N points (nested); the per-step error
estimate is 1.5 times the relative difference of the two runs' a, centre, indentation, peak
pressure, stick-zone edges (over a) and tangential displacement (over its final value), plus
the periodic images' bound of ``solve``; the grid is doubled until every step's estimate is
below ``tol`` (or, with ``grid_points`` fixed, ``tolerance_met`` is False).
"""
from __future__ import annotations

import math
import numbers
import time

import numpy as np

from ..errors import ConvergenceError, InputError, named
from ..numerics.contact import solve_contact
from ..numerics.edges import fit_edges, peak
from ..numerics.fft import get_rfft
from ..numerics.grid import Grid, pow2_at_least
from ..numerics.partial_slip import SlipState
from ..physics.film import Film
from ..physics.indenters import Cylinder
from ..physics.scene import Scene, Scene3D, check_tol
from .base import ONSET_MU_MIN, check_grid_points, check_onset_mu  # noqa: F401 (re-exported)
from .fft import MAX_POINTS, MIN_POINTS, solve_fft
from .onset_core import (
    LOADING_STEPS,
    Dimension,
    LoadingRun,
    OnsetBase,
    differences,
    refine,
    step_record,
    with_load_steps,
)

__all__ = ["onset", "solve_onset", "OnsetResult", "STEP_KEYS", "PROFILE_COLUMNS", "MAX_STEPS",
           "LOADINGS", "DEFAULT_TOL", "LOADING_STEPS"]

MAX_STEPS = 10000
DEFAULT_TOL = 1e-2
"""Default tol of ``onset`` for lines: that of surfaces (``onset3d.DEFAULT_TOL_3D``), about what
a MEMS measurement resolves.  The load steps' error does not shrink with the grid: on the
paper's scene at the default steps (20 tangential, ``LOADING_STEPS`` loading) its estimate is
~7e-3 (the true error in the indentation 1.3e-3 from the loading alone), so a tol of 1e-3, the
default before, was flagged at every default run; meeting it takes of the order of 100 loading
steps.  Finer tols are taken and flagged where the load steps' share exceeds them."""
LOADINGS = ("frictional", "frictionless")
_IMAGE_AMPLITUDE = 2.0  # solvers.fft's bound of the periodic images' relative effect
_MAX_DOUBLINGS = 3

STEP_KEYS = ("Q_over_muP", "tangential_load_N_per_m", "stick_x_min_m", "stick_x_max_m",
             "half_width_m", "contact_center_m", "indentation_m", "max_pressure_Pa",
             "tangential_displacement_m", "error_estimate", "stick_error_estimate")
PROFILE_COLUMNS = ("step", "Q_over_muP", "x_m", "pressure_Pa", "shear_Pa", "slip_m",
                   "base_sigma_zz_Pa", "base_sigma_xz_Pa")


def _check_int(name: str, value, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not lo <= value <= hi:
        raise InputError(f"{name} must be an integer in [{lo}, {hi}]; got {value!r:.40}")
    return int(value)


def check_onset_scene(scene) -> Scene:
    """The scenes ``solve_onset`` takes: a line indenter with Amontons friction mu != 0 on a
    rigid interface, loaded (InputError otherwise, naming the option)."""
    if not isinstance(scene, Scene):
        raise InputError("onset: spheres and other 3D indenters are not implemented yet "
                         "(--indenter line only)")
    if scene.custom():  # its solver builds the cylinder and the film itself
        raise InputError(f"onset: {scene.custom()} is not implemented yet (the built-in "
                         f"cylinder and film only)")
    if scene.friction_law != "amontons":
        raise InputError(f"--friction-law {scene.friction_law}: onset takes Amontons friction "
                         f"only (Coulomb's |q| <= mu p)")
    if scene.interface_compliance or scene.interface_law != "linear":
        raise InputError("--interface-compliance / --interface-law: onset takes a rigid "
                         "interface only")
    check_onset_mu(scene.mu)
    if scene.load <= 0.0:
        raise InputError("--load must be > 0 N/m for onset")
    return scene


def _check_amplitude(amplitude) -> float:
    amp = amplitude if isinstance(amplitude, (int, float)) and not isinstance(amplitude, bool) \
        else math.nan
    if not 0.0 < amp <= 1.0:
        raise InputError(f"{named('amplitude')} must be in (0, 1] (Q_max / (mu P)); got "
                         f"{amplitude!r:.40}")
    return float(amp)


def _stick_edges(x, dx, stick, margin):
    """(left, right) sub-grid edges of the stick zone's envelope: the margin mu p - |q| closes
    as a square root (Cattaneo: a Hertz-like difference), so margin^2 is extrapolated linearly
    from the last two stick nodes to its zero, within the next cell."""
    idx = np.flatnonzero(stick)
    if not idx.size:
        return math.nan, math.nan
    if idx.size == 1:
        return float(x[idx[0]]), float(x[idx[0]])
    out = []
    for node, inner, side in ((idx[0], idx[0] + 1, -1), (idx[-1], idx[-1] - 1, +1)):
        m1, m0 = max(float(margin[node]), 0.0), max(float(margin[inner]), 0.0)
        t = 0.5
        if m0 > m1 > 0.0:
            t = min(m1 * m1 / (m0 * m0 - m1 * m1), 1.0)
        out.append(float(x[node]) + side * t * dx)
    return out[0], out[1]


def _interval(mask):
    """(first, last) node of a mask that is one run (None otherwise)."""
    idx = np.flatnonzero(mask)
    if not idx.size or idx[-1] - idx[0] + 1 != idx.size:
        return None
    return int(idx[0]), int(idx[-1])


def _predict(s0: SlipState, s1: SlipState) -> SlipState | None:
    """First sets of the next step: the contact and stick intervals of the last two steps
    extrapolated linearly (node indices), new slip nodes slipping along the last step's slip,
    the last fields elsewhere.  Only the number of active-set iterations depends on it (None
    when a set is not one interval, or the extrapolation is empty)."""
    c0, c1, t0, t1 = (_interval(s0.contact), _interval(s1.contact), _interval(s0.stick),
                      _interval(s1.stick))
    if None in (c0, c1, t0, t1) or s1.stick.sum() < 3:
        return None
    n = s1.p.size
    lo, hi = 2 * c1[0] - c0[0], 2 * c1[1] - c0[1]
    slo, shi = max(2 * t1[0] - t0[0], lo), min(2 * t1[1] - t0[1], hi)
    if not (0 <= lo <= slo <= shi <= hi < n):
        return None
    contact = np.zeros(n, dtype=bool)
    contact[lo:hi + 1] = True
    stick = np.zeros(n, dtype=bool)
    stick[slo:shi + 1] = True
    direction = 1 if s1.Q - s0.Q >= 0 else -1
    sigma = np.where(contact & ~stick, np.where(s1.sigma != 0, s1.sigma, direction), 0)
    p = np.where(contact, np.maximum(s1.p, 1e-12), 0.0)
    return SlipState(p=p, q=np.where(contact, s1.q, 0.0), w=s1.w, u=s1.u, d=s1.d,
                     delta=2 * s1.delta - s0.delta, contact=contact, stick=stick,
                     sigma=sigma.astype(np.int8), P=s1.P, Q=s1.Q)


class _Line(Dimension):
    """The line's part of the loading (``onset_core``): the cylinder's heights x^2, Q a
    number, the predicted intervals of ``_predict`` (the loading's steps too, and across a
    reversal), the sub-grid edges of ``fit_edges`` and ``_stick_edges``."""

    predict_reversals = True
    unloaded = staticmethod(SlipState.unloaded)

    def heights(self, grid):
        return grid.x ** 2

    def first_contact(self, grid, film, P1, accept):
        s0 = solve_contact(grid, 0.0, [Cylinder(0.0, P1)], rtol=1e-10, accept=accept)
        return s0.active, s0.pressure, float(s0.indentations[0]), s0.fft_pairs

    def tangential(self, Q):
        return Q

    def predict(self, s0, s1, f, mu):
        return _predict(s0, s1)

    def measure(self, g, s, f, amu):
        gap = f - s.d + s.w
        edges = fit_edges(g.x, g.dx, gap, s.p, s.contact)
        left = min(e[0] for e in edges)
        right = max(e[1] for e in edges)
        pm, xm = peak(g.x, s.p)
        lo, hi = _stick_edges(g.x, g.dx, s.stick, amu * s.p - np.abs(s.q))
        return {"a": 0.5 * (right - left), "c": 0.5 * (right + left), "d": s.d, "pmax": pm,
                "xmax": xm, "stick_lo": lo, "stick_hi": hi, "delta": s.delta,
                "stick_nodes": int(s.stick.sum()), "edges": edges}


def _differences(fine, coarse):
    """Per step: ``onset_core.differences`` of the half-width and centre, and of the stick
    zone's edges (over a)."""
    return differences(fine, coarse, "a", "c", lambda mf, mc, a: max(
        abs(mf["stick_lo"] - mc["stick_lo"]) / a, abs(mf["stick_hi"] - mc["stick_hi"]) / a))


def q_path(steps: int, amplitude: float = 1.0, cycle: bool = False) -> list[float]:
    """The tangential loads Q/(mu P) of the steps: amplitude k/N, k = 1..N; with ``cycle``
    then down to -amplitude and back up to +amplitude in 2N steps each (Mindlin's loop)."""
    up = [amplitude * k / steps for k in range(1, steps + 1)]
    if not cycle:
        return up
    down = [amplitude * (1.0 - k / steps) for k in range(1, 2 * steps + 1)]
    return up + down + [-x for x in down]


def onset(scene: Scene | None = None, *, steps: int = 20, tol: float | None = None,
          loading: str = "frictional", loading_steps: int = LOADING_STEPS, grid_points: int | None = None,
          domain_length: float | None = None, amplitude: float = 1.0, cycle: bool = False,
          progress=None, **params) -> OnsetResult:
    """The onset of sliding of a line indenter (or, with ``indenter="sphere"`` or
    ``"paraboloid"`` and ``force`` [N], a 3D one) on the film: the normal load, then the
    tangential load Q raised from 0 to mu P in ``steps`` equal steps (quasi-static,
    incremental Coulomb friction; see ``solvers.onset``).

    scene : a ``Scene`` (line indenter, Amontons friction, rigid interface), or omitted and
            built from ``params`` (``load`` [N/m], ``mu``, ``young`` [Pa], ``radius`` [m],
            ``thickness`` [m], ``poisson``) over the paper's defaults.  mu != 0; its sign is
            the direction of Q (mu > 0: toward +x).
    steps : N, the number of tangential steps (Q/(mu P) = 1/N, ..., 1), 1 ... 10000.
    tol : relative accuracy target of every step's a, contact centre, indentation, peak
          pressure and tangential displacement (default ``DEFAULT_TOL`` = 1e-2 for lines,
          ``onset3d.DEFAULT_TOL_3D`` = 1e-2 for spheres and paraboloids).
    loading : "frictional" (default: the normal load applied in ``loading_steps`` steps,
          default ``LOADING_STEPS`` = 20, with Coulomb friction acting) or "frictionless"
          (lubricated approach: q = 0 at Q = 0).
    grid_points, domain_length [m] : fix the grid instead of choosing it from tol.
    amplitude : the largest Q/(mu P), in (0, 1] (default 1: up to gross sliding).
    cycle : after the loading to amplitude, unload to -amplitude and reload to +amplitude
          (2 ``steps`` each): Mindlin's hysteresis loop.

    Returns an ``OnsetResult`` (3D: ``onset3d.OnsetResult3D``): per step the fields and
    measurements, ``summary()`` (JSON record, SI), ``plot()`` (a Figure).  InputError for a
    bad option (named), ConvergenceError if the refinement cannot meet tol.
    """
    if scene is None:
        indenter = params.pop("indenter", "line")
        if indenter != "line":
            if indenter not in ("sphere", "paraboloid"):
                raise InputError(f"onset: --indenter {indenter} is not implemented (line, "
                                 f"sphere, paraboloid)")
            if "load" in params:
                raise InputError("load [N/m] is for the line indenter; a sphere takes force [N]")
            try:
                scene = Scene3D(indenter=indenter, **params)
            except TypeError as exc:
                raise InputError(f"onset: {exc}") from None
        else:
            if "force" in params:
                raise InputError("force [N] is for 3D indenters; the line indenter takes load "
                                 "[N/m]")
            try:
                scene = Scene(**params)
            except TypeError as exc:
                raise InputError(f"onset: {exc}") from None
    elif params:
        scene = scene.with_(**params)
    if scene.dimension == "surface":  # the surface onset (onset3d), else the line below
        from .onset3d import DEFAULT_TOL_3D, solve_onset3d

        steps = _check_int("steps (--steps)", steps, 1, MAX_STEPS)
        loading_steps = _check_int("loading_steps (--loading-steps)", loading_steps, 1,
                                   MAX_STEPS)
        if loading not in LOADINGS:
            raise InputError(f"{named('loading')} must be one of {', '.join(LOADINGS)}; got "
                             f"{loading!r}")
        amp = _check_amplitude(amplitude)
        grid_points = check_grid_points(grid_points, 32, 8192, "the onset's grid",
                                        even=True)
        L_h = None
        if domain_length is not None:
            from ..physics.scene import check_positive

            v = domain_length if np.ndim(domain_length) else (domain_length, domain_length)
            L_h = tuple(check_positive("domain_length (--domain-length)", x, "m")
                        / scene.length_unit for x in v)
        return solve_onset3d(scene, q_path(steps, amp, bool(cycle)),
                             DEFAULT_TOL_3D if tol is None else tol, loading=loading,
                             loading_steps=loading_steps, grid_points=grid_points,
                             domain_length=L_h, progress=progress)
    L_h = None
    if domain_length is not None:
        from ..physics.scene import check_positive

        L_h = check_positive("domain_length (--domain-length)", domain_length, "m") \
            / scene.length_unit
    return solve_onset(scene, steps, DEFAULT_TOL if tol is None else tol, loading=loading,
                       loading_steps=loading_steps, grid_points=grid_points,
                       domain_length=L_h, amplitude=amplitude, cycle=cycle, progress=progress)


def solve_onset(scene: Scene, steps: int = 20, tol: float = DEFAULT_TOL, *, loading: str = "frictional",
                loading_steps: int = LOADING_STEPS, grid_points: int | None = None,
                domain_length: float | None = None, amplitude: float = 1.0, cycle: bool = False,
                progress=None) -> OnsetResult:
    """Partial slip of ``scene`` (a line indenter, Amontons mu != 0) under Q = mu P k/steps,
    k = 1..steps, after the normal loading (see the module's docstring).

    tol : the relative accuracy target of each step's measurements (as ``solve``'s).
    grid_points, domain_length [h] : fix the grid instead (the estimate then compares N/2 and
    N; ``tolerance_met`` says whether it is below tol).
    progress : optional callable (step, steps, grid points) called after each step.
    """
    t0 = time.perf_counter()
    scene = check_onset_scene(scene)
    steps = _check_int("steps (--steps)", steps, 1, MAX_STEPS)
    loading_steps = _check_int("loading_steps (--loading-steps)", loading_steps, 1, MAX_STEPS)
    path = q_path(steps, _check_amplitude(amplitude), bool(cycle))
    if loading not in LOADINGS:
        raise InputError(f"{named('loading')} must be one of {', '.join(LOADINGS)}; got {loading!r}")
    tol = check_tol(tol)
    grid_points = check_grid_points(grid_points, MIN_POINTS, MAX_POINTS,
                                    "the onset's grid", even=True)
    film = Film(poisson=scene.poisson)
    P, mu = scene.P, scene.mu
    accept = max(1e-8, 1e-2 * tol)
    # the steady sliding solution: the grid spacing, the contact's extent at gross sliding,
    # and the reference of the last step
    # (always on solve's own grid: a user-fixed grid is this loading's, not the reference's)
    steady = solve_fft(scene, "exact", tol)
    a_s, c_s = steady.half_width, steady.center
    lo, hi = min(-a_s, c_s - a_s), max(a_s, c_s + a_s)
    margin = film.domain_margin(tol)
    dx_s = steady.domain_length / steady.grid_points
    if domain_length is None:
        L = (hi - lo) + margin + 4 * dx_s
        center = 0.5 * (hi + lo)
    else:
        L, center = domain_length, 0.0
    n = grid_points or max(pow2_at_least(L / dx_s, MIN_POINTS), 2 * MIN_POINTS)
    if n > MAX_POINTS:
        raise InputError(f"tol {tol:g} needs more than 2^22 grid points for onset; raise tol")
    image = _IMAGE_AMPLITUDE * max(1.0, abs(mu) / 10.0) * math.exp(-film.decay_rate
                                                                   * max(L - (hi - lo), 0.0))
    if domain_length is not None and not grid_points and image > 0.5 * tol:
        need = (hi - lo) + math.log(2.0 * _IMAGE_AMPLITUDE * max(1.0, abs(mu) / 10.0) / tol) \
            / film.decay_rate
        raise InputError(f"domain_length (--domain-length) {L * scene.length_unit:.4g} m is too "
                         f"short for this loading at tol {tol:g}: use at least "
                         f"{need * scene.length_unit:.4g} m, raise tol, or leave it automatic "
                         f"(with --grid-points fixed too, it is taken and the images' error is "
                         f"in the estimate)")

    def run(npts, path_=path, steps_=loading_steps):
        return LoadingRun(_Line(), Grid.centered(npts, L, center), film, P, mu, path_, loading,
                          steps_, accept, progress if path_ is path else None)

    fine, est, stick_est, met, n, doublings, counters, coarse = refine(
        run, n, tol, image, _differences, fixed=bool(grid_points),
        max_doublings=_MAX_DOUBLINGS, max_points=MAX_POINTS)
    if not met and not grid_points:
        raise ConvergenceError(f"onset: error estimate {max(est):.1e} > tol {tol:g} at N = {n}; "
                               f"raise tol", residuals=est, iterations=doublings)
    # the load steps' share (not reduced by the grid: flagged, tolerance_met False)
    est, stick_est, step_est, counters = with_load_steps(
        fine, coarse, run, path, loading, loading_steps, _differences, est, stick_est, counters)
    met = max(est) <= tol
    return OnsetResult(scene=scene, path=path, loading=loading, loading_steps=loading_steps,
                       tol=tol, run=fine, estimates=est, stick_estimates=stick_est,
                       load_step_estimates=step_est,
                       steady=steady, tolerance_met=met,
                       wall_time_s=time.perf_counter() - t0, counters=counters, film=film)


class OnsetResult(OnsetBase):
    """The loading of ``solve_onset``: per step (0 = after the normal load, then 1..steps) the
    dimensionless fields on the grid and the measurements; SI views; ``summary()`` the JSON
    record; ``plot()`` a Figure.

    Fields (dimensionless: lengths in h, stresses in G h/2R, displacements in h^2/2R):
    ``x``, ``pressure[k]``, ``shear[k]`` (sigma_xz(h)), ``slip[k]`` (accumulated slip of the
    indenter over the surface, 0 off the contact), ``stick[k]`` (bool), ``base_sigma_zz[k]``,
    ``base_sigma_xz[k]`` (sigma at z = 0, < 0 in compression), k = 0..steps.
    """

    def __init__(self, scene, path, loading, loading_steps, tol, run, estimates,
                 stick_estimates, steady, tolerance_met, wall_time_s, counters, film,
                 load_step_estimates=None):
        super().__init__(scene, path, loading, loading_steps, tol, run, estimates,
                         stick_estimates, steady, tolerance_met, wall_time_s, counters, film,
                         load_step_estimates)
        self.x = run.grid.x
        states = self.states
        self.pressure = np.array([s.p for s in states])
        self.shear = np.array([s.q for s in states])
        self.slip = np.array([s.slip for s in states])
        self.stick = np.array([s.stick for s in states])
        self.contact = np.array([s.contact for s in states])
        fft = get_rfft(run.grid.shape)
        zz, xz = [], []
        for s in states:
            szz, (sxz,) = film.base_stresses(fft, run.grid, -s.p, (s.q,))
            zz.append(szz)
            xz.append(sxz)
        self.base_sigma_zz = np.array(zz)
        self.base_sigma_xz = np.array(xz)

    # --- SI ------------------------------------------------------------------------------------
    def _si_step(self, k: int) -> dict:
        sc, m = self.scene, self.measures[k]
        h = sc.length_unit
        return step_record(self, k, {
            "tangential_load_N_per_m": float(self.Q_over_muP[k]) * sc.mu * sc.load,
            "stick_x_min_m": m["stick_lo"] * h, "stick_x_max_m": m["stick_hi"] * h,
            "half_width_m": m["a"] * h, "contact_center_m": m["c"] * h})

    def summary(self) -> dict:
        """The JSON record (SI): the scene's keys, the loading, and ``steps``: one object per
        tangential step (Q/(mu P) = 1/N .. 1; keys ``STEP_KEYS``), plus ``loaded``: the state
        after the normal load (Q = 0)."""
        sc = self.scene
        return {
            "load_N_per_m": sc.load, "mu": sc.mu, "young_Pa": sc.young, "poisson": sc.poisson,
            "radius_m": sc.radius, "thickness_m": sc.thickness,
            "loading": self.loading, "loading_steps": self.loading_steps,
            "n_steps": self.n_steps, "tol": self.tol, "grid_points": self.grid.n,
            "domain_length_m": self.grid.length * sc.length_unit,
            "error_estimate": max(self.error_estimates), "tolerance_met": self.tolerance_met,
            "load_step_error_estimate": max(self.load_step_estimates),
            "steady_half_width_m": self.steady.half_width_m,
            "steady_contact_center_m": self.steady.contact_center_m,
            "wall_time_s": self.wall_time_s, "counters": dict(self.counters),
            # steps whose stick-slip boundary node cycled and was accepted with a friction-law
            # violation <= 1e-2 (numerics.partial_slip._MARGINAL), and that largest violation
            "marginal_steps": sum(s.residuals.get("marginal_nodes", 0) for s in self.states),
            "friction_law_residual": max(max(s.residuals.get("coulomb", 0.0),
                                             s.residuals.get("slip_direction", 0.0))
                                         for s in self.states),
            "loaded": self._si_step(0),
            "steps": [self._si_step(k) for k in range(1, self.n_steps + 1)],
        }

    to_dict = summary

    def profiles(self, sensor: dict | None = None) -> dict:
        """The tidy table (SI): a row per step (0 = loaded) and node; ``PROFILE_COLUMNS``
        (+ the columns of ``sensor``, a dict of name -> array (steps + 1, nodes))."""
        sc = self.scene
        ns, n = self.pressure.shape
        cols = {
            "step": np.repeat(np.arange(ns), n),
            "Q_over_muP": np.repeat(self.Q_over_muP, n),
            "x_m": np.tile(self.x * sc.length_unit, ns),
            "pressure_Pa": (self.pressure * sc.stress_unit).ravel(),
            "shear_Pa": (self.shear * sc.stress_unit).ravel(),
            "slip_m": (self.slip * sc.displacement_unit).ravel(),
            "base_sigma_zz_Pa": (self.base_sigma_zz * sc.stress_unit).ravel(),
            "base_sigma_xz_Pa": (self.base_sigma_xz * sc.stress_unit).ravel(),
        }
        for k, v in (sensor or {}).items():
            cols[k] = np.asarray(v).ravel()
        return cols

    def __repr__(self) -> str:
        m = self.measures[-1]
        return (f"OnsetResult(load={self.scene.load:g} N/m, mu={self.scene.mu:g}, steps="
                f"{self.n_steps}, loading={self.loading}, N={self.grid.n}, a={m['a']:.5g} h, "
                f"estimate={max(self.error_estimates):.1e})")

    def plot(self, sensor: dict | None = None, shown=(0.25, 0.5, 0.75, 1.0)):
        """A Figure: surface tractions and base stresses at a few steps (Q/(mu P) in
        ``shown``), the stick zone against Q/(mu P), Q against the indenter's tangential
        displacement."""
        import matplotlib

        matplotlib.use("Agg", force=False)
        from matplotlib.figure import Figure

        sc = self.scene
        fig = Figure(figsize=(11, 7.5), layout="constrained")
        axs = fig.subplots(2, 2)
        mm, kPa = 1e3 / 1.0, 1e-3
        x = self.x * sc.length_unit * mm
        r = self.Q_over_muP
        if self.cycle:  # the turning points and the zero crossings
            ks = [int(np.argmax(r)), int(np.argmin(r)), self.n_steps]
        else:
            ks = sorted({int(np.argmin(np.abs(r - s))) for s in shown if 0 < s <= 1} - {0})
        a_max = max(m["a"] + abs(m["c"]) for m in self.measures)
        win = (np.abs(self.x) < a_max + 2.0)  # the base stresses' reach (lengths in h)
        wt = np.abs(self.x) < 1.5 * a_max  # the tractions: the contact
        ax = axs[0, 0]
        for k in [0] + ks:
            lab = f"Q/(mu P) = {self.Q_over_muP[k]:.2f}"
            line, = ax.plot(x[wt], self.pressure[k][wt] * sc.stress_unit * kPa, lw=1, label=lab)
            ax.plot(x[wt], np.abs(self.shear[k][wt]) * sc.stress_unit * kPa, lw=1, ls="--",
                    color=line.get_color())
        ax.set_xlabel("x [mm] (from the apex)")
        ax.set_ylabel("p (solid), |q| (dashed) [kPa]")
        ax.set_title("surface tractions")
        ax.legend(fontsize=7)
        ax = axs[0, 1]
        for k in [0] + ks:
            line, = ax.plot(x[win], -self.base_sigma_zz[k][win] * sc.stress_unit * kPa, lw=1,
                            label=f"{self.Q_over_muP[k]:.2f}")
            ax.plot(x[win], self.base_sigma_xz[k][win] * sc.stress_unit * kPa, lw=1, ls="--",
                    color=line.get_color())
        if sensor:
            for k in ks[-1:]:
                ax.plot(x[win], np.asarray(sensor["S_zz_Pa"])[k][win] * kPa, color="k", lw=0.8,
                        ls=":", label="sensor S_zz, S_xz")
                ax.plot(x[win], np.asarray(sensor["S_xz_Pa"])[k][win] * kPa, color="k", lw=0.8,
                        ls=":")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("-sigma_zz (solid), sigma_xz (dashed) at the base [kPa]")
        ax.set_title("base stresses")
        ax.legend(fontsize=7)
        ax = axs[1, 0]
        h = sc.length_unit * mm
        if self.cycle:  # the stick zone against the step (Q goes up, down and up)
            r = np.arange(self.n_steps + 1)
        ax.fill_between(r, [m["stick_lo"] * h for m in self.measures],
                        [m["stick_hi"] * h for m in self.measures], alpha=0.4, label="stick zone")
        ax.plot(r, [(m["c"] - m["a"]) * h for m in self.measures], "k-", lw=1, label="contact")
        ax.plot(r, [(m["c"] + m["a"]) * h for m in self.measures], "k-", lw=1)
        ax.set_xlabel("step" if self.cycle else "Q / (mu P)")
        ax.set_ylabel("x [mm]")
        ax.set_title("stick zone")
        ax.legend(fontsize=7)
        ax = axs[1, 1]
        ax.plot([m["delta"] * sc.displacement_unit * 1e6 for m in self.measures],
                self.Q_over_muP * sc.mu * sc.load, "o-", ms=3)
        ax.set_xlabel("indenter's tangential displacement [um]")
        ax.set_ylabel("Q [N/m]")
        ax.set_title("tangential load vs displacement")
        fig.suptitle(f"onset of sliding: P_L = {sc.load:g} N/m, mu = {sc.mu:g}, "
                     f"h = {sc.thickness * 1e3:g} mm ({self.loading} loading)")
        return fig
