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

from .errors import InputError, named
from .physics.film import Film
from .physics.interface import Interface
from .physics.options import INDENTERS, INDENTERS_3D, OPTIONS, check_applies
from .physics.scene import Scene, Scene3D, check_positive, check_tol
from .physics.shapes import Shape
from .result import ContactResult, ContactResult3D
from .solvers.fft3d import default_tol
from .solvers.registry import METHODS, MODELS, solve_scene

__all__ = ["solve", "make_scene", "METHODS", "MODELS", "check_tol"]

_SCENE3D_FIELDS = tuple(f.name for f in dataclasses.fields(Scene3D) if f.name != "indenter")


def solve(scene: Scene | Scene3D | None = None, *, film: Film | None = None, indenter=None,
          interface: Interface | None = None, model: str = "exact", method: str = "fft",
          tol: float | None = None, grid_points=None, domain_length=None,
          **params) -> ContactResult | ContactResult3D:
    """Solve one scene: a line indenter (plane strain, the paper's model) or a 3D indenter.

    The scene is given whole (``scene``), or composed (``film``, ``indenter``, ``interface``
    and the load), or by its parameters over the paper's defaults (the shorthands below); not
    two of these for one quantity (``solve(Scene(load=100), load=200)`` is refused: write
    ``solve(scene.with_(load=200))``).

        solve(film=Film(thickness=2e-3, young=2.2e6, poisson=0.45), interface=Interface(mu=1),
              load=100.0)
        solve(load=50, mu=0.5)                       # shorthand: the scene's fields by name
        solve(indenter="sphere", force=0.2)
        solve(indenter=lambda x: x**2 / 0.26, load=100.0)          # any line shape [m -> m]
        solve(indenter=lambda x, y: (x**2 + y**2) / 0.26, extent=2e-3, force=0.2)   # surface

    Parameters
    ----------
    scene : Scene or Scene3D, optional
        The scene (SI), whole.
    film : physics.film.Film, optional
        The film: ``Film(thickness=h [m], young=E [Pa], poisson=nu)``, or a subclass with its own
        symbols (README, "Adding things").  Default: the paper's film (``thickness``,
        ``young``, ``poisson`` by name).
    indenter : Shape, str or callable, optional
        "line" (default: the plane-strain cylinder of radius ``radius``, loaded by ``load``
        [N/m]), "sphere", "cylinder" (finite, ``length`` [m]), "paraboloid" (``radius_x``,
        ``radius_y`` [m]), pressed with ``force`` [N]; or any shape, a height function [m] of
        the position [m] from the apex (+inf where there is no indenter): of one argument
        height(x) a line indenter loaded per unit length (``load``), of two height(x, y) a
        surface indenter loaded by ``force``; ``extent`` [m] bounds the contact's half-extent
        (default 2 h).  A user's shape needs the FFT method and model exact or goodman.
        ``Shape.sphere(radius=...)``, ``Shape.cylinder(radius, length)``, ... hold the kind
        and its dimensions in one object.
    interface : physics.interface.Interface, optional
        Friction and closure: ``Interface(mu=..., friction=FrictionLaw(...), compliance=...)``.
        Default: Amontons friction of ``mu``, rigid (the shorthands name the scene's fields:
        ``mu``, ``friction_law``, ``friction_exponent``, ``friction_pref`` [Pa],
        ``shear_strength`` [Pa], ``shear_slope``, ``interface_compliance`` [m/Pa],
        ``interface_law`` "exponential" with ``interface_pressure`` [Pa] and
        ``interface_length`` [m]; ``physics.options`` lists each with its range).
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
    parts = {k: v for k, v in (("film", film), ("indenter", indenter), ("interface", interface))
             if v is not None}
    if scene is not None and (params or parts):
        given = ", ".join(f"{k}={v!r:.20}" for k, v in (parts | params).items())
        raise InputError(f"solve(scene, {given}): give the scene or its parameters, not both "
                         f"(a changed copy: scene.with_({', '.join(params) or '...'}=...))")
    if scene is None:
        scene = make_scene(film=film, indenter="line" if indenter is None else indenter,
                           interface=interface, **params)
    if tol is None:
        tol = default_tol(scene) if scene.dimension == "surface" else 1e-4
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


def make_scene(indenter="line", *, film: Film | None = None, interface: Interface | None = None,
               **params) -> Scene | Scene3D:
    """The scene of ``solve``'s keyword parameters: ``Scene`` for a line indenter (or a height
    function of one argument), ``Scene3D`` otherwise (a height function of two).  ``film`` and
    ``interface`` set their fields of the scene; naming one of those fields as well is refused
    (given twice)."""
    if isinstance(indenter, Shape):  # its fields, each given once
        fields = indenter.scene_fields()
        indenter = fields.pop("indenter")
        twice = sorted(set(fields) & set(params))
        if twice:
            raise InputError(f"{named(twice[0])} and {named('indenter')} given both: give it "
                             f"once (in the Shape, or by name)")
        params = {**params, **fields}
    if callable(indenter):
        n = _arity(indenter)
        params = {"height": indenter, **params}
        indenter = "line" if n == 1 else "function"
    if not isinstance(indenter, str):
        raise InputError(f"{named('indenter')} must be one of {', '.join(INDENTERS)} or a height "
                         f"function; got {type(indenter).__name__}")
    if indenter != "line" and indenter not in INDENTERS_3D:
        raise InputError(f"{named('indenter')} must be one of {', '.join(INDENTERS)} or a height "
                         f"function; got {indenter!r}")
    fields = dict(params)
    for what, obj, kind in (("film", film, Film), ("interface", interface, Interface)):
        if obj is None:
            continue
        if not isinstance(obj, kind):
            raise InputError(f"{named(what)} must be a {kind.__name__}; got {type(obj).__name__}")
        sets = obj.scene_fields() if what == "interface" else {"film": obj}
        twice = sorted(set(sets) & set(params)) or (
            sorted({"thickness", "young", "poisson"} & set(params)) if what == "film" else [])
        if twice:
            raise InputError(f"{named(twice[0])} and {named(what)} given both: give it once "
                             f"(in the {what}, or by name without {what}=)")
        fields |= sets
    known = {f.name for f in dataclasses.fields(Scene)} | set(_SCENE3D_FIELDS)
    unknown = sorted(set(fields) - known)
    if unknown:
        raise InputError(f"unknown parameter {unknown[0]!r}: solve accepts scene, film, indenter, "
                         f"interface, model, method, tol, grid_points, domain_length and the "
                         f"scene's {', '.join(o.name for o in OPTIONS if o.scenes != 'solve')}")
    check_applies(fields, indenter)
    if indenter == "line":
        return Scene(**fields)
    return Scene3D(indenter=indenter, **fields)


def _arity(function) -> int:
    """1 or 2: how many positions a height function takes (x, or x and y)."""
    import inspect

    try:
        sig = inspect.signature(function)
    except (TypeError, ValueError):
        return 2  # a builtin or ufunc: taken as a surface's, as before
    kinds = (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD)
    required = [p for p in sig.parameters.values()
                if p.kind in kinds and p.default is inspect.Parameter.empty]
    if len(required) not in (1, 2):
        raise InputError(f"{named('indenter')}: a height function takes one position (x [m]: a "
                         f"line indenter) or two (x, y [m]: a surface indenter); this one takes "
                         f"{len(required)}")
    return len(required)
