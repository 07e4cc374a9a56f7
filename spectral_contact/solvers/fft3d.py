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

import dataclasses
import logging
import math
import os
import time

import numpy as np

from ..errors import ConvergenceError, InputError
from ..numerics.contact import nested_guess, solve_complementarity, solve_contact
from ..numerics.fft import get_rfft, planning_time
from ..numerics.friction import solve_contact_law
from ..numerics.grid import Grid, pow2_at_least
from ..numerics.measure2d import measure_contact_2d
from ..numerics.open_domain import box_of, open_compliance_operator, open_grid
from ..physics.film import Film
from ..physics.friction import ShearLaw
from ..physics.scene import Scene3D, check_positive
from ..physics.transfer import F2, compressible_tangential_function, tanh_over, transfer_functions
from ..result import ContactResult3D
from .base import check_grid_points

_VISCO_EDGE_CELLS = 4  # as solvers.fft (issue 23)
_VISCO_EDGE_SHARE = 0.25

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
_LOCATOR_RTOL, _LOCATOR_ACCEPT, _LOCATOR_SEARCH_RTOL = 1e-6, 1e-3, 1e-2  # as the line solver's
_END_ASPECT = 2.0  # the finite cylinder's cells: dx = this x dy (issue 25).  Measured on the
# paper's slide (default tol 1e-2, its automatic periods): at ny = 1024 the indentation and the
# line load at y = 0 move by 1e-5 and 3e-5 between nx = 256 and 1024 (between ny = 512 and
# 1024: 3.9e-3 and 5.3e-3), the contact radius by 1.3e-3; levels (256, 512) -> (512, 1024)
# differ as (512, 512) -> (1024, 1024) do (3.9e-3 vs 3.8e-3 on the indentation)
_OPEN_MARGIN = 1.5  # the open solve's estimate: this times the last two levels' difference
_FAR_CELLS = 12    # the base fields of an open solve: a periodic grid of cells h / this (the
# base transfer decays as exp(-|k| h): e^-37 at its Nyquist wavenumber)


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


def _difference(q, r, singular_peak: bool = False) -> float:
    """Relative difference of two levels' controlled measures: contact radius sqrt(A/pi),
    pressure centroid (relative to the radius), indentation, line load at y = 0 and peak
    pressure (left out where it is singular: sharp ends)."""
    rad = max(math.sqrt(max(q["area"], 0.0) / math.pi), 1e-300)
    r_rad = math.sqrt(max(r["area"], 0.0) / math.pi)
    out = max(abs(rad - r_rad) / rad, abs(q["xc"] - r["xc"]) / rad,
              abs(q["indentation"] - r["indentation"]) / max(abs(q["indentation"]), 1e-300),
              abs(q["line_load_y0"] - r["line_load_y0"]) / max(abs(q["line_load_y0"]), 1e-300))
    if not singular_peak:
        out = max(out, abs(q["pmax"] - r["pmax"]) / max(q["pmax"], 1e-300))
    return out


def _extent_difference(q, r) -> float:
    """Largest change of the contact's extents between two levels, relative to the radius."""
    rad = max(math.sqrt(max(q["area"], 0.0) / math.pi), 1e-300)
    return max(abs(q[k] - r[k]) for k in ("x_min", "x_max", "y_min", "y_max")) / rad


