"""Models and methods by name: ``solve_scene`` dispatches one scene.

Models: "exact" and "goodman" are solved by a registered method (``base.METHODS``: "fft",
"abel"); "hertz" is closed form whatever the method; "auto" picks the cheapest of the three whose
fitted error bound is below tol (``auto.choose_model``) and reports why in ``info``.
"""
from __future__ import annotations

from ..errors import InputError
from ..physics.scene import Scene, Scene3D
from ..reference.hertz import hertz_half_width
from ..result import ContactResult
from . import abel as _abel  # noqa: F401  (registers "abel")
from . import fft as _fft  # noqa: F401  (registers "fft")
from .auto import PROVENANCE, choose_model
from .base import METHODS
from .hertz import solve_hertz, solve_hertz3d

__all__ = ["MODELS", "METHODS", "solve_scene", "make_method"]

MODELS = ("exact", "goodman", "hertz", "auto")


def make_method(method: str, tol: float, grid_points=None, domain_length=None):
    """The registered method ``method``, constructed (and its options validated)."""
    if not isinstance(method, str) or method not in METHODS:
        raise InputError(f"method must be one of {', '.join(METHODS)}; got {method!r}")
    return METHODS[method](tol=tol, grid_points=grid_points, domain_length=domain_length)


def solve_scene(scene: Scene, model: str, method: str, tol: float, grid_points=None,
                domain_length=None) -> ContactResult:
    """Solve ``scene`` (SI) with ``model`` by ``method``; ``domain_length`` in h."""
    if not isinstance(model, str) or model not in MODELS:
        raise InputError(f"model must be one of {', '.join(MODELS)}; got {model!r}")
    custom = scene.custom()  # a user's indenter or film kind: the FFT method's exact/goodman
    if custom and (model == "hertz" or method != "fft"):
        which = "model hertz" if model == "hertz" else f"method {method}"
        raise InputError(f"{which} solves the built-in cylinder, sphere and film only; {custom} "
                         f"needs method fft and model exact or goodman")
    if isinstance(scene, Scene3D):
        if method != "fft":
            raise InputError(f"method {method!r} is for a line indenter (plane strain); 3D "
                             f"indenters use method fft")
        if model == "auto":
            raise InputError("model auto is for a line indenter; use exact, goodman or hertz in 3D")
        solver = make_method(method, tol, grid_points, domain_length)
        if model == "hertz":
            if scene.poisson != 0.5:
                raise InputError(f"model hertz is the incompressible half-space (poisson 0.5) only; "
                                 f"got poisson {scene.poisson:g}: use model exact or goodman")
            return solve_hertz3d(scene, solver.tol, grid_points, domain_length)
        return solver.solve(scene, model)
    solver = make_method(method, tol, grid_points, domain_length)
    if scene.poisson != 0.5 and model == "hertz":
        raise InputError(f"model hertz is the incompressible half-space (poisson 0.5) only; got "
                         f"poisson {scene.poisson:g}: use model exact or goodman")
    if not scene.friction.is_amontons and model == "hertz":
        raise InputError(f"model hertz takes Amontons friction only; got friction law "
                         f"{scene.friction_law}: use model exact or goodman")
    soft = scene.interface_compliance != 0.0 or scene.interface_law != "linear"
    if soft and model == "hertz":
        raise InputError(f"model hertz has a rigid interface only; got interface compliance "
                         f"{scene.interface_compliance:g} m/Pa, law {scene.interface_law}: use "
                         "model exact or goodman")
    if model == "hertz":  # closed form, whatever the method
        return solve_hertz(scene, tol=solver.tol, grid_points=solver.grid_points,
                           domain_length=domain_length)
    if model != "auto":
        return solver.solve(scene, model)
    s = hertz_half_width(scene.P)
    if scene.poisson != 0.5 or not scene.friction.is_amontons or soft or custom:
        # the bounds were fitted on incompressible films with Amontons friction only
        why = (custom if custom else f"poisson {scene.poisson:g} < 0.5" if scene.poisson != 0.5 else
               f"friction law {scene.friction_law}" if not scene.friction.is_amontons else
               "a compliant interface")
        r = solver.solve(scene, "exact")
        r.info.update({"auto": "exact", "auto_reason": f"exact: {why}, outside the validated map "
                       "(the fitted bounds are for nu = 0.5, Amontons friction and a rigid "
                       "interface)",
                       "auto_bounds": {}, "auto_provenance": PROVENANCE})
        return r
    chosen, reason, bounds = choose_model(s, scene.mu, solver.tol)
    if chosen == "hertz":
        r = solve_hertz(scene, tol=solver.tol, grid_points=solver.grid_points,
                        domain_length=domain_length)
    else:
        r = solver.solve(scene, chosen)
    r.info.update({"auto": chosen, "auto_reason": reason, "auto_bounds": bounds,
                   "auto_provenance": PROVENANCE})
    return r
