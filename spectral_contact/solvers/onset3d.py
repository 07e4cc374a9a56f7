"""The onset of sliding of a 3D indenter (sphere, paraboloid) on the film: partial slip under a
growing tangential load along x, the slip direction solved (``numerics.partial_slip2d``).

As ``solvers.onset`` for lines: the normal load first (frictional in ``loading_steps`` steps,
or frictionless), then Q = mu P k/N along x (with ``cycle``: down to -amplitude and back), the
history kept.  The grid has the spacing of ``solve``'s 3D grid for the same scene and tol, on
periods holding the normal and the sliding contacts plus the kernels' decay margin; the loading
is run at N/2 and N points per axis and the per-step estimate is 1.5 x their difference in the
contact radius sqrt(A/pi) (A the polygon through the sub-grid edges, ``measure_contact_2d``, as
``solve``; counting the contact's cells made it 5-10 x larger and the default tol went to 512^2),
the pressure centroid (over the radius), the indentation, the peak pressure and the tangential
displacement (over its largest value), plus the periodic images' bound; one doubling if it
exceeds tol (then, or with a fixed grid, ``tolerance_met`` says).
The stick zone's radius sqrt(area/pi) has its own estimate (``stick_error_estimate``).

Default tol 1e-2 (``DEFAULT_TOL_3D``): each level costs N^2 points per step and the loading
has 30 steps by default; 1e-2 is about what a MEMS measurement resolves.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..errors import ConvergenceError, InputError
from ..numerics.contact import solve_contact
from ..numerics.fft import get_rfft
from ..numerics.grid import Grid, pow2_at_least
from ..numerics.measure2d import measure_contact_2d
from ..numerics.partial_slip2d import PartialSlipOperator2D, SlipState2D, solve_slip_step_2d
from ..physics.film import Film
from ..physics.indenters import Paraboloid
from ..physics.scene import Scene3D, check_tol
from .fft3d import MAX_POINTS_3D, MIN_POINTS_3D, solve_fft3d

__all__ = ["solve_onset3d", "OnsetResult3D", "DEFAULT_TOL_3D", "STEP_KEYS_3D"]

DEFAULT_TOL_3D = 1e-2
_LEVEL_MARGIN = 1.5
_IMAGE_AMPLITUDE = 2.0
STEP_KEYS_3D = ("Q_over_muP", "tangential_force_N", "stick_area_m2", "stick_radius_m",
                "stick_x_min_m", "stick_x_max_m", "contact_radius_m", "contact_center_m",
                "indentation_m", "max_pressure_Pa", "tangential_displacement_m",
                "error_estimate", "stick_error_estimate")


def check_onset_scene3d(scene) -> Scene3D:
    if scene.indenter not in ("sphere", "paraboloid"):
        raise InputError(f"--indenter {scene.indenter}: onset takes line, sphere or paraboloid "
                         f"(smooth indenters)")
    if scene.friction_law != "amontons":
        raise InputError(f"--friction-law {scene.friction_law}: onset takes Amontons friction "
                         f"only (Coulomb's |q| <= mu p)")
    if scene.interface_compliance:
        raise InputError("--interface-compliance: onset takes a rigid interface only")
    if scene.mu == 0.0:
        raise InputError("--mu must be != 0 for onset (the tangential load goes up to mu P)")
    if scene.force <= 0.0:
        raise InputError("--force must be > 0 N for onset")
    return scene


def _unit(v):
    n = np.hypot(v[0], v[1])
    return v / np.where(n > 0, n, 1.0), n


def _predict(s0: SlipState2D, s1: SlipState2D, f: np.ndarray, mu: float):
    """First sets and fields of the next step, extrapolated linearly from the last two (equal
    load steps along one path): the stick set where the margin |mu| p - |q| stays positive,
    the contact where the pressure does (and free nodes whose gap closes), new slip nodes
    along the last step's slip (or the shear), p, q, d and delta continued.  Only the number
    of active-set iterations depends on it (the solver checks every condition); None when
    nothing would stick."""
    m0 = mu * s0.p - np.hypot(*s0.q)
    m1 = mu * s1.p - np.hypot(*s1.q)
    contact = np.where(s1.contact, 2.0 * s1.p - s0.p > 0.0,
                       2.0 * (f - s1.d + s1.w) - (f - s0.d + s0.w) < 0.0)
    stick = s1.stick & contact & (2.0 * m1 - m0 > 0.0)
    if not stick.any():
        return None
    slipping = contact & ~stick
    ds = (s1.delta - s0.delta)[:, None] - (s1.u - s0.u)
    dsu, dsn = _unit(ds)
    qu, qn = _unit(s1.q)
    t = np.where(qn > 0, qu, np.where(dsn > 0, dsu, 0.0))
    g = SlipState2D(p=np.where(contact, np.maximum(2.0 * s1.p - s0.p, 1e-12 * s1.p.max()), 0.0),
                    q=np.where(contact, s1.q, 0.0), w=s1.w, u=s1.u, d=2.0 * s1.d - s0.d,
                    delta=2.0 * s1.delta - s0.delta, contact=contact, stick=stick,
                    sigma=s1.sigma, P=s1.P, Q=s1.Q)
    g.t = np.where(slipping, t, 0.0)
    return g


class _Run3D:
    def __init__(self, grid, film, ind, P, mu, path, loading, loading_steps, accept,
                 progress=None):
        self.grid = grid
        op = PartialSlipOperator2D(grid, film)
        f = np.asarray(ind.height(grid), dtype=float).ravel()
        n = grid.size
        amu = abs(mu)
        # the inner (GMRES) solves to 1e-2 of the accepted residual: the linear system's
        # relative residual bounds the gap, stick and load rows' (max-norm) residuals
        rtol = max(1e-10, 1e-2 * accept)
        counters = {"fft_pairs": 0, "krylov_iterations": 0, "iterations": 0}

        def count(s):
            counters["fft_pairs"] += s.fft_pairs
            counters["krylov_iterations"] += s.krylov_iterations
            counters["iterations"] += s.iterations

        P1 = P / loading_steps if loading == "frictional" else P
        ind1 = Paraboloid(ind.apex, P1, ind.cx, ind.cy)  # (a sphere is one)
        s0 = solve_contact(grid, 0.0, [ind1], film=film, accept=accept)
        counters["fft_pairs"] += s0.fft_pairs
        if loading == "frictional":
            state = SlipState2D.unloaded(n)
            guess = SlipState2D.unloaded(n)
            guess.contact = s0.active.ravel().copy()
            guess.stick = guess.contact.copy()
            guess.p = s0.pressure.ravel().copy()
            guess.d = float(s0.indentations[0])
            before = None
            for k in range(1, loading_steps + 1):
                if k > 1:
                    guess = _predict(before, state, f, amu) if k > 2 else None
                new = solve_slip_step_2d(op, f, state, P * k / loading_steps, (0.0, 0.0), amu,
                                         guess=guess, accept=accept, rtol=rtol)
                before, state = state, new
                count(state)
        else:
            p = s0.pressure.ravel().copy()
            w, u = op.apply(p, np.zeros((2, n)))
            state = SlipState2D(p=p, q=np.zeros((2, n)), w=w, u=u, d=float(s0.indentations[0]),
                                delta=np.zeros(2), contact=s0.active.ravel().copy(),
                                stick=s0.active.ravel().copy(), sigma=np.zeros(n, dtype=np.int8),
                                P=P, slip=np.zeros((2, n)))
            state.t = np.zeros((2, n))
        self.loaded = state
        self.states = []
        sgn = 1.0 if mu > 0 else -1.0
        for k, r in enumerate(path, start=1):
            guess = None
            if k > 2 and (path[k - 1] - path[k - 2]) * (path[k - 2] - path[k - 3]) > 0:
                guess = _predict(self.states[-2], state, f, amu)
            state = solve_slip_step_2d(op, f, state, P, (sgn * amu * P * r, 0.0), amu,
                                       accept=accept, rtol=rtol, guess=guess)
            count(state)
            self.states.append(state)
            if progress:
                progress(k, len(path), grid.shape[0])
        self.counters = counters
        self.measures = [self.measure(s, f) for s in [self.loaded] + self.states]

    def measure(self, s, f):
        """The contact's area (the polygon through the sub-grid edges, ``measure_contact_2d``,
        as ``solve`` measures it), pressure centroid and peak; the stick zone's area (its
        nodes' cells) and x extent (node positions); d, delta."""
        g = self.grid
        x = np.broadcast_to(g.coordinates()[0], g.shape).ravel()
        m = measure_contact_2d(g, s.p.reshape(g.shape), (f - s.d + s.w).reshape(g.shape),
                               s.contact.reshape(g.shape))
        stick_area = s.stick.sum() * g.cell
        xs = x[s.stick]
        return {"area": m["area"], "radius": math.sqrt(m["area"] / math.pi),
                "stick_area": stick_area, "stick_radius": math.sqrt(stick_area / math.pi),
                "stick_lo": float(xs.min()) if xs.size else math.nan,
                "stick_hi": float(xs.max()) if xs.size else math.nan,
                "xc": m["xc"], "d": float(s.d), "pmax": m["pmax"], "delta": float(s.delta[0]),
                "delta_y": float(s.delta[1]), "stick_nodes": int(s.stick.sum())}


