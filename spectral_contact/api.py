"""The front function: ``solve`` (in the spirit of scipy.integrate.solve_ivp).

    >>> from spectral_contact import solve
    >>> r = solve(load=200.0, mu=2.0)            # the paper's scene, SI inputs
    >>> r.half_width_m, r.max_pressure * r.scene.stress_unit

Methods are registered by name in ``METHODS``; models are "exact" (the paper's exact model:
Amontons friction coupled into the contact), "goodman" (frictionless pressure kept, friction
loads the base only), "hertz" (closed form) and "auto" (the cheapest adequate one).
"""
from __future__ import annotations

from .physics.scene import Scene, check_positive, check_tol
from .result import ContactResult
from .solvers.registry import METHODS, MODELS, solve_scene

__all__ = ["solve", "METHODS", "MODELS", "check_tol"]


def solve(scene: Scene | None = None, *, model: str = "exact", method: str = "fft",
          tol: float = 1e-4, grid_points: int | None = None, domain_length: float | None = None,
          **params) -> ContactResult:
    """Solve one sliding-cylinder scene.

    Parameters
    ----------
    scene : Scene, optional
        The scene (SI).  If omitted, built from ``params`` (``load`` [N/m], ``mu``, ``young``
        [Pa], ``radius`` [m], ``thickness`` [m]; beyond the paper's assumptions: ``poisson``
        in [0, 0.5], ``friction_law`` "amontons" | "power" | "linear" with
        ``friction_exponent``, ``friction_pref`` [Pa], ``shear_strength`` [Pa],
        ``shear_slope``; ``interface_compliance`` [m/Pa], or ``interface_law`` "exponential"
        with ``interface_pressure`` [Pa] and ``interface_length`` [m]: see ``Scene``) over
        the paper's defaults.  Those refinements need the FFT method and model exact or
        goodman (auto picks exact).
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
        Relative accuracy target of a, contact centre, indentation and peak pressure, in (0, 0.1).
    grid_points : int, optional
        Fix the number of grid points (FFT, 64 ... 2^24) or Nystrom nodes (Abel, 6 ... 2000)
        instead of choosing it from ``tol``.
    domain_length : float, optional
        Fix the FFT period [m] instead of choosing it from ``tol`` (FFT only; the Abel method
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
    if scene is None:
        scene = Scene(**params)
    elif params:
        scene = scene.with_(**params)
    L_h = None
    if domain_length is not None:
        L_h = check_positive("domain_length", domain_length, "m") / scene.length_unit
    return solve_scene(scene, model, method, tol, grid_points, L_h)
