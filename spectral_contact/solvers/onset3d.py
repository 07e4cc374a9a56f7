"""The onset of sliding of a 3D indenter (sphere, paraboloid) on the film: partial slip under a
growing tangential load along x, the slip direction solved (``numerics.partial_slip``, the same driver as lines).

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
has 40 steps by default (20 loading, 20 tangential); 1e-2 is about what a MEMS measurement
resolves.
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
from ..numerics.partial_slip import SlipState2D
from ..physics.film import Film
from ..physics.indenters import Paraboloid
from ..physics.scene import Scene3D, check_tol
from .base import check_onset_mu
from .fft3d import MAX_POINTS_3D, MIN_POINTS_3D, _check_size, solve_fft3d
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

__all__ = ["solve_onset3d", "OnsetResult3D", "DEFAULT_TOL_3D", "STEP_KEYS_3D"]

DEFAULT_TOL_3D = 1e-2
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
    check_onset_mu(scene.mu)
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


class _Surface(Dimension):
    """The surface's part of the loading (``onset_core``): a sphere or paraboloid's heights,
    Q along x, the predicted sets of ``_predict``, the measures of ``measure_contact_2d``."""

    def __init__(self, ind):
        self.ind = ind

    def heights(self, grid):
        return np.asarray(self.ind.height(grid), dtype=float).ravel()

    def first_contact(self, grid, film, P1, accept):
        ind = self.ind
        s0 = solve_contact(grid, 0.0, [Paraboloid(ind.apex, P1, ind.cx, ind.cy)], film=film,
                           accept=accept)  # (a sphere is a paraboloid here)
        return (s0.active.ravel(), s0.pressure.ravel(), float(s0.indentations[0]),
                s0.fft_pairs)

    unloaded = staticmethod(SlipState2D.unloaded)

    def tangential(self, Q):
        return (Q, 0.0)

    def predict(self, s0, s1, f, mu):
        return _predict(s0, s1, f, mu)

    def measure(self, g, s, f, mu):
        """The contact's area (the polygon through the sub-grid edges, ``measure_contact_2d``,
        as ``solve`` measures it), pressure centroid and peak; the stick zone's area (its
        nodes' cells) and x extent (node positions); d, delta."""
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
    """Per step: ``onset_core.differences`` of the contact radius and centroid, and of the
    stick zone's radius sqrt(area/pi) (over the contact radius)."""
    return differences(fine, coarse, "radius", "xc", lambda mf, mc, r: abs(
        mf["stick_radius"] - mc["stick_radius"]) / r)


def solve_onset3d(scene: Scene3D, path, tol: float = DEFAULT_TOL_3D, *,
                  loading: str = "frictional", loading_steps: int = LOADING_STEPS, grid_points=None,
                  domain_length=None, progress=None) -> OnsetResult3D:
    """Partial slip of a sphere or paraboloid (``scene``) along the tangential loads
    Q/(mu P) = ``path`` (see the module's docstring).  grid_points: N (both axes) fixed;
    domain_length: (Lx, Ly) [h] fixed."""
    t0 = time.perf_counter()
    scene = check_onset_scene3d(scene)
    tol = check_tol(tol)
    run, n, image, steady, film = loading_runner(scene, path, tol, loading=loading,
                                                 loading_steps=loading_steps,
                                                 grid_points=grid_points,
                                                 domain_length=domain_length, progress=progress)
    fine, est, stick_est, met, n, _, counters, coarse = refine(
        run, n, tol, image, _differences, fixed=bool(grid_points), max_doublings=1,
        max_points=MAX_POINTS_3D)
    if not met and not grid_points:
        raise ConvergenceError(f"onset (3D): error estimate {max(est):.1e} > tol {tol:g} at "
                               f"{n}^2 points; raise tol or fix grid_points", residuals=est)
    # the load steps' share (not reduced by the grid: flagged, tolerance_met False)
    est, stick_est, step_est, counters = with_load_steps(
        fine, coarse, run, list(path), loading, loading_steps, _differences, est, stick_est,
        counters)
    met = max(est) <= tol
    return OnsetResult3D(scene, list(path), loading, loading_steps, tol, fine, est,
                         stick_est, steady, met,
                         time.perf_counter() - t0, counters, film, step_est)


def loading_runner(scene: Scene3D, path, tol: float, *, loading: str = "frictional",
                   loading_steps: int = LOADING_STEPS, grid_points=None, domain_length=None,
                   progress=None):
    """What ``solve_onset3d`` runs (a checked ``scene``): ``run(npts, path, loading_steps)``
    (a ``LoadingRun`` on npts^2 points of the domain chosen for ``tol``), the first grid's
    npts, the periodic images' bound, the steady solution and the film.  (Also for studies
    that run the same loading on other grids and steps: ``studies.onset_reference``.)"""
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
    _check_size((n, n), f"onset at tol {tol:g}")  # solve's memory estimate (a lower bound here)
    image = _IMAGE_AMPLITUDE * max(1.0, abs(mu) / 10.0) * math.exp(
        -film.decay_rate * max(min(L[0] - (hi - lo), L[1] - 2 * ey), 0.0))

    def run(npts, path_=path, steps_=loading_steps):
        return LoadingRun(_Surface(ind), Grid.centered((npts, npts), L, center), film, P, mu,
                          path_, loading, steps_, accept, progress if path_ is path else None)

    return run, n, image, steady, film


