"""A viscoelastic (Prony series) film in steady sliding (issue 23).

    python -m studies.viscoelastic [--quick] [--out DIR] [--parts ...]

Parts (``--parts``), each a CSV (+ .meta.json) in the output folder (default out/viscoelastic):

speed      mu_def, half-width a, x0 and Q/P against V over 8 decades (1e-6 ... 1e2 m/s) for
           the paper's scene (P_L = 200 N/m, mu = 2) and frictionless lines of Hertz half-width
           a_H/h = 0.1, 0.3, 1, 3, on a standard linear solid E_1 = E_inf, tau = 10 ms (peak
           loss tangent 0.354), tol 1e-3; the cost (FFT pairs, grid points) against the elastic
           solve of the same scene and tol.
sphere     the sphere (3D, F = 1 N, mu = 0, tol 1e-2) at a few speeds: its periodic images
           along x (the same fixed grid on twice the period) and its true error (half the
           cells, twice the period along x) against the error estimates.
sphere_cost  the sphere's cost (F = 1 N, mu = 0) against the elastic sphere at the same tol
           (1e-2, 5e-3) at 1e-4, 1e-3, 3e-3, 1e-2 m/s (V tau/h 5e-4 ... 5e-2, where the edge
           rule refines the grid along x): CPU times, fastest of warm interleaved runs
           (``viscoelastic_cost._timed_pair``), grids, estimates; a refused solve is a row.
sphere_fitted  the sphere with the edge structure left to the fits (``solvers.fft3d.edges_fitted``):
           the automatic solve against 4 times finer cells per axis on its own period, over the
           quantities the estimate covers, at 1e-4 ... 3e-2 m/s, tol 1e-2, 5e-3, 1e-3: SLS mu 0
           and 0.5, a two-term series of r = 1/2, and (seventh session) films 4 and 11 times
           stiffer when glassy (E_1 = 3, 10 E_inf; trailing edges from the pressure side), mu 0
           and 0.5 (``trailing_fit`` column); ``--sphere-films`` runs some films alone.
sphere_beyond_cost  the stiff films' cost (E_1 = 3, 10 E_inf, F = 1 N, mu 0) against the
           elastic sphere at tol 1e-2, 5e-3, 1e-3, 1e-4 ... 3e-2 m/s: CPU time ratio, fastest
           of 3 warm interleaved runs, each pair in a child process (refused, or past 300 s:
           a row that says so).
estimate   the error estimate against the true error (a much finer, twice longer fixed grid:
           2^21 points over twice the period) over V, tol 1e-3 and 1e-4, mu 0 and 1.
reference  small contacts (a_H/h = 0.01 ... 0.001): the film solver and the independent x-space
           collocation (reference.sls_halfspace) against Hunter's closed form for the SLS
           half-space (reference.hunter: derived here, his paper's formulas not found).
claim      the paper's "purely elastic" film: a standard linear solid whose peak loss tangent is
           0.1 (no published Prony series of Sylgard 184 was retrieved here: arXiv 2402.07555
           fits one, its coefficients were not accessible), against the elastic film E_inf =
           2.2 MPa on the paper's scene: the changes of a, x0 (over a), Q/P and the base
           stresses (max |difference| / max |elastic|) against V tau / h, the first V tau / h
           where one exceeds 1 %, and the speed that is for loss peaks at 1 Hz ... 1 kHz,
           against the paper's 0.2 - 2 mm/s.
images     the periodic images of the full-path line solves (the fixed grid on its period
           and on twice it: same cells) against the estimate's image term, which is the
           elastic one times ViscoelasticFilm.image_factor where every tail is short or
           summed and the contact frictionless (not measured there; else measured):
           a_H/h = 0.1, 1, 3 (a_H/h = 1 also mirrored, V < 0; a two-term series; tol 1e-4;
           a film 11 times stiffer when glassy, E_1 = 10 E_inf), the paper's scene (mu 2:
           measured; also mirrored, two terms, tol 1e-4, stiffer); 15 speeds 1e-6 ... 10 m/s.
second     the slow-sliding theory's second order (issue 23's cost at tol 1e-4): the first-order
           theory (the relaxed elastic solve at tol 1e-5 + the shift delta) against resolved
           solves (2^21 points over twice the period) where the first-order remainder bound
           is near tol 1e-4 (a_H/h 0.1, 1, 3 frictionless, the paper's scene), signed, in units
           of c2/a^2 (c2 = m2 - delta^2/2, m2 = sum c_j l_j^2 = delta l_r for one term), next
           to the derived second-order centroid (ViscoelasticFilm.slow_centroid_second_order:
           the energy identity; the study's fits on the tol 1e-5 solve) and Hunter's
           second-order coefficients (x_c: -1/4, x_p: -1, a: 0; tests/test_hunter.py).
edge_layer the trailing edges fitted with their inner layer (``numerics.edges.viscous_gap``) instead
           of resolving |V| tau (issue 23's cost at tol 1e-4): the paper's scene and a_H/h =
           0.1, 1, 3 at the speeds where the edge structure was resolved (1e-4 ... 3e-2 m/s),
           tol 1e-4: the automatic solve's estimate against its true error (2^20 points over
           twice the period), its grid against the elastic one's, and a fixed grid with ~1 cell
           across V tau on the solve's period (a, x_c against the reference).
edge_range the layer fit's range (``_LineSolve.LAYER_FITTED_WEIGHT``): films 4 and 11 times stiffer
           when glassy (E_1 = 3, 10 E_inf; their edge structure resolved) and a two-term series
           (E_inf at 1 ms and 0.1 s: fitted), on a_H/h 1 (mu 0), the paper's scene (mu 2) and
           a_H/h 0.3 (mu 0.5), 1e-4 ... 3.2e-2 m/s, tol 1e-4 and 1e-3: the estimate against the
           true error (2^20 points over twice the period).  Since the seventh session
           every film here is fitted (LAYER_FITTED_WEIGHT = 10).
heavy_terms  seventh session: Prony terms up to E_i/E_inf = 10 left to the edge fits (the
           trailing edge's layer fit, the odd-even peak): E_1 = 3, 10 E_inf and three terms
           (3 E_inf at 1 ms, 10 ms, 0.1 s) on a_H/h 0.1, 3 (mu 0), a_H/h 1 (mu 0.5) and the
           paper's scene (mu 2), 1e-5 ... 1 m/s, tol 1e-4 and 1e-3: the estimate against the
           true error (2^20 points over twice the period) and the measure carrying it.
heavy_offset  seventh session: fixed grids (2048 ... 16384 points) against 2^19 points, E_1 =
           1, 3, 10 E_inf, a_H/h 0.3 and the paper's scene, 2.5e-5 ... 2e-4 m/s: the edges'
           offsets over the term's shift while V tau is below a cell (``LAYER_OFFSET``).
offset_range  tenth session: the fitted edges' offsets from l/dx 1e-3 to ~8 (E_1 = 3, 10 E_inf;
           a_H/h 0.1, 0.3, 1, 3 at mu 0 and 0.5, the paper's scene; four fixed grids over the
           elastic period), each a change from the same grid at l/dx 1e-5 (the fits' own
           noise cancelled), against 2^19-2^21 points or the slow-sliding theory: the bound
           ``_LineSolve.layer_offset`` (and the old 0.1 min(1, dx/l)).
offset_phase  tenth session: the same offsets against the edge's phase in its cell (the period
           swept by one cell at the trailing edge, 16 periods) at fixed l/dx, five scenes.
--heavy-weights  ninth session: heavy_terms and heavy_offset run single terms of these weights
           E_1/E_inf instead (e.g. 30,100: rubber-like films 31 and 101 times stiffer when
           glassy; heavy_terms names them "E1=30Einf", ...); their tables get the suffix
           ``_w30_100``.  Default: the tables above, unchanged.
figure     viscoelastic.png: mu_def and a against V; the claim's changes; the base stresses
           and their MEMS view at one speed.
"""
from __future__ import annotations

import math
import os
import sys
import time

import numpy as np

from spectral_contact import solve
from spectral_contact.errors import ConvergenceError, InputError
from spectral_contact.physics.scene import Scene
from spectral_contact.reference.hunter import hunter_contact
from spectral_contact.reference.sls_halfspace import sls_halfspace_contact
from spectral_contact.solvers.fft import solve_fft
from spectral_contact.solvers.visco_slow import edge_amplitudes

from ._common import float_list, parse, progress, table

E_INF = 2.2e6
TAU = 0.01
SLS = ((E_INF, TAU),)  # E_1 = E_inf: E_0 = 2 E_inf, tau_r = 20 ms
FILM = {"young": E_INF, "thickness": 0.002, "radius": 0.130}


def load_for(s: float) -> float:
    """P_L [N/m] whose Hertz half-space half-width is s film thicknesses (P = 2 pi s^2)."""
    base = Scene(**FILM)
    return 2.0 * math.pi * s * s * base.stress_unit * base.length_unit


def sls_for_peak_loss(tan_max: float) -> float:
    """E_1 / E_inf of the SLS whose peak loss tangent is tan_max: (r - 1)/(2 sqrt r) = tan_max,
    r = E_0/E_inf; the peak sits at omega tau = sqrt(E_inf/E_0)."""
    sr = tan_max + math.sqrt(tan_max * tan_max + 1.0)
    return sr * sr - 1.0


def _row(r, el=None) -> dict:
    d = r.to_dict()
    out = {"half_width_m": d["half_width_m"], "x0_m": d["x0_m"],
           "deformation_friction": d.get("deformation_friction", 0.0), "Q_over_P": d["Q_over_P"],
           "error_estimate": d["error_estimate"], "grid_points": d["grid_points"],
           "fft_pairs": r.counters["transforms"]}
    if el is not None:
        out["a_over_a_elastic"] = d["half_width_m"] / el.half_width_m
        out["fft_pairs_ratio"] = r.counters["transforms"] / el.counters["transforms"]
        out["grid_points_ratio"] = d["grid_points"] / el.grid_points
    return out


