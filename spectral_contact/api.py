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

import numpy as np

from .errors import InputError
from .physics.scene import Scene, Scene3D, check_positive, check_tol
from .result import ContactResult, ContactResult3D
from .solvers.fft3d import default_tol
from .solvers.registry import METHODS, MODELS, solve_scene

__all__ = ["solve", "make_scene", "METHODS", "MODELS", "check_tol"]

_SCENE_FIELDS = tuple(f.name for f in dataclasses.fields(Scene))
_SCENE3D_FIELDS = tuple(f.name for f in dataclasses.fields(Scene3D) if f.name != "indenter")


def solve(scene: Scene | Scene3D | None = None, *, model: str = "exact", method: str = "fft",
          tol: float | None = None, grid_points=None, domain_length=None,
          **params) -> ContactResult | ContactResult3D:
    """Solve one scene: a line indenter (plane strain, the paper's model) or a 3D indenter.

    Parameters
    ----------
    scene : Scene or Scene3D, optional
        The scene (SI).  If omitted, built from ``params`` over the paper's defaults: a line
        indenter (``Scene``: ``load`` [N/m], ``mu``, ``young`` [Pa], ``radius`` [m],
        ``thickness`` [m]) unless ``indenter`` is given: "line" (the default), "sphere",
        "cylinder" (finite, ``length`` [m]), "paraboloid" (``radius_x``, ``radius_y`` [m]) or a
        callable height(x_m, y_m) -> m (any shape), each pressed with ``force`` [N]
        (``Scene3D``).  ``load`` with a 3D indenter, or ``force`` with a line, is an InputError.
        Beyond the paper's assumptions (line indenter, ``Scene``): ``poisson`` in [0, 0.5],
        ``friction_law`` "amontons" | "power" | "linear" with ``friction_exponent``,
        ``friction_pref`` [Pa], ``shear_strength`` [Pa], ``shear_slope``;
        ``interface_compliance`` [m/Pa], or ``interface_law`` "exponential" with
        ``interface_pressure`` [Pa] and ``interface_length`` [m]: they need the FFT method and
        model exact or goodman (auto picks exact).
    model : {"exact", "goodman", "hertz", "auto"}
        "exact": the paper's exact model (friction coupled into the contact); "goodman":
        frictionless pressure and window, friction loads the base only; "hertz": closed-form
        half-space Hertz pressure on the film (``method`` is not used; in 3D: sphere only);
        "auto" (line only): the cheapest of the three whose fitted error bound at this scene is
        below ``tol`` (``result.info["auto_reason"]`` says which and why).
    method : {"fft", "abel"}
        "fft": spectral solver on a periodic grid (default; 1D grid for a line, 2D for 3D
        indenters).  "abel": the paper's Abel/Fredholm formulation (line only: an independent
        check).
    tol : float, optional
        Relative accuracy target, in [1e-14, 0.1): of a, contact centre, indentation and peak
        pressure (line; default 1e-4); of the contact radius, centroid, indentation, line load
        at y = 0 and peak pressure (3D; default 1e-3: each halving of the cell costs 4x in 2D
        grids; 1e-2 for the finite cylinder, whose sharp ends converge at first order only).
    grid_points : int or [nx, ny], optional
        Fix the number of grid points (FFT, 64 ... 2^22; 3D: per axis, >= 32, even) or Nystrom
        nodes (Abel, 6 ... 2000) instead of choosing it from ``tol``; if the error estimate then
        exceeds ``tol``, ``result.tolerance_met`` is False (the summary's "tolerance_met").
    domain_length : float or [Lx, Ly], optional
        Fix the FFT period [m] instead of choosing it from ``tol``; its periodic images' error
        is included in ``error_estimate`` (line), and a period too short for the contact plus
        the images' decay to tol/2 is refused (InputError naming the minimum) (FFT only; the
        Abel method needs no domain).

    Returns
    -------
    ContactResult (line) or ContactResult3D (3D indenters)
        Dimensionless fields plus SI views; ``summary()`` gives the JSON record.

    Raises
    ------
    InputError
        A parameter out of range (the message names it and the accepted range).
    ConvergenceError
        A solver did not converge (carries the residual history).
    """
    if scene is not None and not isinstance(scene, (Scene, Scene3D)):
        raise InputError(f"scene must be a Scene or Scene3D (or omitted, with load=..., mu=... "
                         f"given by name); got {type(scene).__name__} {scene!r:.40}")
    three_d = isinstance(scene, Scene3D) or params.get("indenter", "line") != "line"
    fields = _SCENE3D_FIELDS if three_d else _SCENE_FIELDS
    unknown = sorted(set(params) - set(fields) - {"indenter"})
    if unknown and not (not three_d and set(unknown) <= set(_SCENE3D_FIELDS)):
        raise InputError(f"unknown parameter {unknown[0]!r}: solve accepts model, method, tol, "
                         f"grid_points, domain_length, indenter and the scene's {', '.join(fields)}")
    if scene is None:
        scene = make_scene(**params)
    elif params:
        scene = scene.with_(**params)
    if tol is None:
        tol = default_tol(scene) if isinstance(scene, Scene3D) else 1e-4
    L_h = None
    if domain_length is not None:
        values = domain_length if np.ndim(domain_length) else [domain_length]
        L_h = [check_positive("domain_length", v, "m") / scene.length_unit for v in values]
        if not all(math.isfinite(v) for v in L_h):
            raise InputError(f"domain_length must be a finite multiple of the film thickness; "
                             f"got {domain_length} m for h = {scene.thickness:g} m")
        if not np.ndim(domain_length):
            L_h = L_h[0]
    return solve_scene(scene, model, method, tol, grid_points, L_h)


def make_scene(indenter="line", **params) -> Scene | Scene3D:
    """The scene for ``solve``'s keyword parameters: ``Scene`` for a line indenter,
    ``Scene3D`` otherwise (a callable ``indenter`` is a height function of (x, y) [m])."""
    if callable(indenter):
        params = {"height": indenter, **params}
        indenter = "function"
    if indenter == "line":
        if "force" in params:
            raise InputError("force [N] is for 3D indenters (sphere, cylinder, paraboloid); a line "
                             "indenter takes load [N/m]")
        known = {f.name for f in dataclasses.fields(Scene)}  # incl. issue 14's refinements
        bad = set(params) - known
        if bad:
            raise InputError(f"{', '.join(sorted(bad))}: not a parameter of a line indenter "
                             f"({', '.join(sorted(known))})")
        return Scene(**params)
    if "load" in params:
        raise InputError(f"load [N/m] is for a line indenter; a {indenter} takes force [N]")
    return Scene3D(indenter=indenter, **params)