def _differences(fine, coarse):
    main, stick = [], []
    dscale = max(max(abs(m["delta"]) for m in fine.measures), 1e-300)
    for mf, mc in zip(fine.measures, coarse.measures):
        r = max(mf["radius"], 1e-300)
        main.append(max(abs(mf["radius"] - mc["radius"]) / r, abs(mf["xc"] - mc["xc"]) / r,
                        abs(mf["d"] - mc["d"]) / max(abs(mf["d"]), 1e-300),
                        abs(mf["pmax"] - mc["pmax"]) / max(mf["pmax"], 1e-300),
                        abs(mf["delta"] - mc["delta"]) / dscale))
        stick.append(abs(mf["stick_radius"] - mc["stick_radius"]) / r
                     if mf["stick_nodes"] > 1 and mc["stick_nodes"] > 1 else 0.0)
    return main, stick


def solve_onset3d(scene: Scene3D, path, tol: float = DEFAULT_TOL_3D, *,
                  loading: str = "frictional", loading_steps: int = 10, grid_points=None,
                  domain_length=None, progress=None) -> OnsetResult3D:
    """Partial slip of a sphere or paraboloid (``scene``) along the tangential loads
    Q/(mu P) = ``path`` (see the module's docstring).  grid_points: N (both axes) fixed;
    domain_length: (Lx, Ly) [h] fixed."""
    t0 = time.perf_counter()
    scene = check_onset_scene3d(scene)
    tol = check_tol(tol)
    film = Film(poisson=scene.poisson)
    P, mu = scene.P, scene.mu
    accept = max(1e-8, 1e-2 * tol)
    ind = scene.indenter_object()
    steady = solve_fft3d(scene, "exact", tol)
    m = steady.measures
    lx, ly = np.asarray(steady.domain_length, dtype=float)
    nx0, ny0 = steady.grid_points
    dx = min(lx / nx0, ly / ny0)
    ey = 0.5 * (m["y_max"] - m["y_min"])
    lo, hi = min(-ey, m["x_min"]), max(ey, m["x_max"])
    margin = film.domain_margin(tol)
    if domain_length is None:
        L = ((hi - lo) + margin + 4 * dx, 2 * ey + margin + 4 * dx)
        center = (0.5 * (hi + lo), 0.0)
    else:
        L, center = tuple(domain_length), (0.0, 0.0)
    if grid_points:
        n = int(grid_points)
    else:
        n = max(pow2_at_least(max(L) / dx, MIN_POINTS_3D), 2 * MIN_POINTS_3D)
    if n > MAX_POINTS_3D:
        raise InputError(f"tol {tol:g} needs more than {MAX_POINTS_3D} points per axis for onset")
    image = _IMAGE_AMPLITUDE * max(1.0, abs(mu) / 10.0) * math.exp(
        -film.decay_rate * max(min(L[0] - (hi - lo), L[1] - 2 * ey), 0.0))

    def run(npts):
        return _Run3D(Grid.centered((npts, npts), L, center), film, ind, P, mu, path, loading,
                      loading_steps, accept, progress)

    coarse, fine = run(n // 2), run(n)
    doubled = False
    while True:
        diff, sdiff = _differences(fine, coarse)
        est = [_LEVEL_MARGIN * e + image for e in diff]
        if grid_points or max(est) <= tol or doubled or 2 * n > MAX_POINTS_3D:
            break
        coarse, fine, n = fine, run(2 * n), 2 * n
        doubled = True
    met = max(est) <= tol
    if not met and not grid_points:
        raise ConvergenceError(f"onset (3D): error estimate {max(est):.1e} > tol {tol:g} at "
                               f"{n}^2 points; raise tol or fix grid_points", residuals=est)
    counters = {k: fine.counters[k] + coarse.counters[k] for k in fine.counters}
    return OnsetResult3D(scene, list(path), loading, loading_steps, tol, fine, est,
                         [_LEVEL_MARGIN * e for e in sdiff], steady, met,
                         time.perf_counter() - t0, counters, film)


class OnsetResult3D:
    """The loading of ``solve_onset3d``: per step (0 = after the normal load) the fields on the
    grid (flat arrays reshaped [x, y] by ``field``), ``measures``, ``summary()`` (JSON, SI),
    ``profiles()`` (the y = 0 line, tidy), ``plot()`` (a Figure)."""

    def __init__(self, scene, path, loading, loading_steps, tol, run, estimates, stick_estimates,
                 steady, tolerance_met, wall_time_s, counters, film):
        self.scene = scene
        self.n_steps = len(path)
        self.cycle = min(path) < 0.0
        self.loading, self.loading_steps, self.tol = loading, loading_steps, tol
        self.grid = run.grid
        self.states = [run.loaded] + run.states
        self.measures = run.measures
        self.error_estimates = [float(e) for e in estimates]
        self.stick_error_estimates = [float(e) for e in stick_estimates]
        self.steady = steady
        self.tolerance_met = bool(tolerance_met)
        self.wall_time_s = wall_time_s
        self.counters = counters
        self.film = film
        self.Q_over_muP = np.array([0.0] + list(path))

    def field(self, k: int, name: str) -> np.ndarray:
        """A field of step k as an [x, y] array: "pressure", "shear_x", "shear_y", "stick",
        "contact"."""
        s = self.states[k]
        v = {"pressure": s.p, "shear_x": s.q[0], "shear_y": s.q[1], "stick": s.stick,
             "contact": s.contact}[name]
        return np.asarray(v).reshape(self.grid.shape)

    def base_stresses(self, k: int):
        """(sigma_zz, sigma_xz, sigma_yz) at the base, [x, y] arrays (core units)."""
        g = self.grid
        s = self.states[k]
        fft = get_rfft(g.shape)
        szz, (sxz, syz) = self.film.base_stresses(
            fft, g, -s.p.reshape(g.shape), (s.q[0].reshape(g.shape), s.q[1].reshape(g.shape)))
        return szz, sxz, syz

    def _si_step(self, k: int) -> dict:
        sc, m = self.scene, self.measures[k]
        h, dU, sU = sc.length_unit, sc.displacement_unit, sc.stress_unit
        r = float(self.Q_over_muP[k])
        return {
            "Q_over_muP": r,
            "tangential_force_N": r * sc.mu * sc.force,
            "stick_area_m2": m["stick_area"] * h * h,
            "stick_radius_m": m["stick_radius"] * h,
            "stick_x_min_m": m["stick_lo"] * h, "stick_x_max_m": m["stick_hi"] * h,
            "contact_radius_m": m["radius"] * h,
            "contact_center_m": m["xc"] * h,
            "indentation_m": m["d"] * dU,
            "max_pressure_Pa": m["pmax"] * sU,
            "tangential_displacement_m": m["delta"] * dU,
            "error_estimate": self.error_estimates[k],
            "stick_error_estimate": self.stick_error_estimates[k],
        }

    def summary(self) -> dict:
        sc = self.scene
        return {
            "indenter": sc.indenter, "force_N": sc.force, "mu": sc.mu, "young_Pa": sc.young,
            "poisson": sc.poisson, "radius_m": sc.radius, "thickness_m": sc.thickness,
            "loading": self.loading, "loading_steps": self.loading_steps,
            "n_steps": self.n_steps, "tol": self.tol, "grid_points": list(self.grid.shape),
            "domain_length_m": [v * sc.length_unit for v in self.grid.lengths],
            "error_estimate": max(self.error_estimates), "tolerance_met": self.tolerance_met,
            "steady_contact_radius_m": self.steady.contact_radius_m,
            "wall_time_s": self.wall_time_s, "counters": dict(self.counters),
            "marginal_steps": sum(s.residuals.get("marginal_nodes", 0) for s in self.states),
            "loaded": self._si_step(0),
            "steps": [self._si_step(k) for k in range(1, self.n_steps + 1)],
        }

    to_dict = summary

    def profiles(self, sensor: dict | None = None) -> dict:
        """The tidy table of the y = 0 line (SI): step, Q_over_muP, x_m, pressure_Pa, shear_Pa
        (q_x), slip_m (x), base_sigma_zz_Pa, base_sigma_xz_Pa."""
        sc = self.scene
        g = self.grid
        j0 = int(np.argmin(np.abs(g.axes[1])))
        x = g.axes[0] * sc.length_unit
        cols = {k: [] for k in ("step", "Q_over_muP", "x_m", "pressure_Pa", "shear_Pa", "slip_m",
                                "base_sigma_zz_Pa", "base_sigma_xz_Pa")}
        for k, s in enumerate(self.states):
            szz, sxz, _ = self.base_stresses(k)
            nx = g.shape[0]
            cols["step"].append(np.full(nx, k))
            cols["Q_over_muP"].append(np.full(nx, self.Q_over_muP[k]))
            cols["x_m"].append(x)
            cols["pressure_Pa"].append(self.field(k, "pressure")[:, j0] * sc.stress_unit)
            cols["shear_Pa"].append(self.field(k, "shear_x")[:, j0] * sc.stress_unit)
            cols["slip_m"].append(np.asarray(s.slip[0]).reshape(g.shape)[:, j0]
                                  * sc.displacement_unit)
            cols["base_sigma_zz_Pa"].append(szz[:, j0] * sc.stress_unit)
            cols["base_sigma_xz_Pa"].append(sxz[:, j0] * sc.stress_unit)
        return {k: np.concatenate(v) for k, v in cols.items()}

    def __repr__(self) -> str:
        return (f"OnsetResult3D({self.scene.indenter}, force={self.scene.force:g} N, "
                f"mu={self.scene.mu:g}, steps={self.n_steps}, N={self.grid.shape}, "
                f"estimate={max(self.error_estimates):.1e})")

    def plot(self, sensor=None, shown=(0.25, 0.5, 0.75, 0.95)):
        """A Figure: the stick / slip / free map at a few steps, the stick radius against
        Q/(mu P) with Mindlin's (1 - Q/(mu P))^(1/3), Q against the tangential displacement."""
        import matplotlib

        matplotlib.use("Agg", force=False)
        from matplotlib.figure import Figure

        sc = self.scene
        r = self.Q_over_muP
        ks = [int(np.argmin(np.abs(r - s))) for s in shown]
        fig = Figure(figsize=(13, 6.5), layout="constrained")
        axs = fig.subplots(2, len(ks))
        g = self.grid
        h = sc.length_unit * 1e3
        a = self.measures[0]["radius"]
        ext = [(g.axes[0][0]) * h, (g.axes[0][-1]) * h, g.axes[1][0] * h, g.axes[1][-1] * h]
        for ax, k in zip(axs[0], ks):
            zone = self.field(k, "contact").astype(float) + self.field(k, "stick")
            ax.imshow(zone.T, origin="lower", extent=ext, cmap="Blues", vmin=0, vmax=2)
            ax.set_xlim(-2.5 * a * h, 2.5 * a * h)
            ax.set_ylim(-2.5 * a * h, 2.5 * a * h)
            ax.set_title(f"Q/(mu P) = {r[k]:.2f}: stick (dark), slip", fontsize=8)
            ax.set_xlabel("x [mm]")
        ax = axs[1, 0]
        q = np.linspace(0, 1, 101)
        ax.plot(q, (1 - q) ** (1 / 3), "k--", lw=1, label="Mindlin (1 - Q/muP)^(1/3)")
        ax.plot(r[1:], [m["stick_radius"] / a for m in self.measures[1:]], "o-", ms=3,
                label="stick radius / a")
        ax.set_xlabel("Q / (mu P)")
        ax.legend(fontsize=7)
        ax = axs[1, 1]
        ax.plot([m["delta"] * sc.displacement_unit * 1e6 for m in self.measures],
                r * sc.mu * sc.force, "o-", ms=3)
        ax.set_xlabel("tangential displacement [um]")
        ax.set_ylabel("Q [N]")
        for ax in axs[1, 2:]:
            ax.axis("off")
        fig.suptitle(f"onset of sliding: {sc.indenter}, F = {sc.force:g} N, mu = {sc.mu:g}")
        return fig