def part_speed(quick: bool, out, t0) -> list[dict]:
    speeds = np.logspace(-6, 2, 5 if quick else 17)
    scenes = [("paper", 200.0, 2.0)] + [(f"aH/h={s:g}", load_for(s), 0.0)
                                        for s in ((0.3, 3.0) if quick else (0.1, 0.3, 1.0, 3.0))]
    rows = []
    n = len(speeds) * len(scenes)
    for name, load, mu in scenes:
        el = solve(load=load, mu=mu, tol=1e-3, **FILM)
        for V in speeds:
            row = {"scene": name, "load_N_per_m": load, "mu": mu, "speed_m_per_s": float(V),
                   "V_tau_over_h": V * TAU / FILM["thickness"], "status": "ok"}
            t = time.perf_counter()
            try:
                r = solve(load=load, mu=mu, speed=float(V), prony=SLS, tol=1e-3, **FILM)
                row |= _row(r, el)
            except (InputError, ConvergenceError) as exc:  # refused or not converged: say so
                row |= {k: float("nan") for k in _row(el, el)}
                row["status"] = type(exc).__name__ + ": " + str(exc).splitlines()[0][:80]
            row["time_s"] = time.perf_counter() - t
            rows.append(row)
            progress(len(rows), n, f"{name} V={V:.1e}", t0)
    table(rows, out / "viscoelastic_speed.csv",
          "Viscoelastic line (SLS E1 = E_inf, tau = 10 ms): mu_def, a, x0, Q/P against V; cost "
          "against the elastic (E_inf) solve at tol 1e-3")
    return rows


_SPHERE_COVERED = ("contact_radius_m", "pressure_centroid_x_m", "indentation_m", "max_pressure_Pa")
_SPHERE_EXTENTS = ("contact_x_min_m", "contact_x_max_m")


def _sphere_change(d, ref, keys) -> float:
    """Largest relative change of ``keys`` from ``ref`` to ``d`` (lengths over the contact
    radius, d and p_max over themselves)."""
    rad = ref["contact_radius_m"]
    return max(abs(d[k] - ref[k]) / (abs(ref[k]) if k in ("indentation_m", "max_pressure_Pa")
                                     else rad) for k in keys)


def part_sphere(quick: bool, out, t0) -> list[dict]:
    """The sphere at a few speeds (tol 1e-2), and its error against the estimates:
    period_difference: the fixed grid of the solve on its period and on twice the period along
    x (same cells, same path: the periodic images alone); true_error: the solve against a
    reference with half the cells on twice the period along x (skipped past 2^22 points),
    over the quantities the error estimate covers (radius, centroid, d, p_max); the x extents
    against ``extent_error_estimate`` (they are not controlled by tol: ContactResult3D)."""
    sph = []
    speeds = (1e-4, 0.1) if quick else (1e-4, 1e-2, 0.03, 0.1, 0.3, 1.0, 10.0, 100.0)
    L = FILM["thickness"]
    t = time.perf_counter()
    el = solve(indenter="sphere", force=1.0, mu=0.0, tol=1e-2, **FILM)
    t_el = time.perf_counter() - t
    for V in speeds:
        kw = dict(indenter="sphere", force=1.0, mu=0.0, speed=V, prony=SLS, tol=1e-2, **FILM)
        t = time.perf_counter()
        r = solve(**kw)
        t_v = time.perf_counter() - t
        d = r.summary()
        (nx, ny), (Lx, Ly) = r.grid_points, r.domain_length
        fixed = solve(**kw, grid_points=(nx, ny), domain_length=(Lx * L, Ly * L)).summary()
        far = solve(**kw, grid_points=(2 * nx, ny), domain_length=(2 * Lx * L, Ly * L)).summary()
        ref = (solve(**kw, grid_points=(4 * nx, 2 * ny), domain_length=(2 * Lx * L, Ly * L)).summary()
               if 8 * nx * ny <= 2**22 else None)
        nan = float("nan")
        err = _sphere_change(d, ref, _SPHERE_COVERED) if ref else nan
        ext = _sphere_change(d, ref, _SPHERE_EXTENTS) if ref else nan
        ext_est = r.info["extent_error_estimate"]
        sph.append({"speed_m_per_s": V, "contact_radius_m": d["contact_radius_m"],
                    "pressure_centroid_x_m": d["pressure_centroid_x_m"],
                    "deformation_friction": d["deformation_friction"],
                    "error_estimate": d["error_estimate"],
                    "tail_length_h": r.info.get("tail_length", 0.0), "period_x_h": Lx,
                    "period_difference": _sphere_change(fixed, far, _SPHERE_COVERED + _SPHERE_EXTENTS),
                    "true_error": err, "bounded": bool(err <= d["error_estimate"]) if ref else None,
                    "extent_error_estimate": ext_est, "extent_true_error": ext,
                    "extent_bounded": bool(ext <= ext_est) if ref else None,
                    "grid_x": nx, "grid_y": ny, "fft_pairs": r.counters["transforms"],
                    "fft_pairs_ratio": r.counters["transforms"] / el.counters["transforms"],
                    "grid_points_ratio": nx * ny / (el.grid_points[0] * el.grid_points[1]),
                    "time_ratio": t_v / t_el})
        progress(len(sph), len(speeds), f"sphere V={V:g}", t0)
    table(sph, out / "viscoelastic_sphere.csv",
          "Viscoelastic sphere (F = 1 N, mu = 0, SLS E1 = E_inf, tau = 10 ms), tol 1e-2; "
          "period_difference: the fixed grid on twice the period along x; true_error: against "
          "half the cells on twice the period along x")
    return sph


def part_sphere_cost(quick: bool, out, t0) -> list[dict]:
    from .viscoelastic_cost import _timed_pair  # (it imports this module)
    speeds = (1e-3, 1e-2) if quick else (1e-4, 1e-3, 3e-3, 1e-2)
    rows, load0 = [], os.getloadavg()[0]
    tols = (1e-2,) if quick else (1e-2, 5e-3)
    for tol in tols:
        kw = dict(indenter="sphere", force=1.0, mu=0.0, tol=tol, **FILM)
        for V in speeds:
            row = {"tol": tol, "speed_m_per_s": V, "V_tau_over_h": V * TAU / FILM["thickness"]}
            try:
                el, r, (c_el, c_v), _ = _timed_pair(lambda: solve(**kw),
                                                    lambda: solve(speed=V, prony=SLS, **kw), 5)
                row |= {"cpu_elastic_s": c_el, "cpu_visco_s": c_v, "time_ratio": c_v / c_el,
                        "grid_x": r.grid_points[0], "grid_y": r.grid_points[1],
                        "grid_x_elastic": el.grid_points[0], "error_estimate": r.error_estimate,
                        "status": "ok"}
            except (InputError, ConvergenceError) as exc:  # refused or not converged
                row |= dict.fromkeys(("cpu_elastic_s", "cpu_visco_s", "time_ratio", "grid_x",
                                      "grid_y", "grid_x_elastic", "error_estimate"), math.nan)
                row["status"] = type(exc).__name__ + ": " + str(exc).splitlines()[0][:80]
            rows.append(row)
            progress(len(rows), len(tols) * len(speeds), f"sphere cost tol {tol:g} V={V:g}", t0)
    table(rows, out / "viscoelastic_sphere_cost.csv",
          f"Viscoelastic sphere (F = 1 N, mu 0, SLS E1 = E_inf, tau 10 ms) against the elastic one "
          f"(E_inf), CPU time ratio (fastest of 5 warm interleaved runs); load average "
          f"{load0:.1f} -> {os.getloadavg()[0]:.1f}")
    return rows


