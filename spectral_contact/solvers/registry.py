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
from . import fft_method as _fft  # noqa: F401  (registers "fft")
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
    if getattr(scene, "prony", ()) and (model == "hertz" or method != "fft"
                                        or (model == "auto" and scene.dimension == "surface")):
        # issue 23: the viscoelastic film's symbol is in the FFT solver only
        raise InputError(f"--prony (a viscoelastic film) needs --model exact or goodman (auto: "
                         f"line indenter) and --method fft; got --model {model}, --method {method}")
    if getattr(scene, "prony", ()) and model == "auto":
        return _viscous_auto(scene, tol, make_method(method, max(0.25 * tol, 1e-14), grid_points,
                                                     domain_length))
    custom = scene.custom()  # a user's indenter or film kind: the FFT method's exact/goodman
    if custom and (model == "hertz" or method != "fft"):
        which = "model hertz" if model == "hertz" else f"method {method}"
        raise InputError(f"{which} solves the built-in cylinder, sphere and film only; {custom} "
                         f"needs method fft and model exact or goodman")
    return _SOLVE[scene.dimension](scene, model, method, tol, grid_points, domain_length, custom)


def _solve_surface(scene: Scene3D, model, method, tol, grid_points, domain_length, custom):
    """A surface indenter: method fft, model exact, goodman or hertz (no auto)."""
    if method != "fft":
        raise InputError(f"method {method!r} is for a line indenter (plane strain); 3D "
                         f"indenters use method fft")
    if model == "auto":
        raise InputError("model auto is for a line indenter; use exact, goodman or hertz in 3D")
    solver = make_method(method, tol, grid_points, domain_length)
    if model == "hertz":
        if scene.poisson != 0.5:
            raise InputError(f"model hertz is the incompressible half-space (poisson 0.5) only; "
                             f"got poisson {scene.poisson:.10g}: use model exact or goodman")
        return solve_hertz3d(scene, solver.tol, grid_points, domain_length)
    return solver.solve(scene, model)


def _solve_line(scene: Scene, model, method, tol, grid_points, domain_length, custom):
    """A line indenter: any method; model hertz closed form; auto by the fitted bounds."""
    solver = make_method(method, tol, grid_points, domain_length)
    if scene.poisson != 0.5 and model == "hertz":
        raise InputError(f"model hertz is the incompressible half-space (poisson 0.5) only; got "
                         f"poisson {scene.poisson:.10g}: use model exact or goodman")
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
        why = (custom if custom else f"poisson {scene.poisson:.10g} < 0.5" if scene.poisson != 0.5 else
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


_SOLVE = {"line": _solve_line, "surface": _solve_surface}
"""What ``solve_scene`` dispatches on: the scene's ``dimension``."""


def _viscous_auto(scene: Scene, tol: float, solver) -> ContactResult:
    """Model auto for a viscoelastic film (issue 23): the exact model on the viscoelastic film,
    and the viscous effect measured against the relaxed elastic film (E_inf, the same scene at
    rest), both solved at tol/4 (``solver``: so that their error estimates leave half of tol to
    the effect; about twice the work of one solve at tol, or more): the largest relative change of a,
    x0 (over a), Q/P (mu + mu_def on both) and the base stresses (max |difference| / max
    |elastic|).  ``auto_reason`` says whether the elastic film is enough at tol (change + both
    error estimates <= tol); the result is the viscoelastic solve (at tol/4)."""
    import numpy as np

    r = solver.solve(scene, "exact")
    el = solver.solve(scene.with_(speed=0.0), "exact")  # V = 0: the relaxed film, bit for bit
    a = el.half_width
    L = r.domain_length

    def base(field):
        g = np.interp(el.x, r.x, getattr(r, field), period=L)
        e = getattr(el, field)
        return float(np.max(np.abs(g - e)) / max(float(np.max(np.abs(e))), 1e-300))

    qp_el = el.friction_ratio + el.deformation_friction
    changes = {"a": abs(r.half_width - a) / a, "x0": abs(r.center - el.center) / a,
               "Q_over_P": abs(r.Q_over_P - qp_el) / max(abs(qp_el), 1e-300),
               "base_sigma_zz": base("base_sigma_zz"), "base_sigma_xz": base("base_sigma_xz")}
    worst = max(changes, key=changes.get)
    bound = changes[worst] + r.error_estimate + el.error_estimate
    enough = bound <= tol
    r.info.update({
        "auto": "exact", "auto_viscous_changes": changes, "auto_viscous_bound": bound,
        "auto_reason": (f"exact on the viscoelastic film; viscous effect against the relaxed "
                        f"elastic film (E_inf; both solved at tol/4): largest change "
                        f"{changes[worst]:.2e} ({worst}), bound {bound:.2e} with both error "
                        f"estimates: the elastic film is {'enough' if enough else 'not enough'} "
                        f"at tol {tol:g}")})
    return r
