"""The front function: ``solve`` (in the spirit of scipy.integrate.solve_ivp).

    >>> from spectral_contact import solve
    >>> r = solve(load=200.0, mu=2.0)            # the paper's scene, SI inputs
    >>> r.half_width_m, r.max_pressure * r.scene.stress_unit

Methods are registered by name in ``METHODS``; models are "exact" (the paper's exact model:
Amontons friction coupled into the contact), "goodman" (frictionless pressure kept, friction
loads the base only), "hertz" (closed form) and "auto" (the cheapest adequate one).
"""
from __future__ import annotations

from .errors import InputError
from .physics.scene import Scene, check_positive, check_tol
from .result import ContactResult

__all__ = ["solve", "METHODS", "MODELS", "check_tol"]

MODELS = ("exact", "goodman", "hertz", "auto")


def _fft(scene, model, tol, grid_points, domain_length_h):
    from .solvers.fft import solve_fft

    return solve_fft(scene, model=model, tol=tol, grid_points=grid_points,
                     domain_length=domain_length_h)


def _abel(scene, model, tol, grid_points, domain_length_h):
    from .numerics.abel import solve_abel

    return solve_abel(scene, model=model, tol=tol, n_nodes=grid_points)


METHODS = {"fft": _fft, "abel": _abel}


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
    if model not in MODELS:
        raise InputError(f"model must be one of {', '.join(MODELS)}; got {model!r}")
    if method not in METHODS:
        raise InputError(f"method must be one of {', '.join(METHODS)}; got {method!r}")
    tol = check_tol(tol)
    if grid_points is not None:
        # FFT grid points, or Nystrom nodes for the Abel method
        lo, hi = (6, 2000) if method == "abel" else (64, 2**24)
        try:
            grid_points = int(grid_points)
        except (TypeError, ValueError):
            raise InputError(f"grid_points must be an integer in [{lo}, {hi}]; got {grid_points!r}") from None
        if not lo <= grid_points <= hi:
            raise InputError(f"grid_points must be in [{lo}, {hi}] for method {method}; got {grid_points}")
        if method == "fft" and grid_points % 2:
            raise InputError(f"grid_points must be even for method fft (a power of two is fastest); got {grid_points}")
    L_h = None
    if domain_length is not None and method != "fft":
        raise InputError(f"domain_length applies to method fft only (method {method} needs no domain)")
    if domain_length is not None:
        L_h = check_positive("domain_length", domain_length, "m") / scene.length_unit
    if model == "hertz":  # closed form, whatever the method
        from .solvers.hertz import solve_hertz

        return solve_hertz(scene, tol=tol, grid_points=grid_points, domain_length=L_h)
    if model == "auto":  # cheapest model whose fitted error bound is below tol
        from .solvers.auto import solve_auto

        return solve_auto(scene, tol, method, grid_points, L_h, methods=METHODS)
    return METHODS[method](scene, model, tol, grid_points, L_h)