def _measure(sol, ind) -> dict:
    q = measure_contact_2d(sol.grid, sol.pressure, sol.gap, sol.active)
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
    t0 = time.perf_counter()
    plans0 = planning_time()
    grid_points, domain_length = _check_fixed(grid_points, domain_length)
    # issue 14: any nu (nu = 1/2: the incompressible path); issue 23: a viscoelastic film in
    # steady sliding (its relaxation tail lengthens the period along x only)
    film = scene.core_film()
    visco = film.moving  # a film whose symbols depend on the sliding (physics.film)
    P = scene.P
    mu_contact = scene.mu if model == "exact" else 0.0
    ind = scene.indenter_object()
    if progress is None:  # issue 24: surface solves of 5-14 s printed nothing
        progress = logging.getLogger(__name__).info
    margin = film.domain_margin(tol, surface=True) if visco else film.domain_margin(tol)
    accept = max(1e-8, 1e-2 * tol)
    counters = {"transforms": 0, "iterations": 0, "linear_iterations": 0}
    # issue 14: a friction law (outer fixed point) and/or a linear interface (H + c), as in 2D
    law = scene.friction.dimensionless(scene.stress_unit, scene.mu)
    with_law = model == "exact" and not scene.friction.is_amontons
    c = scene.interface

    # the inner (GMRES) solves to 1e-4 of the accepted residual (issue 25: 1e-10 before; one
    # to two GMRES iterations per active-set step for digits no measure keeps; 1e-3 left the
    # surface 1.6e-7 d off the indenter at tol 3e-3, 1e-4 2e-9); the locator's looser
    # still, as in 1D (its contact only sizes the period and the grid)
    rtol = max(1e-10, 1e-4 * accept)

    def contact(grid, p_init=None, locator=False):
        if visco:  # the k_x = 0 modes: R averaged over their band (Film.on_grid)
            if p_init is None:  # the indenter's own guess, not the nested start: its coarse
                # grids on the tail's long period hold the contact on a node or two (measured:
                # the sphere at V = 10 m/s, tau 10 ms failed on the load residual, 5 %)
                p_init = np.broadcast_to(ind.initial_pressure(grid), grid.shape).copy()
            return _contact(grid, film.on_grid(grid.lengths), p_init, locator)
        return _contact(grid, film, p_init, locator)

    def _contact(grid, film, p_init=None, locator=False):
        rt, acc = (max(rtol, _LOCATOR_RTOL), max(accept, _LOCATOR_ACCEPT)) if locator else \
            (rtol, accept)
        search = _LOCATOR_SEARCH_RTOL if locator else None
        if not with_law and c == 0.0:
            return solve_contact(grid, mu_contact, [ind], film=film, p_init=p_init, accept=acc,
                                 rtol=rt, search_rtol=search)
        s_, _, _ = solve_contact_law(grid, law if with_law else ShearLaw("amontons", mu=mu_contact),
                                     [ind], film=film, interface=c, p_init=p_init, accept=acc,
                                     law_tol=accept, rtol=rt, search_rtol=search)
        return s_

    def count(sol):
        counters["transforms"] += sol.fft_pairs
        counters["iterations"] += sol.iterations
        counters["linear_iterations"] += sol.krylov_iterations
        return sol

    if P == 0.0:
        Lx, Ly = domain_length or (margin, margin)
        g = Grid.centered(grid_points or (MIN_POINTS_3D, MIN_POINTS_3D), (Lx, Ly))
        z = np.zeros(g.shape)
        q = measure_contact_2d(g, z, z, z > 0) | {"indentation": 0.0}
        return ContactResult3D(scene, model, "fft", g.axes[0], g.axes[1], z, z, z, z, z, z, z, q,
                               g.shape, g.lengths, 0, 0.0, 0.0, time.perf_counter() - t0, 0.0,
                               counters=counters)

    # 1. locate the contact
    ex, ey = ind.extent_bound()
    if not (ex > 0 and ey > 0 and math.isfinite(ex) and math.isfinite(ey)):
        raise InputError(f"the indenter's contact extent bound ({ex:g}, {ey:g}) h is not usable")
    # the locator never uses a user period (nor the viscoelastic tail's margin: it only
    # locates the contact)
    m0 = Film.domain_margin(film, tol) if visco else margin
    L0 = (4.0 * ex + m0, 4.0 * ey + m0)
    d0 = 2.0 * min(ex, ey) / _FIRST_ACROSS
    if grid_points:
        n0 = tuple(max(MIN_POINTS_3D, n // 4 // 2 * 2) for n in grid_points)
    else:
        n0 = tuple(pow2_at_least(L / d0, MIN_POINTS_3D) for L in L0)
    if not grid_points and domain_length is None and not with_law and not visco \
            and max(n0) > _OPEN_ABOVE:
        # a small contact (issue 24): cells sized from the contact on an open box
        return _solve_open(scene, model, tol, film, ind, mu_contact, c, accept, margin,
                           progress, t0, plans0, counters)
    def check_period(q):
        """A user period must hold the contact plus the decay of its images to tol/2."""
        width_x, width_y = q["x_max"] - q["x_min"], q["y_max"] - q["y_min"]
        free = math.log(2.0 / tol) / film.decay_rate
        need = (width_x + free, width_y + free)
        if visco:  # and along x the relaxation tail behind the contact (issue 23)
            need = (width_x + free + margin - Film.domain_margin(film, tol),
                    need[1])
        if any(L < n for L, n in zip(domain_length, need)):
            raise InputError(
                f"domain_length ({domain_length[0]:.4g}, {domain_length[1]:.4g}) h is too short "
                f"for this contact at tol {tol:g}: the periods must hold the contact "
                f"({width_x:.3g} x {width_y:.3g} h) plus {free:.3g} h for its images to decay "
                f"below tol/2{' (along x also the relaxation tail behind it)' if visco else ''}: "
                f"at least ({need[0]:.4g}, {need[1]:.4g}) h, or leave it automatic")

    # a user grid on a user period (issue 25): no locator, whose contact would only be checked
    # against the period (~4-6 FFT-pair times of 512^2); the first level's contact is
    fixed_box = bool(grid_points) and domain_length is not None
    if fixed_box:
        L, center = domain_length, (0.0, 0.0)
    else:
        _check_size(n0, "locating the contact")
        if progress:
            progress(f"locating the contact on a {n0[0]} x {n0[1]} grid")
        sol = count(contact(Grid.centered(n0, L0), locator=True))
        q = _measure(sol, ind)

        # 2. the periods: the contact plus the decay margin, centred on the contact
        width_x = q["x_max"] - q["x_min"]
        width_y = q["y_max"] - q["y_min"]
        if domain_length is not None:
            check_period(q)
        guard = 4.0 * max(sol.grid.spacing)
        margin_y = Film.domain_margin(film, tol) if visco else margin  # the tail is along x
        L = domain_length or (width_x + margin + guard, width_y + margin_y + guard)
        center = (0.5 * (q["x_max"] + q["x_min"]), 0.0) if domain_length is None else (0.0, 0.0)
    if grid_points:
        levels = [tuple(n // 2 for n in grid_points), grid_points]
    else:
        d1 = min(width_x, width_y) / _FIRST_ACROSS
        # sharp ends (finite cylinder): cells _END_ASPECT times longer across the cylinder
        # (x) than along it: the ends' singularity sets the error, through the cells along y
        stretch = (_END_ASPECT, 1.0) if ind.singular_peak else (1.0, 1.0)
        dx1 = d1 * stretch[0]
        radius = 0.25 * (width_x + width_y)
        for width, weight in (film.edge_scales() if visco else ()):
            # as in 2D (solvers.fft._level_sizes): resolve the edge structure |V| tau_i (along
            # x, the sliding direction) of a term that moves the contact by more than a share
            # of tol (issue 23)
            if weight * width / radius > _VISCO_EDGE_SHARE * tol:
                dx1 = min(dx1, width / _VISCO_EDGE_CELLS)
        n1 = (pow2_at_least(L[0] / dx1, MIN_POINTS_3D),
              pow2_at_least(L[1] / (d1 * stretch[1]), MIN_POINTS_3D))
        if dx1 < d1 * stretch[0] and n1[0] > MAX_POINTS_3D:
            raise InputError(
                f"the viscoelastic film's edge structure (|V| tau down to "
                f"{dx1 * _VISCO_EDGE_CELLS:.2g} h) needs ~{L[0] / dx1:.2g} points along x at tol "
                f"{tol:g} (> {MAX_POINTS_3D}): raise --tol, or change --speed")
        levels = [n1]
        while max(levels[-1]) < MAX_POINTS_3D:
            levels.append(tuple(2 * n for n in levels[-1]))
    prev = qprev = None
    est = extent_est = float("inf")
    history = []
    for i, shape in enumerate(levels):
        _check_size(shape, f"tol {tol:g}")
        g = Grid.centered(shape, L, center)
        if progress:
            progress(f"level {i + 1}: {shape[0]} x {shape[1]} grid, "
                     f"{time.perf_counter() - t0:.1f} s")
        if prev is not None and prev.grid.shape == tuple(n // 2 for n in shape):
            p_init = nested_guess(prev, g)
        else:
            p_init = None  # the indenter's own guess
        cur = count(contact(g, p_init=p_init))
        qcur = _measure(cur, ind)
        if fixed_box and i == 0:
            check_period(qcur)
        history.append((shape, qcur))
        if qprev is not None:
            est = _difference(qcur, qprev, ind.singular_peak)
            if visco:  # terms whose edge structure spans < _VISCO_EDGE_CELLS cells
                radius = math.sqrt(qcur["area"] / math.pi)
                est += sum(w * ell / radius for ell, w in film.edge_scales()
                           if ell < _VISCO_EDGE_CELLS * g.spacing[0])
            extent_est = _extent_difference(qcur, qprev)
            if grid_points or est <= tol:
                break
        prev, qprev = cur, qcur
    else:
        raise ConvergenceError(
            f"grid refinement reached {levels[-1][0]} x {levels[-1][1]} points with error "
            f"estimate {est:.1e} > tol {tol:.1e}; raise tol or set grid_points",
            residuals=[est], iterations=len(history))

    sol, q = cur, qcur
    p = sol.pressure
    if scene.friction.is_amontons:
        shear = (scene.mu * p, np.zeros_like(p))
    else:  # exact: the law's shear of the coupled solve; goodman: the law on the frictionless p
        shear = (sol.shear if with_law else law.shear(p), np.zeros_like(p))
    if visco:  # the final grid's film (its k_x = 0 band): the Film's own output fields
        film = dataclasses.replace(film, kx_cell=math.pi / sol.grid.lengths[0])
        fft = get_rfft(sol.grid.shape)
        shear_ = (shear[0], np.zeros_like(p))
        szz, (sxz, syz) = film.base_stresses(fft, sol.grid, -p, shear_)
        (ux, uy), delta = film.surface_displacements(fft, sol.grid, p, shear_)
        counters["transforms"] += 5
    else:
        # (a law with q = mu p exactly, e.g. power with n = 0: the Amontons fields, bit for bit)
        prop = scene.mu if scene.friction.is_amontons else law.mu if law.proportional else None
        szz, sxz, syz, ux, uy, delta = _output_fields(film, sol.grid, p, prop, shear[0])
        counters["transforms"] += 4
    # mu_def = Int p df/dx / P on every film (Q_over_P = Int q / P + mu_def, issue 23),
    # df/dx = (h/2R) d f_core / d x_core (central differences, exact for quadratic heights),
    # over the contact nodes
    f = np.asarray(ind.height(sol.grid), dtype=float)
    dfdx = (np.roll(f, -1, axis=0) - np.roll(f, 1, axis=0)) / (2.0 * sol.grid.spacing[0])
    on = p > 0
    mu_def = (float(np.sum(p[on] * dfdx[on]) / np.sum(p[on])) * scene.thickness
              / (2.0 * scene.radius) if on.any() else 0.0)
    total = time.perf_counter() - t0
    plan_time = planning_time() - plans0
    info = {
        **_solve_info(history, sol, margin, q, extent_est),
        "deformation_friction": mu_def + 0.0,
        **({"tail_length": film.tail_length} if visco else {}),
    }
    x, y = sol.grid.axes
    return ContactResult3D(
        scene=scene, model=model, method="fft", x=x, y=y, pressure=p, base_sigma_zz=szz,
        base_sigma_xz=sxz, base_sigma_yz=syz, surface_ux=ux, surface_uy=uy, surface_uz=-delta,
        measures=q, grid_points=sol.grid.shape, domain_length=sol.grid.lengths,
        iterations=sol.iterations, residual=sol.residual, error_estimate=est,
        wall_time_s=total - plan_time, plan_time_s=plan_time, info=info, counters=counters,
        shear=None if scene.friction.is_amontons else shear[0])



def _solve_info(history, sol, margin, q, extent_est) -> dict:
    """The ``info`` entries every 3D solve reports (periodic grid or open box)."""
    return {
        "levels": [(s, h["area"], h["x_min"], h["x_max"], h["indentation"], h["pmax"])
                   for s, h in history],
        "residuals": sol.residuals,
        "domain_margin": margin,
        "load_on_grid": q["load"],
        "extent_error_estimate": extent_est,
        "extent_note": "contact x and y extents are envelopes of edges fitted along grid lines "
                       "(a few hundredths of a cell); not controlled by tol: their level "
                       "difference is extent_error_estimate",
        # the finest grid's own work (its nested start's coarser grids excluded), issue 25
        "final_level_active_set_iterations": sol.iterations,
        "final_level_krylov_iterations": sol.krylov_iterations,
        "final_level_fft_pairs": sol.fft_pairs - sol.coarse_fft_pairs,
    }

_MULTIPLIERS: dict = {}  # (film, shape, lengths, mu) -> the output fields' multipliers
_MULTIPLIER_BYTES = 2**28  # the cache's budget: 256 MB (2048^2 with mu given: 6 complex
# arrays of 2048 x 1025, 202 MB, the only entry; 1024^2: 50 MB each).  Measured: their
# evaluation at 2048^2 cost ~12 FFT-pair times of the grid, each solve, when not kept


def _radial_coefficients(film: Film, K):
    """The output fields' coefficients that depend on |k| only (``_multipliers``)."""
    Kh = K * film.thickness
    if film.incompressible:  # one evaluation of the five transfer functions
        F0, F1, A, B, C = transfer_functions(Kh)
        iB = iBp = 1j * B
        e = np.exp(-np.abs(Kh))
        T = 2.0 * e / (1.0 + e * e)  # sech K (Film's)
    else:
        A, iB, iBp, C, T = film.base_coefficients(K)
        F0, F1 = film._F0_F1(K)
    F2_ = F2(Kh) if film.incompressible else compressible_tangential_function(Kh, film.poisson)
    pos = K > 0
    inv2k = np.where(pos, 0.5 / np.where(pos, K, 1.0), 0.0)
    cL = np.where(pos, F2_ * inv2k, film.thickness)
    cT = film.thickness * tanh_over(Kh)
    iF1 = 1j * F1 * inv2k
    d0 = F0 * inv2k
    if not film.incompressible:
        d0 = d0 + np.where(pos, 0.0, film.uniform_compliance)
    return A, iB, iBp, C, T, cL, cT, iF1, d0


def _even_in_kx(fn, K):
    """fn(K) (a tuple of arrays, elementwise in K) on the half spectrum's |k| (shape kshape, the
    first axis in fftfreq order), evaluated on the rows k_x >= 0 only and mirrored: |k| of row
    n - i is |k| of row i bit for bit (fftfreq's values are exact negatives), so the result is
    fn(K)'s, at half the cost (issue 25: the transfer functions were ~1/3 of the outputs' time
    at 2048^2)."""
    n = K.shape[0]
    m = n // 2 + 1
    if K.ndim != 2 or n < 4:
        return fn(K)
    out = []
    for h in fn(K[:m]):
        h = np.broadcast_to(h, (m,) + K.shape[1:])
        out.append(np.concatenate([h, h[1:n - m + 1][::-1]]))
    return tuple(out)


def _multipliers(film: Film, grid, mu):
    """Per-mode multipliers of the output fields (``_output_fields``): with t^ = mu p^
    (``mu`` given) six arrays M with field^ = M p^; otherwise the pairs (M_p, M_t) with
    field^ = M_p p^ + M_t t^.  Averaged over the two aliases on the Nyquist plane of the
    first axis (``Grid.alias_average``; the last axis's is the real transform's).  Cached per
    film, grid shape, periods and mu for the next solve on that grid (issue 25: a sweep over
    forces or friction on one grid; their evaluation cost ~20 FFT pairs at 512^2)."""
    key = (film, grid.shape, grid.lengths, mu)
    out = _MULTIPLIERS.get(key)
    if out is not None:
        return out
    A, iB, iBp, C, T, cL, cT, iF1, d0 = _even_in_kx(lambda K: _radial_coefficients(film, K),
                                                    grid.kmag)

    def pairs(nx, ny, sl):
        """(M_p, M_t) of szz, sxz, syz, ux, uy, delta on the modes ``sl``."""
        a, b, bp, c, t = A[sl], iB[sl], iBp[sl], C[sl], T[sl]
        cl, ct, f1, dd = cL[sl], cT[sl], iF1[sl], d0[sl]
        nx2 = nx * nx
        return ((-a, b * nx), (-bp * nx, c * nx2 + t * (1.0 - nx2)),
                (-bp * ny, (c - t) * nx * ny), (-f1 * nx, cl * nx2 + ct * (1.0 - nx2)),
                (-f1 * ny, (cl - ct) * nx * ny), (dd, f1 * nx))

    nx, ny = (np.broadcast_to(n, grid.kshape) for n in grid.direction)
    full = (slice(None),) * 2
    ms = [list(m) for m in pairs(nx, ny, full)]
    mask = grid.nyquist_mask
    if mask is not None:  # the Nyquist plane k_x = -pi/dx: the mean with its alias +pi/dx
        row = (grid.shape[0] // 2, slice(None))
        ax, ay = (np.broadcast_to(n, grid.kshape)[row] for n in grid.alias_direction)
        for m, alias in zip(ms, pairs(ax, ay, row)):
            for i in (0, 1):
                m[i] = np.array(m[i], dtype=complex)
                m[i][row] = 0.5 * (m[i][row] + alias[i])
    if mu is not None:
        out = tuple(mp + mu * mt for mp, mt in ms)
    else:
        out = tuple(tuple(m) for m in ms)
    size = sum(m.nbytes for m in (out if mu is not None else sum(out, ())))
    if size <= _MULTIPLIER_BYTES:
        while _MULTIPLIERS and size + sum(m.nbytes for v in _MULTIPLIERS.values() for m in
                                          (v if isinstance(v[0], np.ndarray) else sum(v, ()))
                                          ) > _MULTIPLIER_BYTES:
            del _MULTIPLIERS[next(iter(_MULTIPLIERS))]  # the oldest first
        _MULTIPLIERS[key] = out
    return out


def _output_fields(film: Film, grid, p, mu, shear):
    """Base tractions (sigma_zz, sigma_xz, sigma_yz at z = 0) and surface displacements
    (u_x, u_y, delta = -u_z) on ``grid`` from the pressure p and the surface shear along x
    (``shear``; = mu p when ``mu`` is given: its spectrum is then mu p^, no transform).  The
    fields of ``Film.base_stresses`` and ``Film.surface_displacements`` (physics3d.md, equal
    to round-off), with one forward transform (two with a friction law) instead of six and
    the transfer functions evaluated once per grid (``_multipliers``): issue 25."""
    fft = get_rfft(grid.shape)
    p_hat = fft.forward(p)
    m = _multipliers(film, grid, mu)
    if mu is not None:
        return tuple(fft.backward(mi * p_hat) for mi in m)
    t_hat = fft.forward(shear)
    return tuple(fft.backward(mp * p_hat + mt * t_hat) for mp, mt in m)


def _open_contact(grid, ind, mu: float, film: Film, c: float, accept: float, p_init=None):
    """The contact solve on an open box (``numerics.open_domain``): the padded ``grid``'s
    nodes outside its central box cannot touch (height +inf)."""
    op = open_compliance_operator(grid.shape, grid.lengths, float(mu), film)
    if c:
        op = op + c
    f = np.full(grid.shape, np.inf)
    box = box_of(grid)
    f[box] = np.broadcast_to(ind.height(grid), grid.shape)[box]
    if p_init is None:
        p_init = np.where(np.isfinite(f), np.broadcast_to(ind.initial_pressure(grid), grid.shape),
                          0.0)
    sol = solve_complementarity(op, f, np.zeros(grid.shape, dtype=np.intp), [ind.load],
                                p_init=p_init, accept=accept, grid=grid)
    if c:
        sol.sinking = sol.sinking - c * sol.pressure  # the film's sinking (as solve_contact_law)
    return sol


def _touches_box(sol) -> bool:
    """Whether the contact comes within 7 nodes of its box's border (the edge fits need 6)."""
    box = box_of(sol.grid)
    act = sol.active[box]
    if not act.any():
        return False
    ix, iy = np.nonzero(act)
    nx, ny = act.shape
    return bool(ix.min() < 7 or iy.min() < 7 or ix.max() > nx - 8 or iy.max() > ny - 8)


def _far_fields(film: Film, grid, p: np.ndarray, mu: float, margin: float, shear=None):
    """Base tractions and surface displacements at the box nodes of an open solve: the
    pressure's Fourier series on a periodic grid of the film's period (box + ``margin``, cells
    h / _FAR_CELLS), taken exactly from the nodes (a non-uniform DFT: no deposit error), through
    the film's transfer functions and summed back at the box nodes.  The base transfer decays
    as exp(-|k| h): exact to round-off there; the surface displacements are band-limited to
    that grid's wavenumbers (resolved at h / _FAR_CELLS, not at the box's cells)."""
    x, y = grid.axes
    Lc = tuple(float(np.ptp(a)) + d + margin for a, d in zip((x, y), grid.spacing))
    nc = tuple(2 * math.ceil(L * _FAR_CELLS / film.thickness / 2) for L in Lc)
    origin = (float(x.mean()) - Lc[0] / 2, float(y.mean()) - Lc[1] / 2)
    kx = 2 * np.pi * np.fft.fftfreq(nc[0], Lc[0] / nc[0])
    ky = 2 * np.pi * np.fft.fftfreq(nc[1], Lc[1] / nc[1])
    Ex = np.exp(-1j * np.outer(kx, x - origin[0]))
    Ey = np.exp(-1j * np.outer(ky, y - origin[1]))
    weight = grid.cell / (Lc[0] * Lc[1] / (nc[0] * nc[1]))

    def spectrum(field):
        return (Ex @ (field * weight)) @ Ey.T

    p_hat = spectrum(p)
    tau = mu * p if shear is None else shear
    t_hat = spectrum(tau)
    K = np.hypot(kx[:, None], ky[None, :])
    safe = np.where(K > 0, K, 1.0)
    n = (np.where(K > 0, kx[:, None] / safe, 1.0), np.where(K > 0, ky[None, :] / safe, 0.0))
    zero = np.zeros_like(p_hat)
    szz, (sxz, syz) = film.base_transfer(n, K, -p_hat, (t_hat, zero))
    (ux, uy), _ = film.surface_displacement_transfer(n, K, p_hat, (t_hat, zero))
    scale = 1.0 / (nc[0] * nc[1])

    def back(spec):
        return ((Ex.conj().T @ spec) @ Ey.conj()).real * scale

    return back(szz), back(sxz), back(syz), back(ux), back(uy), nc[0] * (Lc[0] / nc[0])


def _solve_open(scene, model, tol, film, ind, mu, c, accept, margin, progress, t0, plans0,
                counters) -> ContactResult3D:
    """A contact much smaller than the film's decay margin (issue 24): solved on an open box
    (``numerics.open_domain``: the film's kernel in real space, non-periodic), cells sized from
    the contact, refined as the periodic levels until two agree to ``tol``; the base fields
    from the film's period (``_far_fields``).  The reported grid is the box."""

    def count(sol):
        counters["transforms"] += sol.fft_pairs
        counters["iterations"] += sol.iterations
        counters["linear_iterations"] += sol.krylov_iterations
        return sol

    ex, ey = ind.extent_bound()
    apex = float(getattr(ind, "apex", 0.0))
    box = (4.0 * ex, 4.0 * ey)
    d0 = 2.0 * min(ex, ey) / _FIRST_ACROSS
    for _ in range(6):  # the locator's box doubled while the contact reaches its border
        nb = tuple(pow2_at_least(B / d0, MIN_POINTS_3D) for B in box)
        g0 = open_grid(nb, box, (apex, 0.0))
        _check_size(g0.shape, "locating the contact")
        if progress:
            progress(f"locating the contact on an open {nb[0]} x {nb[1]} box")
        sol = count(_open_contact(g0, ind, mu, film, c, accept))
        if not _touches_box(sol):
            break
        box = (2.0 * box[0], 2.0 * box[1])
    q = _measure(sol, ind)
    width = (q["x_max"] - q["x_min"], q["y_max"] - q["y_min"])
    center = (0.5 * (q["x_max"] + q["x_min"]), 0.0)
    d1 = min(width) / _FIRST_ACROSS
    # the contact plus 8 cells of the first level each side (the edge fits need 6), in
    # multiples of 8 cells (FFT-friendly sizes); cells d1 exactly: the levels share the box
    n1 = tuple(max(MIN_POINTS_3D, 8 * math.ceil((w / d1 + 16.0) / 8.0)) for w in width)
    box = tuple(n * d1 for n in n1)
    prev = qprev = None
    est = extent_est = float("inf")
    history = []
    shape = n1
    while True:
        g = open_grid(shape, box, center)
        _check_size(g.shape, f"tol {tol:g}")
        if progress:
            progress(f"open box level {len(history) + 1}: {shape[0]} x {shape[1]} box, "
                     f"{time.perf_counter() - t0:.1f} s")
        p_init = nested_guess(prev, g) if prev is not None else None
        cur = count(_open_contact(g, ind, mu, film, c, accept, p_init))
        if _touches_box(cur):
            raise ConvergenceError(f"the open box ({box[0]:.3g} x {box[1]:.3g} h) does not hold "
                                   "the contact: raise tol or fix grid_points",
                                   residuals=[cur.residual], iterations=len(history) + 1)
        qcur = _measure(cur, ind)
        history.append((shape, qcur))
        if qprev is not None:
            # 1.5 x the level difference (as the line solver's _LEVEL_MARGIN): the measures
            # converge at first order here (the difference halves per level), where the bare
            # difference was measured 0.9x the error against the axisymmetric reference
            est = _OPEN_MARGIN * _difference(qcur, qprev, ind.singular_peak)
            extent_est = _extent_difference(qcur, qprev)
            if est <= tol:
                break
        if 2 * max(g.shape) > MAX_POINTS_3D:
            raise ConvergenceError(
                f"grid refinement reached an open {shape[0]} x {shape[1]} box with error "
                f"estimate {est:.1e} > tol {tol:.1e}; raise tol", residuals=[est],
                iterations=len(history))
        prev, qprev = cur, qcur
        shape = tuple(2 * n for n in shape)

    sol, q = cur, qcur
    sl = box_of(sol.grid)
    x, y = (a[s] for a, s in zip(sol.grid.axes, sl))
    p = np.ascontiguousarray(sol.pressure[sl])
    uz = -np.ascontiguousarray(sol.sinking[sl])
    gbox = Grid.centered(p.shape, box, center)
    szz, sxz, syz, ux, uy, _ = _far_fields(film, gbox, p, scene.mu, margin)
    total = time.perf_counter() - t0
    plan_time = planning_time() - plans0
    info = {
        **_solve_info(history, sol, margin, q, extent_est),
        "open_box": True,
        "open_box_note": "a contact much smaller than h: solved on an open (non-periodic) box "
                         f"of {box[0]:.4g} x {box[1]:.4g} h around it (the film's kernel in real "
                         "space); the maps cover that box only; the base tractions come from the "
                         "film's period (exact), the surface ux, uy are resolved at "
                         f"h/{_FAR_CELLS} only (u_z and the pressure at the box's cells)",
    }
    return ContactResult3D(
        scene=scene, model=model, method="fft", x=x, y=y, pressure=p, base_sigma_zz=szz,
        base_sigma_xz=sxz, base_sigma_yz=syz, surface_ux=ux, surface_uy=uy, surface_uz=uz,
        measures=q, grid_points=p.shape, domain_length=box,
        iterations=sol.iterations, residual=sol.residual, error_estimate=est,
        wall_time_s=total - plan_time, plan_time_s=plan_time, info=info, counters=counters)