def part_sphere_fitted(quick: bool, out, t0, films=None) -> list[dict]:
    import spectral_contact.solvers.fft3d as f3
    from spectral_contact.api import make_scene
    speeds = (1e-3, 1e-2) if quick else (1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2)
    two = ((0.5 * E_INF, 1e-3), (0.5 * E_INF, 0.1))
    tols = (1e-2, 5e-3, 1e-3)
    # the seventh session's: films 4 and 11 times stiffer when glassy (trailing edges fitted
    # from the pressure side; E_1 = 10 E_inf's leading edge peak gridded where it may be the
    # maximum, ``fft3d._leading_peak_terms``), also with friction
    cases = [("SLS", SLS, 0.0, tols), ("SLS", SLS, 0.5, tols), ("two-term", two, 0.0, tols),
             ("E1=3Einf", ((3 * E_INF, TAU),), 0.0, tols),
             ("E1=10Einf", ((10 * E_INF, TAU),), 0.0, tols),
             ("E1=3Einf", ((3 * E_INF, TAU),), 0.5, (1e-2, 1e-3)),
             ("E1=10Einf", ((10 * E_INF, TAU),), 0.5, (1e-2, 1e-3))]
    if quick:
        cases = cases[:1]
    if films:  # --sphere-films: these films' cases only
        cases = [c for c in cases if c[0] in films]
    rows, L = [], FILM["thickness"]
    total = sum(len(c[3]) for c in cases) * len(speeds)
    for name, prony, mu, tols_ in cases:
        for tol in tols_:
            for V in speeds:
                kw = dict(indenter="sphere", force=1.0, mu=mu, speed=V, prony=prony, tol=tol,
                          **FILM)
                film = make_scene(indenter="sphere", **{k: v for k, v in kw.items()
                                                        if k not in ("indenter", "tol")}).core_film()
                row = {"film": name, "mu": mu, "tol": tol, "speed_m_per_s": V,
                       "trailing_fit": "pressure" if f3.trailing_from_pressure(film) else "gap"}
                try:
                    r = solve(**kw)
                except (InputError, ConvergenceError) as exc:
                    row["status"] = type(exc).__name__ + ": " + str(exc)[:60]
                    rows.append(row)
                    progress(len(rows), total, f"sphere fitted {name} tol {tol:g} V={V:g}: "
                             f"{row['status'][:30]}", t0)
                    continue
                (nx, ny), (Lx, Ly) = r.grid_points, r.domain_length
                n = (min(8192, 4 * nx), min(8192, 4 * ny))
                row |= {"grid_x": nx, "grid_y": ny, "error_estimate": r.error_estimate}
                if n[0] * n[1] > 2**23:  # (a reference past 4096 x 2048: minutes each here)
                    row["status"] = f"reference skipped: {n[0]} x {n[1]}"
                    rows.append(row)
                    progress(len(rows), total, f"sphere fitted {name} tol {tol:g} V={V:g}: "
                             "no reference", t0)
                    continue
                try:
                    ref = solve(**kw, grid_points=n, domain_length=(Lx * L, Ly * L)).summary()
                except InputError as exc:  # too large for the machine
                    row["status"] = "reference refused: " + str(exc)[:60]
                    rows.append(row)
                    continue
                err = _sphere_change(r.summary(), ref, _SPHERE_COVERED)
                row |= {"true_error": err, "bounded": bool(err <= r.error_estimate),
                        "status": "ok"}
                row |= {"error_" + k: _sphere_change(r.summary(), ref, (k,))
                        for k in _SPHERE_COVERED}
                rows.append(row)
                progress(len(rows), total, f"sphere fitted {name} mu {mu:g} tol {tol:g} V={V:g}: "
                         f"{err:.1e} / {r.error_estimate:.1e}", t0)
    keys = dict.fromkeys(k for row in rows for k in row)  # refused rows: the columns as nan
    rows = [dict.fromkeys(keys, math.nan) | row for row in rows]
    table(rows, out / ("viscoelastic_sphere_fitted.csv" if not films else
                       f"viscoelastic_sphere_fitted_{'_'.join(films)}.csv"),
          "Viscoelastic sphere (F = 1 N): automatic solve (edge structure fitted where "
          "edges_fitted) against 4x the cells per axis on its period (radius, centroid, d, p_max)")
    return rows


STIFF_FILMS = (("E1=3Einf", ((3 * E_INF, TAU),)), ("E1=10Einf", ((10 * E_INF, TAU),)))
TAN01 = ((sls_for_peak_loss(0.1) * E_INF, TAU),)  # the claim part's SLS: peak loss tangent 0.1
SPHERE_FILMS = (("SLS", SLS), ("tan0.1", TAN01)) + STIFF_FILMS  # sphere_beyond_cost's names
_BEYOND_SPEEDS = (1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2)
_BEYOND_TIMEOUT = 300.0  # s per (elastic, viscoelastic) timed pair; past it: a "timeout" row


def _in_child(fn, timeout: float):
    """``fn()`` in a forked child, its value back, or ("timeout", seconds) when it runs past
    ``timeout`` (the child is ended: it is this process's own)."""
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    q = ctx.Queue()

    def target():
        try:
            q.put(("ok", fn()))
        except (InputError, ConvergenceError) as exc:
            q.put(("refused", type(exc).__name__ + ": " + str(exc).splitlines()[0][:100]))

    child = ctx.Process(target=target)
    child.start()
    t = time.perf_counter()
    try:
        out = q.get(timeout=timeout)
    except Exception:  # queue.Empty: still running
        out = ("timeout", time.perf_counter() - t)
    child.join(5.0)
    if child.is_alive():
        child.terminate()
        child.join()
    return out


def part_sphere_beyond_cost(quick: bool, out, t0, tols=None, films=None,
                            forces=(1.0,), mus=(0.0,), speeds=None) -> list[dict]:
    """The sphere's cost (F = 1 N, mu 0) beyond the fitted range (seventh session): films 4 and
    11 times stiffer when glassy (E_1 = 3, 10 E_inf, tau 10 ms) at 1e-4 ... 3e-2 m/s, tol 1e-2,
    5e-3, 1e-3, against the elastic (E_inf) sphere at the same tol: CPU times, fastest of 3
    warm interleaved runs (``viscoelastic_cost._timed_pair``), each pair in a child process
    (refused, or past _BEYOND_TIMEOUT: a row that says so).  ``forces`` [N]: the sphere's
    loads (--sphere-forces; the elastic sphere's own grid at tol 1e-3 depends on it);
    ``mus``, ``speeds``: friction coefficients and speeds [m/s] (``studies.viscoelastic_sphere``;
    default mu 0 and _BEYOND_SPEEDS); ``films`` may also name the SLS and tan0.1 (peak loss
    tangent 0.1).  ``time_ratio_glassy``: the same against the glassy film's elastic sphere
    (E_0 = E_inf + sum E_i), the limit the viscoelastic one approaches at high speed."""
    from .viscoelastic_cost import _timed_pair  # (it imports this module)
    speeds = speeds or ((1e-3, 3e-2) if quick else _BEYOND_SPEEDS)
    tols = tols or ((1e-2,) if quick else (1e-2, 5e-3, 1e-3))
    chosen = films
    films = STIFF_FILMS[:1] if quick else STIFF_FILMS
    if chosen:  # --sphere-films (also the SLS, for comparison)
        films = [f for f in SPHERE_FILMS if f[0] in chosen]
    rows, load0 = [], os.getloadavg()[0]
    n = len(films) * len(tols) * len(speeds) * len(forces) * len(mus)
    for name, prony in films:
        for tol, force, mu in ((t, f, m) for t in tols for f in forces for m in mus):
            kw = dict(indenter="sphere", force=force, mu=mu, tol=tol, **FILM)
            for V in speeds:
                row = {"film": name, "tol": tol, "force_N": force, "mu": mu, "speed_m_per_s": V}

                def pair(V=V, kw=kw, prony=prony):
                    el, r, (c_el, c_v), _ = _timed_pair(lambda: solve(**kw),
                                                        lambda: solve(speed=V, prony=prony, **kw), 3)
                    # and against the glassy film's elastic solve (E_0 = E_inf + sum E_i), the
                    # limit the viscoelastic one approaches at high speed, as lines have it
                    glassy = dict(kw, young=kw["young"] + sum(e for e, _ in prony))
                    gl, _, (c_gl, c_v2), _ = _timed_pair(
                        lambda: solve(**glassy), lambda: solve(speed=V, prony=prony, **kw), 3)
                    return {"cpu_elastic_s": c_el, "cpu_visco_s": c_v, "time_ratio": c_v / c_el,
                            "time_ratio_glassy": c_v2 / c_gl,
                            "grid_x": r.grid_points[0], "grid_y": r.grid_points[1],
                            "grid_x_elastic": el.grid_points[0],
                            "grid_x_glassy": gl.grid_points[0],
                            "error_estimate": r.error_estimate,
                            "error_estimate_elastic": el.error_estimate,
                            "fft_pairs_ratio": r.counters["transforms"] / el.counters["transforms"]}
                t = time.perf_counter()
                status, value = _in_child(pair, _BEYOND_TIMEOUT)
                row["wall_s"] = time.perf_counter() - t
                row |= value if status == "ok" else {"status": value if status == "refused"
                                                     else f"timeout after {value:.0f} s"}
                row.setdefault("status", "ok")
                rows.append(row)
                progress(len(rows), n, f"{name} tol {tol:g} F {force:g} mu {mu:g} V={V:g}: "
                         f"{row['status'][:40]} "
                         f"{row.get('time_ratio', math.nan):.2f}x (glassy "
                         f"{row.get('time_ratio_glassy', math.nan):.2f}x)", t0)
    keys = dict.fromkeys(k for row in rows for k in row)
    rows = [dict.fromkeys(keys, math.nan) | row for row in rows]
    tag = ("" if tols == (1e-2, 5e-3, 1e-3) else "_tol" + "_".join(f"{t:g}" for t in tols)) + \
        ("_" + "_".join(chosen) if chosen else "") + \
        ("" if tuple(forces) == (1.0,) else "_F" + "_".join(f"{f:g}" for f in forces)) + \
        ("" if tuple(mus) == (0.0,) else "_mu" + "_".join(f"{m:g}" for m in mus)) + \
        ("" if tuple(speeds) in (_BEYOND_SPEEDS, (1e-3, 3e-2)) else
         "_V" + "_".join(f"{v:g}" for v in speeds))
    table(rows, out / f"viscoelastic_sphere_beyond_cost{tag}.csv",
          f"Viscoelastic sphere (F = {', '.join(f'{f:g}' for f in forces)} N, mu "
          f"{', '.join(f'{m:g}' for m in mus)}) on the films "
          f"{', '.join(name for name, _ in films)} (tau 10 ms) "
          f"against the elastic one (E_inf; time_ratio_glassy: against the glassy film's, "
          f"E_0), CPU time ratio (fastest of 3 warm interleaved runs); "
          f"load average {load0:.1f} -> {os.getloadavg()[0]:.1f}")
    return rows


