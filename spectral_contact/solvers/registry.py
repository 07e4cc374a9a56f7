"""Models and methods by name: ``solve_scene`` dispatches one scene.

Models: "exact" and "goodman" are solved by a registered method (``base.METHODS``: "fft",
"abel"); "hertz" is closed form whatever the method; "auto" picks the cheapest of the three whose
fitted error bound is below tol (``auto.choose_model``) and reports why in ``info``.
"""
from __future__ import annotations

from ..errors import InputError
from ..physics.scene import Scene
from ..reference.hertz import hertz_half_width
from ..result import ContactResult
from . import abel as _abel  # noqa: F401  (registers "abel")
from . import fft as _fft  # noqa: F401  (registers "fft")
from .auto import PROVENANCE, choose_model
from .base import METHODS
from .hertz import solve_hertz

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
    solver = make_method(method, tol, grid_points, domain_length)
    if model == "hertz":  # closed form, whatever the method
        return solve_hertz(scene, tol=solver.tol, grid_points=solver.grid_points,
                           domain_length=domain_length)
    if model != "auto":
        return solver.solve(scene, model)
    s = hertz_half_width(scene.P)
    chosen, reason, bounds = choose_model(s, scene.mu, solver.tol)
    if chosen == "hertz":
        r = solve_hertz(scene, tol=solver.tol, grid_points=solver.grid_points,
                        domain_length=domain_length)
    else:
        r = solver.solve(scene, chosen)
    r.info.update({"auto": chosen, "auto_reason": reason, "auto_bounds": bounds,
                   "auto_provenance": PROVENANCE})
    return r
