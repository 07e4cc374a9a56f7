"""The front function: ``solve`` (in the spirit of scipy.integrate.solve_ivp).

    >>> from spectral_contact import solve
    >>> r = solve(load=200.0, mu=2.0)            # the paper's scene, SI inputs
    >>> r.half_width_m, r.max_pressure * r.scene.stress_unit

Methods are registered by name in ``METHODS``; models are "exact" (the paper's exact model:
Amontons friction coupled into the contact), "goodman" (frictionless pressure kept, friction
loads the base only), "hertz" (closed form) and "auto" (the cheapest adequate one).
"""
from __future__ import annotations

import dataclasses
import math

from .errors import InputError
from .physics.scene import Scene, check_positive, check_tol
from .result import ContactResult
from .solvers.registry import METHODS, MODELS, solve_scene

__all__ = ["solve", "METHODS", "MODELS", "check_tol"]

_SCENE_FIELDS = tuple(f.name for f in dataclasses.fields(Scene))


def solve(scene: Scene | None = None, *, model: str = "exact", method: str = "fft",
          tol: float = 1e-4, grid_points: int | None = None, domain_length: float | None = None,
          **params) -> ContactResult:
    """Solve one sliding-cylinder scene.

    Parameters
    ----------
    scene : Scene, optional
        The scene (SI).  If omitted, built from ``params`` (``load`` [N/m], ``mu``, ``young``
        [Pa], ``radius`` [m], ``thickness`` [m]) over the paper's defaults.
    model : {"exact", "goodman", "hertz", "auto"}
        "exact": the paper's exact model (friction coupled into the contact); "goodman":
        frictionless pressure and window, friction loads the base only; "hertz": closed-form
        half-space Hertz pressure on the film (``method`` is not used); "auto": the cheapest of
        the three whose fitted error bound at this scene is below ``tol``
        (``result.info["auto_reason"]`` says which and why).
    method : {"fft", "abel"}
        "fft": spectral solver on a periodic grid (default).  "abel": the paper's Abel/Fredholm
        formulation (an independent check).
    tol : float
        Relative accuracy target of a, contact centre, indentation and peak pressure, in [1e-14, 0.1).
    grid_points : int, optional
        Fix the number of grid points (FFT, 64 ... 2^22) or Nystrom nodes (Abel, 6 ... 2000)
        instead of choosing it from ``tol``; if the error estimate then exceeds ``tol``,
        ``result.tolerance_met`` is False (the summary's "tolerance_met").
    domain_length : float, optional
        Fix the FFT period [m] instead of choosing it from ``tol``; its periodic images' error
        is included in ``error_estimate``, and a period too short for the contact plus the
        images' decay to tol/2 is refused (InputError naming the minimum) (FFT only; the Abel method
        needs no domain).

    Returns
    -------
    ContactResult
        Dimensionless fields plus SI views; ``summary()`` gives the JSON record.

    Raises
    ------
    InputError
        A parameter out of range (the message names it and the accepted range).
    ConvergenceError
        A solver did not converge (carries the residual history).
    """
    if scene is not None and not isinstance(scene, Scene):
        raise InputError(f"scene must be a Scene (or omitted, with load=..., mu=... given by "
                         f"name); got {type(scene).__name__} {scene!r:.40}")
    unknown = sorted(set(params) - set(_SCENE_FIELDS))
    if unknown:
        raise InputError(f"unknown parameter {unknown[0]!r}: solve accepts model, method, tol, "
                         f"grid_points, domain_length and the scene's {', '.join(_SCENE_FIELDS)}")
    if scene is None:
        scene = Scene(**params)
    elif params:
        scene = scene.with_(**params)
    L_h = None
    if domain_length is not None:
        L_h = check_positive("domain_length", domain_length, "m") / scene.length_unit
        if not math.isfinite(L_h):
            raise InputError(f"domain_length must be a finite multiple of the film thickness; "
                             f"got {domain_length:g} m for h = {scene.thickness:g} m")
    return solve_scene(scene, model, method, tol, grid_points, L_h)
