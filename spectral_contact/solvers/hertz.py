"""The Hertz model as a solver: closed-form contact (``reference.hertz``), base transfer exact."""
from __future__ import annotations

import math
import time

import numpy as np

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
from ..result import ContactResult
from .auto import model_error_bound
from .base import check_grid_points

__all__ = ["solve_hertz"]

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