class OnsetResult3D(OnsetBase):
    """The loading of ``solve_onset3d``: per step (0 = after the normal load) the fields on the
    grid (flat arrays reshaped [x, y] by ``field``), ``measures``, ``summary()`` (JSON, SI),
    ``profiles()`` (the y = 0 line, tidy), ``plot()`` (a Figure)."""

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
        h = sc.length_unit
        return step_record(self, k, {
            "tangential_force_N": float(self.Q_over_muP[k]) * sc.mu * sc.force,
            "stick_area_m2": m["stick_area"] * h * h, "stick_radius_m": m["stick_radius"] * h,
            "stick_x_min_m": m["stick_lo"] * h, "stick_x_max_m": m["stick_hi"] * h,
            "contact_radius_m": m["radius"] * h, "contact_center_m": m["xc"] * h})

    def summary(self) -> dict:
        sc = self.scene
        return {
            "indenter": sc.indenter, "force_N": sc.force, "mu": sc.mu, "young_Pa": sc.young,
            "poisson": sc.poisson, "radius_m": sc.radius, "thickness_m": sc.thickness,
            "loading": self.loading, "loading_steps": self.loading_steps,
            "n_steps": self.n_steps, "tol": self.tol, "grid_points": list(self.grid.shape),
            "domain_length_m": [v * sc.length_unit for v in self.grid.lengths],
            "error_estimate": max(self.error_estimates), "tolerance_met": self.tolerance_met,
            "load_step_error_estimate": max(self.load_step_estimates),
            "steady_contact_radius_m": self.steady.contact_radius_m,
            "wall_time_s": self.wall_time_s, "counters": dict(self.counters),
            "marginal_steps": sum(s.residuals.get("marginal_nodes", 0) for s in self.states),
            "loaded": self._si_step(0),
            "steps": [self._si_step(k) for k in range(1, self.n_steps + 1)],
        }

    to_dict = summary

    def maps(self, k: int | None = None) -> dict:
        """The fields in SI, [x, y] arrays: ``solve``'s map keys (``result.MAP_KEYS``: x_m,
        y_m, pressure_Pa, base_sigma_zz_Pa, base_sigma_xz_Pa, base_sigma_yz_Pa, surface_ux_m,
        surface_uy_m, surface_uz_m) and the onset's shear_x_Pa, shear_y_Pa (sigma_xz(h),
        sigma_yz(h)), slip_x_m, slip_y_m (the accumulated slip), stick, contact (bool).  Of step
        k (0 = after the normal load): (nx, ny) arrays; k None: every step on a leading step
        axis, (steps + 1, nx, ny), with ``step`` and ``Q_over_muP`` (steps + 1,) (the layout of
        ``--maps``)."""
        if k is None:
            per = [self.maps(i) for i in range(len(self.states))]
            out = {key: np.stack([m[key] for m in per]) for key in per[0]
                   if key not in ("x_m", "y_m")}
            return {"x_m": per[0]["x_m"], "y_m": per[0]["y_m"],
                    "step": np.arange(len(self.states)), "Q_over_muP": self.Q_over_muP, **out}
        sc, g, s = self.scene, self.grid, self.states[k]
        L, S, U = sc.length_unit, sc.stress_unit, sc.displacement_unit
        szz, sxz, syz = self.base_stresses(k)

        def field(v):
            return np.asarray(v).reshape(g.shape)
        return {"x_m": g.axes[0] * L, "y_m": g.axes[1] * L, "pressure_Pa": field(s.p) * S,
                "base_sigma_zz_Pa": szz * S, "base_sigma_xz_Pa": sxz * S,
                "base_sigma_yz_Pa": syz * S, "surface_ux_m": field(s.u[0]) * U,
                "surface_uy_m": field(s.u[1]) * U, "surface_uz_m": -field(s.w) * U,
                "shear_x_Pa": field(s.q[0]) * S, "shear_y_Pa": field(s.q[1]) * S,
                "slip_x_m": field(s.slip[0]) * U, "slip_y_m": field(s.slip[1]) * U,
                "stick": field(s.stick), "contact": field(s.contact)}

    def profiles(self, sensor: dict | None = None) -> dict:
        """The tidy table of the y = 0 line (the grid line nearest it; SI): step, Q_over_muP,
        x_m, pressure_Pa, shear_Pa (q_x), slip_m (x), base_sigma_zz_Pa, base_sigma_xz_Pa
        (+ with ``sensor``, a dict of name -> (steps + 1, nx, ny) maps: those names on the
        line)."""
        g = self.grid
        j0 = int(np.argmin(np.abs(g.axes[1])))
        cols = {k: [] for k in ("step", "Q_over_muP", "x_m", "pressure_Pa", "shear_Pa", "slip_m",
                                "base_sigma_zz_Pa", "base_sigma_xz_Pa")}
        names = {"shear_Pa": "shear_x_Pa", "slip_m": "slip_x_m"}
        for k in range(len(self.states)):
            m = self.maps(k)
            nx = g.shape[0]
            cols["step"].append(np.full(nx, k))
            cols["Q_over_muP"].append(np.full(nx, self.Q_over_muP[k]))
            cols["x_m"].append(m["x_m"])
            for c in ("pressure_Pa", "shear_Pa", "slip_m", "base_sigma_zz_Pa",
                      "base_sigma_xz_Pa"):
                cols[c].append(m[names.get(c, c)][:, j0])
        out = {k: np.concatenate(v) for k, v in cols.items()}
        for name, v in (sensor or {}).items():
            out[name] = np.asarray(v)[:, :, j0].ravel()
        return out

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