def part_estimate(quick: bool, out, t0) -> list[dict]:
    speeds = (1e-4, 1e-2, 1.0) if quick else (1e-6, 1e-5, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1,
                                              1.0, 10.0)
    cases = ((1e-3, 0.0),) if quick else ((1e-3, 0.0), (1e-3, 1.0), (1e-4, 0.0))
    rows = []
    n = len(speeds) * len(cases)
    for tol, mu in cases:
        nref = 2**18 if quick else 2**20 if tol >= 1e-3 else 2**21
        for V in speeds:
            s = Scene(load=200.0, mu=mu, speed=V, prony=SLS, **FILM)
            r = solve_fft(s, tol=tol)
            ref = solve_fft(s, tol=tol, grid_points=nref, domain_length=2 * r.domain_length)
            a = ref.half_width
            errs = [abs(r.half_width - a) / a, abs(r.center - ref.center) / a,
                    abs(r.indentation - ref.indentation) / ref.indentation,
                    abs(r.max_pressure - ref.max_pressure) / ref.max_pressure,
                    abs(r.info["pressure_centroid"] - ref.info["pressure_centroid"]) / a]
            err = max(errs)
            rows.append({"tol": tol, "mu": mu, "speed_m_per_s": V,
                         "V_tau_over_h": V * TAU / FILM["thickness"],
                         "error_estimate": r.error_estimate, "true_error": err,
                         "ratio": err / r.error_estimate, "bounded": bool(err <= r.error_estimate),
                         "reference_estimate": ref.error_estimate,
                         "grid_points": r.grid_points, "period_h": r.domain_length})
            progress(len(rows), n, f"tol {tol:g} mu {mu:g} V={V:.0e}", t0)
    table(rows, out / "viscoelastic_estimate.csv",
          "Error estimate against the true error (reference: 2^20 points (tol 1e-3), 2^21 (tol "
          "1e-4) over twice the period), paper's load, SLS E1 = E_inf, tau = 10 ms")
    return rows


def part_edge_layer(quick: bool, out, t0) -> list[dict]:
    speeds = (1e-3,) if quick else (1e-4, 10 ** -3.5, 1e-3, 10 ** -2.5, 1e-2, 10 ** -1.5)
    scenes = [("paper", 200.0, 2.0)] + [(f"aH/h={s:g}", load_for(s), 0.0)
                                        for s in ((1.0,) if quick else (0.1, 1.0, 3.0))]
    tol = 1e-4
    rows = []
    n = len(speeds) * len(scenes)
    for name, load, mu in scenes:
        el = solve(load=load, mu=mu, tol=tol, **FILM)
        for V in speeds:
            kw = dict(load=load, mu=mu, speed=V, prony=SLS, tol=tol, **FILM)
            r = solve(**kw)
            L = r.domain_length * FILM["thickness"]
            ref = solve(**kw, grid_points=2**18 if quick else 2**20, domain_length=2 * L)
            width = V * TAU / FILM["thickness"]  # V tau [h]
            n1 = max(512, 2 ** round(math.log2(r.domain_length / width)))  # ~1 cell across
            one = solve(**kw, grid_points=n1, domain_length=L)
            a = ref.half_width
            err = _line_change(r, ref)
            rows.append({
                "scene": name, "speed_m_per_s": V, "V_tau_over_h": width,
                "path": "slow" if "slow_sliding" in r.info else "full",
                "grid_points": r.grid_points, "grid_points_elastic": el.grid_points,
                "error_estimate": r.error_estimate, "true_error": err,
                "ratio": err / r.error_estimate, "bounded": bool(err <= r.error_estimate),
                "one_cell_points": n1, "one_cell_V_tau_cells": width * n1 / r.domain_length,
                "one_cell_a_error": abs(one.half_width - a) / a,
                "one_cell_center_error": abs(one.center - ref.center) / a,
                "one_cell_change": _line_change(one, ref)})
            progress(len(rows), n, f"{name} V={V:.1e}: est {r.error_estimate:.1e}, true "
                     f"{err:.1e}, N {r.grid_points} (elastic {el.grid_points})", t0)
    table(rows, out / "viscoelastic_edge_layer.csv",
          f"trailing edges fitted with their inner layer: estimate against the true error "
          f"(reference {2**18 if quick else 2**20} points over twice the period), tol {tol:g}, "
          f"SLS E1 = E_inf, tau = 10 ms")
    return rows


def part_edge_range(quick: bool, out, t0) -> list[dict]:
    films = {"E1=3Einf": ((3 * E_INF, TAU),), "E1=10Einf": ((10 * E_INF, TAU),),
             "two terms": TWO_TERMS}
    scenes = [("aH/h=1", load_for(1.0), 0.0), ("paper", 200.0, 2.0), ("aH/h=0.3", load_for(0.3), 0.5)]
    speeds = (1e-3,) if quick else (1e-4, 10 ** -3.5, 1e-3, 10 ** -2.5, 1e-2, 10 ** -1.5)
    tols = (1e-3,) if quick else (1e-4, 1e-3)
    rows = _against_references(films, scenes, speeds, tols, quick, t0)
    table(rows, out / "viscoelastic_edge_range.csv",
          "the trailing-edge layer fit's range: stiffer films (resolved) and two terms (fitted), "
          "estimate against the true error (2^20 points over twice the period)")
    return rows


HEAVY_FILMS = {"E1=3Einf": ((3 * E_INF, TAU),), "E1=10Einf": ((10 * E_INF, TAU),),
               "three terms": ((3 * E_INF, 1e-3), (3 * E_INF, TAU), (3 * E_INF, 0.1))}


def _against_reference(kw, quick: bool, row: dict):
    """(the automatic line solve of ``kw``, its reference on 2^20 points (2^18 with --quick)
    over twice its period), or (None, None) with ``row["failed"]`` saying why."""
    try:
        r = solve(**kw)
        return r, solve(**kw, grid_points=2**18 if quick else 2**20,
                        domain_length=2 * r.domain_length * FILM["thickness"])
    except (ConvergenceError, InputError) as exc:
        row["failed"] = f"{type(exc).__name__}: {exc}"[:120]
        return None, None


def _against_references(films, scenes, speeds, tols, quick: bool, t0, carrier=False) -> list:
    """The rows of edge_range and heavy_terms: every (tol, film, scene, speed), the automatic
    line solve's estimate against its error from ``_against_reference`` (a failure is a row,
    not a stop); ``carrier``: also which measure carries the error."""
    names = ("a", "x_c", "d", "p_max", "centroid")
    rows = []
    n = len(films) * len(scenes) * len(speeds) * len(tols)
    for tol in tols:
        for fname, prony in films.items():
            for name, load, mu in scenes:
                for V in speeds:
                    kw = dict(load=load, mu=mu, speed=V, prony=prony, tol=tol, **FILM)
                    row = {"tol": tol, "film": fname, "scene": name, "speed_m_per_s": V,
                           "path": "", "edge_structure_resolved": False, "grid_points": 0,
                           "error_estimate": math.nan, "true_error": math.nan,
                           **({"carrier": ""} if carrier else {}), "bounded": False,
                           "failed": ""}
                    r, ref = _against_reference(kw, quick, row)
                    if r is None:  # a row, not a stop
                        rows.append(row)
                        progress(len(rows), n, f"{fname} {name} V={V:.1e}: {row['failed'][:40]}", t0)
                        continue
                    errs = _line_changes(r, ref)
                    err = max(errs)
                    row.update({
                        "path": "slow" if "slow_sliding" in r.info else "full",
                        "edge_structure_resolved": bool(r.info.get("edge_structure_resolved")),
                        "grid_points": r.grid_points, "error_estimate": r.error_estimate,
                        "true_error": err, "bounded": bool(err <= r.error_estimate)})
                    if carrier:
                        row["carrier"] = names[errs.index(err)]
                    rows.append(row)
                    progress(len(rows), n, f"tol {tol:g} {fname} {name} V={V:.1e}: est "
                             f"{r.error_estimate:.1e} true {err:.1e}"
                             + (f" ({row['carrier']}), N {r.grid_points}" if carrier else ""), t0)
    return rows


def _weights_suffix(weights) -> str:
    """'_w30_100' for --heavy-weights 30,100; '' without it (the default tables' names)."""
    return "_w" + "_".join(f"{w:g}" for w in weights) if weights else ""


def part_heavy_terms(quick: bool, out, t0, weights=None) -> list[dict]:
    """Seventh session: Prony terms up to E_i/E_inf = 10 left to the edge fits (the layer fit
    of the trailing edge, the odd-even peak): the automatic solve's estimate against its error
    (2^20 points over twice its period; 2^18 with --quick), and which measure carries it.
    ``weights`` (--heavy-weights, ninth session): single terms E_1 = w E_inf instead of
    HEAVY_FILMS."""
    scenes = [("aH/h=0.1", load_for(0.1), 0.0), ("aH/h=3", load_for(3.0), 0.0),
              ("aH/h=1 mu0.5", load_for(1.0), 0.5), ("paper", 200.0, 2.0)]
    speeds = (1e-4,) if quick else (1e-5, 1e-4, 1e-3, 1e-2, 0.1, 1.0)
    tols = (1e-3,) if quick else (1e-4, 1e-3)
    films = dict(list(HEAVY_FILMS.items())[1:2]) if quick else HEAVY_FILMS
    if weights:
        films = {f"E1={w:g}Einf": ((w * E_INF, TAU),) for w in weights}
    if quick:
        scenes = scenes[3:]
    rows = _against_references(films, scenes, speeds, tols, quick, t0, carrier=True)
    table(rows, out / f"viscoelastic_heavy_terms{_weights_suffix(weights)}.csv",
          f"Prony terms {', '.join(films)} left to the edge fits: estimate against the true "
          f"error (2^20 points over twice the period)")
    return rows


def _offset_reference(kw, L, quick: bool, weights):
    """heavy_offset's reference: 2^19 points on the period L (2^17 with --quick); with
    --heavy-weights, where that active set does not settle, 2^20 then 2^18 points (ninth
    session: E_1 = 30 E_inf, the paper's scene at 5e-5 m/s on 2^19 points cycles).
    (solution, its points), or (None, 0)."""
    for n_ref in ((2**17 if quick else 2**19),) + (() if not weights else (2**20, 2**18)):
        try:
            return solve(**kw, grid_points=n_ref, domain_length=L), n_ref
        except ConvergenceError:
            if not weights:
                raise
    return None, 0


