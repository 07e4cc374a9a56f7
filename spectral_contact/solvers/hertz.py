"""The Hertz model as a solver: closed-form contact (``reference.hertz``), base transfer exact."""
from __future__ import annotations

import math
import time

import numpy as np

from ..errors import InputError
from ..numerics.fft import get_rfft
from ..numerics.grid import Grid, pow2_at_least
from ..physics.film import DECAY_RATE, Film
from ..physics.scene import Scene, check_positive
from ..reference.hertz import (
    _K_NYQUIST_MIN,
    _POINTS_ACROSS,
    hertz_base_stresses,
    hertz_film_sinking,
    hertz_half_width,
    hertz_pressure,
)
from ..result import ContactResult, ContactResult3D
from .auto import model_error_bound
from .base import check_grid_points

__all__ = ["solve_hertz", "solve_hertz3d"]

_MAX_POINTS = 2**22


def solve_hertz(scene: Scene, tol: float = 1e-4, grid_points: int | None = None,
                domain_length: float | None = None) -> ContactResult:
    """The Hertz model of ``scene`` (closed form; method "closed-form").

    tol : sets the period of the profile grid (images of the base stresses ~ tol/100);
          a, the centre, p_max and the indentation are closed-form whatever tol.
    grid_points, domain_length (in h) : fix the profile grid instead.

    ``error_estimate`` is the numerical error of a, centre, indentation, p_max (closed forms:
    quadrature level, reported 1e-12); the model error against the exact model is in
    ``info["model_error_bound"]`` (the fitted bound of ``solvers.auto``).
    """
    t0 = time.perf_counter()
    grid_points = check_grid_points(grid_points, 64, 2**24, "hertz profile grid points")
    if domain_length is not None:
        domain_length = check_positive("domain_length", domain_length, "h")
    P, mu = scene.P, scene.mu
    a = hertz_half_width(P)
    margin = Film().domain_margin(tol)
    L = domain_length or (2.0 * a + margin)
    if grid_points:
        n = int(grid_points)
    else:
        dx = math.pi / _K_NYQUIST_MIN
        if a > 0:
            dx = min(dx, 2.0 * a / _POINTS_ACROSS)
        n = min(pow2_at_least(L / dx, 64), _MAX_POINTS)
    g = Grid.centered(n, L, 0.0)
    p = hertz_pressure(g.x, a)
    if a > 0:
        szz, sxz = hertz_base_stresses(g, a, mu)
    else:
        szz, sxz = np.zeros(n), np.zeros(n)
    d = hertz_film_sinking(a)
    bound = model_error_bound("hertz", a, mu)
    info = {
        "model_note": "Hertz pressure on the film: surface model Hertz (incompressible "
                      "half-space, E* = 4E/3, friction uncoupled), base transfer exact",
        "indentation_note": "film's sinking at the apex under the Hertz pressure, w(0) = (H p)(0)",
        "image_error": math.exp(-DECAY_RATE * max(L - 2.0 * a, 0.0)),
        "k_nyquist": math.pi / g.dx,
        "model_error_bound": bound,
        "fft_pairs": 1,
    }
    wall = time.perf_counter() - t0
    return ContactResult(
        scene=scene, model="hertz", method="closed-form", x=g.x, pressure=p,
        base_sigma_zz=szz, base_sigma_xz=sxz, half_width=a, center=0.0, indentation=d,
        max_pressure=4.0 * a, max_pressure_x=0.0, grid_points=n, domain_length=L,
        iterations=0, residual=0.0, error_estimate=1e-12 if a > 0 else 0.0,
        wall_time_s=wall, plan_time_s=0.0, info=info,
        counters={"transforms": 1 if a > 0 else 0, "iterations": 0, "linear_iterations": 0})


def solve_hertz3d(scene, tol: float = 1e-3, grid_points=None, domain_length=None):
    """The Hertz model of a 3D sphere scene (closed form, incompressible half-space, E* = 4E/3):
    a^3 = 3P/32, p = (16 a/pi) sqrt(1 - r^2/a^2) (dimensionless, sphere f = r^2), friction
    uncoupled; base stresses and surface displacements through the film's exact transfer on a
    grid (as in 2D).  The indentation reported is the film's sinking at the apex under that
    pressure (the half-space's would be 2 a^2: ``info["half_space_indentation"]``)."""
    t0 = time.perf_counter()
    if scene.indenter != "sphere":
        raise InputError(f"model hertz is the sphere's closed form; got indenter {scene.indenter!r} "
                         f"(use model exact or goodman)")
    P, mu = scene.P, scene.mu
    a = (3.0 * P / 32.0) ** (1.0 / 3.0)
    film = Film()
    L = domain_length or (2.0 * a + film.domain_margin(tol))
    L = (L, L) if np.ndim(L) == 0 else tuple(L)
    if grid_points:
        shape = (grid_points, grid_points) if np.ndim(grid_points) == 0 else tuple(grid_points)
    else:
        dx = min(math.pi / _K_NYQUIST_MIN, 2.0 * a / 64) if a > 0 else math.pi / _K_NYQUIST_MIN
        shape = tuple(min(pow2_at_least(Li / dx, 64), 4096) for Li in L)
    g = Grid.centered(shape, L)
    x, y = g.coordinates()
    r2 = x * x + y * y
    p = (16.0 * a / math.pi) * np.sqrt(np.maximum(1.0 - r2 / (a * a), 0.0)) if a > 0 else \
        np.zeros(shape)
    p = np.broadcast_to(p, shape).copy()
    if a > 0:  # the sampled sqrt profile misses ~1e-4 of the load at the rim: restore it exactly
        p *= P / (p.sum() * g.cell)
    fft = get_rfft(shape)
    shear = (mu * p, np.zeros(shape))
    szz, (sxz, syz) = film.base_stresses(fft, g, -p, shear)
    (ux, uy), delta = film.surface_displacements(fft, g, p, shear)
    i0, j0 = (n // 2 for n in shape)
    q = {"area": math.pi * a * a, "x_min": -a, "x_max": a, "y_min": -a, "y_max": a,
         "pmax": 16.0 * a / math.pi, "xmax": 0.0, "ymax": 0.0, "xc": 0.0, "load": P,
         "line_load_y0": 8.0 * a * a,  # Int (16a/pi) sqrt(1 - x^2/a^2) dx
         "indentation": float(delta[i0, j0])}
    info = {"model_note": "Hertz pressure on the film (sphere, incompressible half-space, "
                          "friction uncoupled); base transfer exact",
            "half_space_indentation": 2.0 * a * a,
            "image_error": math.exp(-DECAY_RATE * max(min(L) - 2.0 * a, 0.0))}
    wall = time.perf_counter() - t0
    return ContactResult3D(scene, "hertz", "closed-form", g.axes[0], g.axes[1], p, szz, sxz, syz,
                           ux, uy, -delta, q, shape, L, 0, 0.0, 1e-12 if a > 0 else 0.0, wall,
                           0.0, info, {"transforms": 5, "iterations": 0, "linear_iterations": 0})