def _offset_failed(name, w, V, N, n_ref, why) -> dict:
    """heavy_offset's row (--heavy-weights) for a solve that did not settle."""
    nan = math.nan
    return {"scene": name, "w": w, "speed_m_per_s": V, "V_tau_over_dx": nan, "l_over_dx": nan,
            "delta_over_a": nan, "grid_points": N, "trailing_offset_over_delta": nan,
            "leading_offset_over_delta": nan, "offsets_sum_over_delta": nan,
            "bound_over_delta": nan, "a_error": nan, "center_error": nan, "pmax_error": nan,
            "reference_points": n_ref, "failed": why}


def part_heavy_offset(quick: bool, out, t0, weights=None) -> list[dict]:
    """Seventh session: what a fixed grid leaves when |V| tau is below a cell (the measures of
    ``_LineSolve.LAYER_OFFSET``): single terms E_1 = 1, 3, 10 E_inf on a_H/h 0.3 (mu 0) and the
    paper's scene (mu 2) at 2.5e-5 ... 2e-4 m/s, on 2048 ... 16384 points over the elastic
    solve's period, against 2^19 points on that period: the edges' offsets over the term's
    shift delta = (E_1/E_inf) V tau, against |V| tau/dx and the retardation length l/dx, the
    bound LAYER_OFFSET min(1, dx/l) of their sum (a and x_c move by half of it each, relative
    to a: ``_LineSolve.layer_bias``), and p_max.  ``weights`` (--heavy-weights, ninth
    session): these weights E_1/E_inf instead."""
    from spectral_contact.solvers.fft import _LineSolve
    films = (10.0,) if quick else (1.0, 3.0, 10.0)
    if weights:
        films = tuple(weights)
    scenes = [("paper", 200.0, 2.0)] + ([] if quick else [("aH/h=0.3", load_for(0.3), 0.0)])
    speeds = (1e-4,) if quick else (2.5e-5, 5e-5, 1e-4, 2e-4)
    grids = (2048, 4096) if quick else (2048, 4096, 8192, 16384)
    h = FILM["thickness"]
    rows = []
    n = len(films) * len(scenes) * len(speeds)
    for name, load, mu in scenes:
        el = solve(load=load, mu=mu, tol=1e-4, **FILM)
        L = el.domain_length * h
        for w in films:
            for V in speeds:
                kw = dict(load=load, mu=mu, speed=V, prony=((w * E_INF, TAU),), **FILM)
                ref, n_ref = _offset_reference(kw, L, quick, weights)
                if ref is None:  # (--heavy-weights: no reference settles; rows that say so)
                    rows += [_offset_failed(name, w, V, N, 0, "no reference settled")
                             for N in grids]
                    progress(len(rows) // len(grids), n, f"{name} w={w:g} V={V:.1e}: no ref", t0)
                    continue
                lam, a = V * TAU / h, ref.half_width
                delta = w * lam
                trail0, lead0 = ref.center - a, ref.center + a
                for N in grids:
                    try:
                        r = solve(**kw, grid_points=N, domain_length=L)
                    except ConvergenceError as exc:
                        if not weights:
                            raise
                        rows.append(_offset_failed(name, w, V, N, n_ref, f"{exc}"[:80]))
                        continue
                    dx = el.domain_length / N
                    lr = (1.0 + w) * lam
                    rows.append({
                        "scene": name, "w": w, "speed_m_per_s": V, "V_tau_over_dx": lam / dx,
                        "l_over_dx": lr / dx, "delta_over_a": delta / a, "grid_points": N,
                        "trailing_offset_over_delta": (r.center - r.half_width - trail0) / delta,
                        "leading_offset_over_delta": (r.center + r.half_width - lead0) / delta,
                        "offsets_sum_over_delta": (abs(r.center - r.half_width - trail0)
                                                   + abs(r.center + r.half_width - lead0))
                        / delta,
                        "bound_over_delta": _LineSolve.layer_offset(lr / dx)
                        if lam < _LineSolve.LAYER_CELLS * dx else 0.0,
                        "a_error": abs(r.half_width - a) / a,
                        "center_error": abs(r.center - ref.center) / a,
                        "pmax_error": abs(r.max_pressure - ref.max_pressure) / ref.max_pressure,
                        **({"reference_points": n_ref, "failed": ""} if weights else {})})
                progress(len(rows) // len(grids), n, f"{name} w={w:g} V={V:.1e}", t0)
    table(rows, out / f"viscoelastic_heavy_offset{_weights_suffix(weights)}.csv",
          "fixed grids against 2^19 points on the elastic period: the edges' offsets over the "
          "term's shift delta while V tau is below a cell (trailing positive = inward)")
    return rows


OFFSET_SCENES = {"aH/h=0.1": (0.1, 0.0), "aH/h=0.1 mu0.5": (0.1, 0.5), "aH/h=0.3": (0.3, 0.0),
                 "aH/h=0.3 mu0.5": (0.3, 0.5), "aH/h=1": (1.0, 0.0), "aH/h=1 mu0.5": (1.0, 0.5),
                 "aH/h=3": (3.0, 0.0), "aH/h=3 mu0.5": (3.0, 0.5), "paper": (None, 2.0)}
# l/dx on the coarsest grid (finer grids: 1/2, 1/4, 1/8 of it)
OFFSET_CELLS = (0.001, 0.003, 0.01, 0.03, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8, 4.0, 5.6,
                8.0)
OFFSET_BASE_CELLS = 1e-5  # the baseline's l/dx on each grid (the fits' own noise, cancelled)
OFFSET_RESOLVED = 8.0  # the reference's l/dx from which it is taken over the slow theory


def _offset_scene(name):
    """(load, mu) of an offset part's scene (``OFFSET_SCENES``)."""
    aH, mu = OFFSET_SCENES[name]
    return (200.0 if aH is None else load_for(aH)), mu


def _edge_pair(r):
    return r.center - r.half_width, r.center + r.half_width


def _layer_change(r, b, ref, ref0, delta, delta0) -> tuple:
    """(trailing, leading) offset over delta of the fixed grid's edges ``r`` as a change from
    its baseline ``b`` (the same grid and period at OFFSET_BASE_CELLS: the fits' own sub-cell
    noise cancels), against the same change of the reference (``ref``, ``ref0``) or, where
    ``ref`` is None, of the slow-sliding theory (the trailing edge in by delta, the leading
    one unchanged: ``ViscoelasticFilm.slow_shift``).  Positive: moved toward +x."""
    (t, ld), (t0, l0) = _edge_pair(r), _edge_pair(b)
    if ref is None:
        true_t, true_l = delta - delta0, 0.0
    else:
        (rt, rl), (rt0, rl0) = _edge_pair(ref), _edge_pair(ref0)
        true_t, true_l = rt - rt0, rl - rl0
    return ((t - t0) - true_t) / delta, ((ld - l0) - true_l) / delta


def part_offset_range(quick: bool, out, t0, weights=None, scenes=None) -> list[dict]:
    """Tenth session: the fitted edges' offsets from far below a cell to a few cells (the
    measures of ``_LineSolve.layer_offset``): single terms E_1 = 3, 10 E_inf (``weights``:
    --heavy-weights) on ``OFFSET_SCENES``, at the speeds giving l/dx = ``OFFSET_CELLS`` on the
    coarsest of four fixed grids (the elastic solve's at tol 1e-4 and 2, 4, 8 times it; three
    grids up to it where it has more than 8192 points) over the elastic solve's period, each
    as a change from a baseline at l/dx = OFFSET_BASE_CELLS on the same grid (``_layer_change``),
    against 2^19 points on the period (2^21 where the elastic grid has more than 8192 points)
    where those resolve l (l/dx there >= OFFSET_RESOLVED), else the slow-sliding theory
    (``ref_vs_slow``: the two where both are computed); also the raw a, x_c errors against the
    reference, as the seventh session's heavy_offset.  ``scenes`` (--offset-scenes): some of
    ``OFFSET_SCENES`` alone (their table gets their names' suffix)."""
    from spectral_contact.solvers.fft import _LineSolve
    films = tuple(weights) if weights else ((10.0,) if quick else (3.0, 10.0))
    names = scenes or (["paper", "aH/h=1"] if quick else list(OFFSET_SCENES))
    cells = (0.01, 0.3, 2.0) if quick else OFFSET_CELLS
    h = FILM["thickness"]
    rows = []
    n = len(films) * len(names) * len(cells)
    for name in names:
        load, mu = _offset_scene(name)
        el = solve(load=load, mu=mu, tol=1e-4, **FILM)
        L, N_el = el.domain_length * h, el.grid_points
        grids = ([N_el, 2 * N_el, 4 * N_el, 8 * N_el] if N_el <= 8192
                 else [N_el // 4, N_el // 2, N_el])
        if quick:
            grids = grids[:2]
        n_ref = (2**17 if quick else 2**19) if N_el <= 8192 else (2**19 if quick else 2**21)
        for w in films:
            def kw(V, w=w):
                return dict(load=load, mu=mu, speed=V, prony=((w * E_INF, TAU),), **FILM)

            def speed(x, w=w):  # V for l/dx = x on the coarsest grid
                return x * el.domain_length / grids[0] * h / ((1.0 + w) * TAU)
            V0 = speed(OFFSET_BASE_CELLS)
            ref0 = solve(**kw(V0), grid_points=n_ref, domain_length=L)
            base = {N: solve(**kw(V0), grid_points=N, domain_length=L) for N in grids}
            for x in cells:
                V = speed(x)
                lam = V * TAU / h
                delta, delta0, lr = w * lam, w * V0 * TAU / h, (1.0 + w) * lam
                try:
                    ref = solve(**kw(V), grid_points=n_ref, domain_length=L)
                except ConvergenceError:
                    ref = None
                resolved = ref is not None and lr / (el.domain_length / n_ref) >= OFFSET_RESOLVED
                for N in grids:
                    dx = el.domain_length / N
                    try:
                        r = solve(**kw(V), grid_points=N, domain_length=L)
                    except ConvergenceError as exc:
                        rows.append({"scene": name, "w": w, "speed_m_per_s": V, "grid_points": N,
                                     "failed": f"{exc}"[:80]})
                        continue
                    tr, ld = _layer_change(r, base[N], ref if resolved else None, ref0, delta,
                                           delta0)
                    slow = (_layer_change(r, base[N], None, ref0, delta, delta0)[0]
                            if ref is not None else math.nan)
                    total = abs(tr) + abs(ld)
                    bound = _LineSolve.layer_offset(lr / dx) if lam < _LineSolve.LAYER_CELLS * dx \
                        else 0.0
                    rows.append({
                        "scene": name, "w": w, "speed_m_per_s": V, "grid_points": N,
                        "V_tau_over_dx": lam / dx, "l_over_dx": lr / dx, "delta_over_dx": delta / dx,
                        "delta_over_a": delta / el.half_width,
                        "reference": "resolved" if resolved else "slow theory",
                        "trailing_offset_over_delta": tr, "leading_offset_over_delta": ld,
                        "offsets_sum_over_delta": total,
                        "trailing_resolved_minus_slow": (tr - slow) if resolved else math.nan,
                        "bound_over_delta": bound,
                        "old_bound_over_delta": _LineSolve.LAYER_OFFSET * min(1.0, dx / lr)
                        if lam < dx else 0.0,
                        "within": bool(total <= bound) if bound else True,
                        "a_error_raw": (abs(r.half_width - ref.half_width) / ref.half_width
                                        if ref is not None else math.nan),
                        "center_error_raw": (abs(r.center - ref.center) / ref.half_width
                                             if ref is not None else math.nan),
                        "failed": ""})
                progress(len(rows) // len(grids), n, f"{name} w={w:g} l/dx={x:g}", t0)
    full = max(rows, key=len)  # (a failed row: the others' columns, nan)
    rows = [{**{k: math.nan for k in full}, **r} for r in rows]
    suffix = _weights_suffix(weights) + ("_" + "_".join(
        n.replace("aH/h=", "aH").replace(" ", "") for n in scenes) if scenes else "")
    table(rows, out / f"viscoelastic_offset_range{suffix}.csv",
          "the fitted edges' offsets over delta, as changes from l/dx 1e-5 on the same grid, "
          "against 2^19-2^21 points (resolved) or the slow-sliding theory; bound: "
          "_LineSolve.layer_offset (tenth session), old: 0.1 min(1, dx/l)")
    return rows


def part_offset_phase(quick: bool, out, t0) -> list[dict]:
    """Tenth session: the offsets against the edge's phase in its cell at fixed l/dx: the
    period of the fixed grid stretched by up to one cell at the trailing edge (16 periods; 4
    with --quick), each solve as a change from its baseline (``_layer_change``) against one
    2^19-point solve at the elastic period (the slow theory below l/dx 0.05); per (scene, w,
    N, l/dx) the range over the phases, the largest sum against ``layer_offset``."""
    from spectral_contact.solvers.fft import _LineSolve
    cases = [("aH/h=1", 10.0, 4096, (0.01, 0.1, 0.2, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8, 4.0,
                                     5.6, 8.0, 11.0)),
             ("paper", 10.0, 2048, (0.01, 0.1, 0.2, 0.5, 1.0, 1.4, 2.0, 2.8, 4.0, 5.6, 8.0, 11.0)),
             ("aH/h=0.3", 3.0, 4096, (0.01, 0.1, 0.2, 0.5, 1.0, 1.4, 2.0, 2.8, 3.5)),
             ("aH/h=1 mu0.5", 10.0, 4096, (0.01, 0.2, 1.0, 1.4, 2.0, 2.8, 4.0, 5.6, 8.0, 11.0)),
             ("aH/h=3", 10.0, 2048, (0.01, 0.2, 1.0, 1.4, 2.0, 2.8, 4.0, 5.6, 8.0, 11.0))]
    K = 4 if quick else 16
    if quick:
        cases = [("aH/h=1", 10.0, 4096, (0.01, 2.0))]
    h = FILM["thickness"]
    rows = []
    n = sum(len(c[3]) for c in cases)
    for name, w, N, xs in cases:
        load, mu = _offset_scene(name)
        el = solve(load=load, mu=mu, tol=1e-4, **FILM)
        L0 = el.domain_length
        sweep = L0 / abs(el.center - el.half_width)  # one cell at the trailing edge

        def kw(V, L, n, w=w):
            return dict(load=load, mu=mu, speed=V, prony=((w * E_INF, TAU),), grid_points=n,
                        domain_length=L * h, **FILM)
        for x in xs:
            V = x * L0 / N * h / ((1.0 + w) * TAU)
            V0 = OFFSET_BASE_CELLS * L0 / N * h / ((1.0 + w) * TAU)
            delta, delta0 = w * V * TAU / h, w * V0 * TAU / h
            ref = ref0 = None
            if x >= 0.05:
                n_ref = 2**17 if quick else 2**19
                ref, ref0 = solve(**kw(V, L0, n_ref)), solve(**kw(V0, L0, n_ref))
            trs, lds = [], []
            for k in range(K):
                L = L0 * (1.0 + k / K * sweep / N)
                tr, ld = _layer_change(solve(**kw(V, L, N)), solve(**kw(V0, L, N)), ref, ref0,
                                       delta, delta0)
                trs.append(tr)
                lds.append(ld)
            trs, lds = np.array(trs), np.array(lds)
            total = np.abs(trs) + np.abs(lds)
            bound = _LineSolve.layer_offset(x) if x < 1.0 + w else 0.0
            rows.append({"scene": name, "w": w, "grid_points": N, "l_over_dx": x, "phases": K,
                         "trailing_min": float(trs.min()), "trailing_max": float(trs.max()),
                         "leading_min": float(lds.min()), "leading_max": float(lds.max()),
                         "sum_max": float(total.max()), "sum_mean": float(total.mean()),
                         "x_c_max": float(np.abs(trs + lds).max() / 2),
                         "a_max": float(np.abs(trs - lds).max() / 2),
                         "bound": bound, "old_bound": 0.1 * min(1.0, 1.0 / x),
                         "within": bool(total.max() <= bound) if bound else True})
            progress(len(rows), n, f"{name} w={w:g} l/dx={x:g}: sum max {total.max():.3f}", t0)
    table(rows, out / "viscoelastic_offset_phase.csv",
          "the fitted edges' offsets over delta against the edge's phase (the period swept by "
          "one cell at the trailing edge): ranges over the phases, the largest sum against "
          "_LineSolve.layer_offset (tenth session)")
    return rows


TWO_TERMS = ((E_INF, 1e-3), (E_INF, 0.1))  # a short and a long tail together (tau_r 5.2 ms, 0.39 s)
STIFF = ((10.0 * E_INF, TAU),)  # E_0 = 11 E_inf: tau_r = 0.11 s


def _line_change(r, ref) -> float:
    """Largest relative change of a, x_c, d, p_max and the pressure centroid from ``ref`` to
    ``r`` (lengths over ref's half-width, d and p_max over themselves): the estimate's."""
    return max(_line_changes(r, ref))


def _line_changes(r, ref) -> list:
    """The relative changes of ``_line_change``, [a, x_c, d, p_max, centroid]."""
    a = ref.half_width
    return [abs(r.half_width - a) / a, abs(r.center - ref.center) / a,
            abs(r.indentation - ref.indentation) / ref.indentation,
            abs(r.max_pressure - ref.max_pressure) / ref.max_pressure,
            abs(r.info["pressure_centroid"] - ref.info["pressure_centroid"]) / a]


def part_images(quick: bool, out, t0) -> list[dict]:
    """The periodic images of full-path line solves against the bound the estimate now uses
    where the film's far field is bounded (``ViscoelasticFilm.image_factor``: every tail short
    or summed) and the contact frictionless; else measured on twice the period, as before
    (column ``images``): period_difference is the fixed grid of the solve (N on L) against 2N
    on 2L (same cells, same path: the images alone)."""
    speeds = (1e-3, 1e-2, 1.0) if quick else tuple(float(v) for v in np.logspace(-6, 1, 15))
    scenes = [("paper", 200.0, 2.0, 1.0, SLS, 1e-3), ("paper mirrored", 200.0, -2.0, -1.0, SLS, 1e-3),
              ("paper two terms", 200.0, 2.0, 1.0, TWO_TERMS, 1e-3),
              ("paper tol 1e-4", 200.0, 2.0, 1.0, SLS, 1e-4)]
    scenes += [(f"aH/h={s_:g}", load_for(s_), 0.0, 1.0, SLS, 1e-3) for s_ in
               ((0.1,) if quick else (0.1, 1.0, 3.0))]
    if not quick:  # frictionless (the bound's range): mirrored, two terms, tol 1e-4; glassy
        # 11 times stiffer (image factors up to ~11; measured past 12.5), also with friction
        a1 = load_for(1.0)
        scenes += [("aH/h=1 mirrored", a1, 0.0, -1.0, SLS, 1e-3),
                   ("aH/h=1 two terms", a1, 0.0, 1.0, TWO_TERMS, 1e-3),
                   ("aH/h=1 tol 1e-4", a1, 0.0, 1.0, SLS, 1e-4),
                   ("aH/h=1 E_1=10E_inf", a1, 0.0, 1.0, STIFF, 1e-3),
                   ("paper E_1=10E_inf", 200.0, 2.0, 1.0, STIFF, 1e-3)]
    if quick:
        scenes = scenes[:1] + scenes[-1:]
    rows = []
    n = len(speeds) * len(scenes)
    for name, load, mu, sign, prony, tol in scenes:
        for V in speeds:
            s = Scene(load=load, mu=mu, speed=sign * V, prony=prony, **FILM)
            try:
                r = solve_fft(s, tol=tol)
            except ConvergenceError as exc:  # not converged (the stiff film's slow paper
                # scene at tol 1e-3 stagnates): say so, no images to compare
                nan = float("nan")
                rows.append({"scene": name, "tol": tol, "mu": mu, "speed_m_per_s": sign * V,
                             "path": "not converged", "image_factor": nan, "images": "-",
                             "grid_points": 0, "period_h": nan, "image_error": nan,
                             "domain_difference": nan, "error_estimate": nan,
                             "period_difference": nan, "bounded": None})
                print(f"  {name} V={sign * V:.2e}: {exc}".splitlines()[0], file=sys.stderr)
                progress(len(rows), n, f"images {name} V={V:.1e}: not converged", t0)
                continue
            row = {"scene": name, "tol": tol, "mu": mu, "speed_m_per_s": sign * V,
                   "path": "slow" if "slow_sliding" in r.info else "full",
                   "image_factor": s.core_film().image_factor(),
                   "images": "measured" if r.info["domain_difference"] else "bounded",
                   "grid_points": r.grid_points,
                   "period_h": r.domain_length, "image_error": r.info["image_error"],
                   "domain_difference": r.info["domain_difference"],
                   "error_estimate": r.error_estimate, "period_difference": float("nan"),
                   "bounded": None}
            if row["path"] == "full":
                N, L = r.grid_points, r.domain_length
                fixed = solve_fft(s, tol=tol, grid_points=N, domain_length=L)
                far = solve_fft(s, tol=tol, grid_points=2 * N, domain_length=2 * L)
                diff = _line_change(fixed, far)
                row["period_difference"] = diff
                row["bounded"] = bool(diff <= r.info["image_error"])
            rows.append(row)
            progress(len(rows), n, f"images {name} V={V:.1e}", t0)
    table(rows, out / "viscoelastic_images.csv",
          "Periodic images of the full-path viscoelastic line solves: the fixed grid N on L "
          "against 2N on 2L (period_difference) and the estimate's image term (image_error: "
          "the elastic model x image_factor where that is known, else max(model, measured))")
    return rows


def part_reference(quick: bool, out, t0) -> list[dict]:
    """Hunter's closed form (reference.hunter, derived) against the film solver and the x-space
    collocation (a_H/h = 0.01), and the film's departure from the half-space as the tail l_r
    reaches the thickness (a_H/h = 0.01, 0.003, 0.001 at the same l_r/a)."""
    base = Scene(**FILM)
    rows = []
    cases = [(0.01, lr) for lr in ((3e-3, 3e-2) if quick else (1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.14,
                                                               1.4))]
    if not quick:
        cases += [(0.003, 0.042), (0.003, 0.42), (0.001, 0.014), (0.001, 0.14)]
    tol = 1e-3
    for ah, lr in cases:
        P = 2.0 * math.pi * ah * ah
        V = lr * FILM["thickness"] / (2.0 * TAU)  # tau_r = 2 tau
        s = Scene(load=P * base.stress_unit * base.length_unit, mu=0.0, speed=V, prony=SLS, **FILM)
        r = solve(s, tol=tol)
        h = hunter_contact(P, 0.5, lr)
        a, c = h["a"], h["c"]
        mu_h = h["centroid"] * FILM["thickness"] / FILM["radius"]
        row = {"a_H_over_h": ah, "l_r_over_h": lr, "l_r_over_a": lr / a, "speed_m_per_s": V,
               "a_hunter_h": a, "x_c_hunter_h": c, "mu_def_hunter": mu_h,
               "da_over_a": (r.half_width - a) / a, "dxc_over_xc": (r.center - c) / c,
               "dxc_over_a": (r.center - c) / a,
               "dmu_over_mu": (r.deformation_friction - mu_h) / mu_h,
               "error_estimate": r.error_estimate, "grid_points": r.grid_points,
               "slow_sliding": "slow_sliding" in r.info}
        row.update(dict.fromkeys(("colloc_da_over_a", "colloc_dxc_over_a", "colloc_dmu_over_mu",
                                  "colloc_dx_over_a"), float("nan")))
        if ah == 0.01 and lr <= 0.14:  # the collocation against the closed form
            o = sls_halfspace_contact(P, 0.5, lr, n=700 if quick else 1500)
            row.update({"colloc_da_over_a": (o["a"] - a) / a, "colloc_dxc_over_a": (o["c"] - c) / a,
                        "colloc_dmu_over_mu": (o["centroid"] - h["centroid"]) / h["centroid"],
                        "colloc_dx_over_a": o["dx"] / a})
        rows.append(row)
        progress(len(rows), len(cases), f"reference a/h = {ah:g}, l_r = {lr:g} h", t0)
    table(rows, out / "viscoelastic_reference.csv",
          f"the film (fft, tol {tol:g}) and the x-space collocation against Hunter's closed form "
          f"(SLS half-space, E_0 = 2 E_inf), lengths in h")
    return rows


def _changes(r, el) -> dict:
    a = el.half_width
    szz = np.interp(el.x, r.x, r.base_sigma_zz, period=r.domain_length)
    sxz = np.interp(el.x, r.x, r.base_sigma_xz, period=r.domain_length)
    return {"d_a": abs(r.half_width / a - 1.0), "d_x0": abs(r.x0 - el.x0) / a,
            # Q/P = mu + mu_def on both films (one definition: ContactResult.Q_over_P)
            "d_Q_over_P": abs(r.Q_over_P / el.Q_over_P - 1.0),
            "d_base_zz": float(np.max(np.abs(szz - el.base_sigma_zz)) / np.max(np.abs(el.base_sigma_zz))),
            "d_base_xz": float(np.max(np.abs(sxz - el.base_sigma_xz)) / np.max(np.abs(el.base_sigma_xz)))}


def part_claim(quick: bool, out, t0):
    w = sls_for_peak_loss(0.1)
    tau = 1.0  # s: results depend on V tau / h only
    el = solve(load=200.0, mu=2.0, tol=1e-4, **FILM)
    ells = np.logspace(-5, 1, 7 if quick else 25)
    rows = []
    for ell in ells:
        V = ell * FILM["thickness"] / tau
        r = solve(load=200.0, mu=2.0, speed=float(V), prony=((w * E_INF, tau),), tol=1e-4, **FILM)
        ch = _changes(r, el)
        rows.append({"V_tau_over_h": float(ell), **ch, "max_change": max(ch.values()),
                     "deformation_friction": r.deformation_friction,
                     "error_estimate": r.error_estimate})
        progress(len(rows), len(ells), f"claim V tau/h = {ell:.1e}", t0)
    table(rows, out / "viscoelastic_claim.csv",
          f"Paper's scene (P_L 200 N/m, mu 2): SLS with peak loss tangent 0.1 (E1 = {w:.4f} E_inf)"
          f" against the elastic E_inf film: relative changes against V tau / h")
    # the first V tau/h where the largest change exceeds 1 % (log interpolation)
    m = np.array([r_["max_change"] for r_ in rows])
    k = int(np.argmax(m > 0.01)) if np.any(m > 0.01) else None
    ell1 = None
    if k:
        x0_, x1_ = math.log(ells[k - 1]), math.log(ells[k])
        y0_, y1_ = math.log(m[k - 1]), math.log(m[k])
        ell1 = math.exp(x0_ + (math.log(0.01) - y0_) * (x1_ - x0_) / (y1_ - y0_))
    speeds = []
    if ell1 is not None:
        for f_peak in (1.0, 10.0, 100.0, 1000.0):
            # SLS peak at omega tau = sqrt(E_inf/E_0): tau = 1/(2 pi f sqrt(1 + w))
            tau_p = 1.0 / (2.0 * math.pi * f_peak * math.sqrt(1.0 + w))
            speeds.append({"loss_peak_Hz": f_peak, "tau_s": tau_p,
                           "V_tau_over_h_at_1pct": ell1,
                           "V_1pct_m_per_s": ell1 * FILM["thickness"] / tau_p,
                           "paper_V_max_over_V_1pct": 2e-3 / (ell1 * FILM["thickness"] / tau_p)})
        table(speeds, out / "viscoelastic_claim_speeds.csv",
              "The speed above which a, x0, Q/P or the base stresses change by > 1 % (SLS, peak "
              "loss tangent 0.1 at loss_peak_Hz), against the paper's V = 0.2 - 2 mm/s")
    return rows, speeds


def figure(speed_rows, claim_rows, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from spectral_contact.instruments.mems_view import sensor

    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    for name in dict.fromkeys(r["scene"] for r in speed_rows):
        rr = [r for r in speed_rows if r["scene"] == name and r["status"] == "ok"]
        V = [r["speed_m_per_s"] for r in rr]
        ax[0, 0].loglog(V, [max(r["deformation_friction"], 1e-12) for r in rr], "o-", ms=3, label=name)
        ax[0, 1].semilogx(V, [r["a_over_a_elastic"] for r in rr], "o-", ms=3, label=name)
    ax[0, 0].set(xlabel="V [m/s]", ylabel="mu_def", title="deformation friction (SLS, tau 10 ms)")
    ax[0, 1].set(xlabel="V [m/s]", ylabel="a / a(E_inf)", title="half-width")
    ax[0, 0].legend(fontsize=7)
    ells = [r["V_tau_over_h"] for r in claim_rows]
    for k in ("d_a", "d_x0", "d_Q_over_P", "d_base_zz", "d_base_xz"):
        ax[1, 0].loglog(ells, [max(r[k], 1e-9) for r in claim_rows], "o-", ms=3, label=k)
    ax[1, 0].axhline(0.01, color="k", lw=0.8, ls="--")
    ax[1, 0].set(xlabel="V tau / h", ylabel="relative change", title="peak tan delta 0.1 vs elastic")
    ax[1, 0].legend(fontsize=7)
    r = solve(load=200.0, mu=2.0, speed=0.05, prony=SLS, tol=1e-3, **FILM)
    el = solve(load=200.0, mu=2.0, tol=1e-3, **FILM)
    for res, lab, ls in ((el, "elastic E_inf", "--"), (r, "SLS, V = 5 cm/s", "-")):
        v = sensor(res)
        xm = res.x_m * 1e3
        ax[1, 1].plot(xm, -res.base_sigma_zz_Pa / 1e3, ls, color="C0", label=f"-sigma_zz(0) {lab}")
        ax[1, 1].plot(xm, res.base_sigma_xz_Pa / 1e3, ls, color="C1", label=f"sigma_xz(0) {lab}")
        prof = v.profiles()
        ax[1, 1].plot(np.asarray(prof["x_m"]) * 1e3, np.asarray(prof["S_zz_Pa"]) / 1e3, ls,
                      color="C2", lw=0.8, label=f"MEMS S_zz {lab}")
    ax[1, 1].set(xlim=(-10, 10), xlabel="x [mm] from the apex (sliding toward +x)", ylabel="kPa",
                 title="base stresses and MEMS view, paper's scene")
    ax[1, 1].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(out / "viscoelastic.png", dpi=110)
    print(f"(written {out / 'viscoelastic.png'})")


def part_second(quick: bool, out, t0) -> list[dict]:
    points = [("aH/h=0.1", load_for(0.1), 0.0, (1e-4,) if quick else (3.2e-5, 1e-4, 3.2e-4))]
    if not quick:
        points += [("aH/h=1", load_for(1.0), 0.0, (3.2e-4, 1e-3, 3.2e-3)),
                   ("aH/h=3", load_for(3.0), 0.0, (3.2e-4, 1e-3, 3.2e-3)),
                   ("paper", 200.0, 2.0, (3.2e-4, 1e-3, 3.2e-3))]
    rows = []
    n = sum(len(v) for *_, v in points)
    for name, load, mu, speeds in points:
        relaxed = Scene(load=load, mu=mu, **FILM)
        el = solve_fft(relaxed, tol=1e-5)
        amp = edge_amplitudes(el.x, el.pressure, (el.center - el.half_width,
                                                  el.center + el.half_width), 0.1 * el.half_width)
        P = float(np.sum(el.pressure)) * (el.x[1] - el.x[0])
        xp_el = el.info.get("pressure_centroid", float(np.dot(el.pressure, el.x)) * (el.x[1] - el.x[0]) / P)
        for V in speeds:
            s = Scene(load=load, mu=mu, speed=V, prony=SLS, **FILM)
            full = solve_fft(s, tol=1e-4)
            ref = solve_fft(s, tol=1e-4, grid_points=2**18 if quick else 2**21,
                            domain_length=2 * full.domain_length)
            film = s.core_film()
            delta = film.slow_shift
            m2 = film.slow_second_moment
            c2 = m2 - 0.5 * delta * delta
            a = ref.half_width
            unit = c2 / (a * a)
            first = {"a": (el.half_width - 0.5 * abs(delta) - a) / a,
                     "x_c": (el.center + 0.5 * delta - ref.center) / a,
                     "d": (el.indentation - ref.indentation) / ref.indentation,
                     "p_max": (el.max_pressure - ref.max_pressure) / ref.max_pressure,
                     "x_p": (xp_el + delta - ref.info["pressure_centroid"]) / a}
            row = {"scene": name, "speed_m_per_s": V, "l_over_a": abs(V) * TAU / FILM["thickness"] / a,
                   "first_order_bound": film.slow_remainder(a), "c2_over_a2": unit,
                   "reference_estimate": ref.error_estimate}
            row |= {f"err_{k}": v for k, v in first.items()}
            row |= {f"coef_{k}": -v / unit for k, v in first.items()}  # reference - first order
            if mu == 0.0:
                xp2 = film.slow_centroid_second_order(sum(amp), P)
                row["derived_coef_x_p"] = xp2 / a / unit
                row["x_p_left_after_second_order"] = first["x_p"] + xp2 / a
                row["derived_coef_d_interior"] = -2.0 * c2 / ref.indentation / unit
            else:
                row["derived_coef_x_p"] = row["x_p_left_after_second_order"] = float("nan")
                row["derived_coef_d_interior"] = -2.0 * c2 / ref.indentation / unit
            rows.append(row)
            progress(len(rows), n, f"{name} V={V:.1e}", t0)
    table(rows, out / "viscoelastic_second.csv",
          "Slow sliding's first-order theory (relaxed elastic solve at tol 1e-5 + delta) against "
          "2^21-point references; coef_* = (reference - first order) / (c2/a^2), relative like "
          "the estimate; derived: x_p (energy identity, edge amplitudes fitted), d's interior "
          "part -c2 f''; Hunter: x_c -1/4, x_p -1, a 0")
    return rows


PARTS = ("speed", "sphere", "sphere_cost", "sphere_fitted", "sphere_beyond_cost", "reference",
         "claim", "figure", "estimate", "images", "second", "edge_layer", "edge_range",
         "heavy_terms", "heavy_offset", "offset_range", "offset_phase")


def _forces(text: str) -> tuple:
    """--sphere-forces: loads [N]."""
    return float_list(text, "--sphere-forces", "loads > 0 [N]")


def _weights(text: str) -> tuple:
    """--heavy-weights: E_1/E_inf of single Prony terms."""
    return float_list(text, "--heavy-weights", "weights E_1/E_inf > 0")


def _offset_scenes(text: str):
    """--offset-scenes: a comma list of OFFSET_SCENES' names (None: all); one line and exit 2
    naming the option otherwise."""
    if not text:
        return None
    names = text.split(",")
    if not all(n in OFFSET_SCENES for n in names):
        print(f"--offset-scenes must be a comma list of {', '.join(OFFSET_SCENES)}; got "
              f"{text!r}", file=sys.stderr)
        raise SystemExit(2)
    return names


def main(argv=None) -> int:
    def extra(p):
        p.add_argument("--parts", default=",".join(PARTS),
                       help=f"comma list of {', '.join(PARTS)} (default all; figure needs the "
                            "speed and claim CSVs, made now or before)")
        p.add_argument("--sphere-films", default="",
                       help="sphere_fitted: a comma list of its films (SLS, two-term, E1=3Einf, "
                            "E1=10Einf) to run alone (default all); sphere_beyond_cost: its films "
                            "(E1=3Einf, E1=10Einf, or SLS)")
        p.add_argument("--sphere-tols", default="",
                       help="sphere_beyond_cost: comma list of tolerances (default 1e-2,5e-3,1e-3)")
        p.add_argument("--sphere-forces", default="1",
                       help="sphere_beyond_cost: comma list of the sphere's loads [N] (default 1)")
        p.add_argument("--offset-scenes", default="",
                       help="offset_range: comma list of its scenes to run alone (default all: "
                            + ", ".join(OFFSET_SCENES) + ")")
        p.add_argument("--heavy-weights", default="",
                       help="heavy_terms, heavy_offset, offset_range: comma list of single terms' weights "
                            "E_1/E_inf to run instead of the default films (e.g. 30,100)")

    args, out = parse(argv, __doc__.splitlines()[0], "out/viscoelastic", extra=extra)
    parts = args.parts.split(",")
    weights = _weights(args.heavy_weights) if args.heavy_weights else None
    offset_scenes = _offset_scenes(args.offset_scenes)  # (checked before any part runs)
    t0 = time.perf_counter()
    if "speed" in parts:
        part_speed(args.quick, out, t0)
    if "sphere" in parts:
        part_sphere(args.quick, out, t0)
    if "sphere_cost" in parts:
        part_sphere_cost(args.quick, out, t0)
    if "sphere_fitted" in parts:
        part_sphere_fitted(args.quick, out, t0,
                           [f for f in args.sphere_films.split(",") if f] or None)
    if "sphere_beyond_cost" in parts:
        part_sphere_beyond_cost(args.quick, out, t0,
                                tuple(float(t) for t in args.sphere_tols.split(",")) or None
                                if args.sphere_tols else None,
                                [f for f in args.sphere_films.split(",") if f] or None,
                                _forces(args.sphere_forces))
    if "reference" in parts:
        part_reference(args.quick, out, t0)
    if "claim" in parts:
        part_claim(args.quick, out, t0)
    if "figure" in parts:
        import pandas as pd

        figure(pd.read_csv(out / "viscoelastic_speed.csv").to_dict("records"),
               pd.read_csv(out / "viscoelastic_claim.csv").to_dict("records"), out)
    if "estimate" in parts:
        part_estimate(args.quick, out, t0)
    if "images" in parts:
        part_images(args.quick, out, t0)
    if "second" in parts:
        part_second(args.quick, out, t0)
    if "edge_layer" in parts:
        part_edge_layer(args.quick, out, t0)
    if "edge_range" in parts:
        part_edge_range(args.quick, out, t0)
    if "heavy_terms" in parts:
        part_heavy_terms(args.quick, out, t0, weights)
    if "heavy_offset" in parts:
        part_heavy_offset(args.quick, out, t0, weights)
    if "offset_range" in parts:
        part_offset_range(args.quick, out, t0, weights, offset_scenes)
    if "offset_phase" in parts:
        part_offset_phase(args.quick, out, t0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
