"""The scene's validation (``physics.scene``): the checks of single values (``check_finite``,
``check_positive``, ``check_poisson``, ``check_tol``), the units warning outside soft-contact
practice, and the checks that relate several fields (a film given whole, the friction law's
scales and film, the viscoelastic film's speed and Prony terms).  Each refusal is one
InputError line naming the option as the user typed it (``errors.named``).
"""
from __future__ import annotations

import math
import numbers

from ..errors import InputError, named
from . import options as _options
from .film import Film
from .options import default

__all__ = ["check_finite", "check_positive", "check_poisson", "check_tol", "UnitsWarning",
           "SOFT_CONTACT_RANGES", "A_OVER_H_MAX", "LAW_SCALE_MAX", "SHAPE_RATIO_MIN",
           "SHAPE_RATIO_MAX", "PRONY_RATIO_RANGE", "RELAXATION_LENGTH_RANGE"]


def check_finite(name: str, value, accepted: str) -> float:
    """A real number (int, float, numpy scalar; not bool, str or bytes), finite as a float.
    ``name``, if a Python name, is marked (``errors.named``): the command line says its flag."""
    name = named(name) if name.isidentifier() else name
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be a number ({accepted}); got {_short(value)}")
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be a finite number ({accepted}); got "
                         f"{_short(value)}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be finite ({accepted}); got {v}")
    return v


def _short(value, n: int = 40) -> str:
    r = repr(value)
    return r if len(r) <= n else r[:n] + "..."


def check_positive(name: str, value, unit: str) -> float:
    v = check_finite(name, value, f"> 0 {unit}".strip())
    if v <= 0.0:
        name = named(name) if name.isidentifier() else name
        raise InputError(f"{name} must be > 0 {unit}; got {v}".replace("  ", " "))
    return v


def check_poisson(nu) -> float:
    """A Poisson ratio in [0, 0.5] (0.5: incompressible): ``options`` "poisson"."""
    return _options.option("poisson").check(nu)


def check_tol(tol) -> float:
    """A relative accuracy target: a number in [TOL_MIN, 0.1) (``options`` "tol")."""
    return _options.option("tol").check(tol)


A_OVER_H_MAX = 1e8
"""Largest Hertz half-width a_H/h = sqrt(P / 2 pi) accepted: the FFT solver is verified to 1e8
frictionless (with friction it stops converging, exit 3, from ~1e3); beyond, the film's scales
leave floating-point range."""
_TYPICAL = {"load": 200.0, "young": 2.2e6, "radius": 0.130, "thickness": 0.002}


LAW_SCALE_MAX = 1e8
"""Bound on the friction law's stress parameters (p_ref, tau_0) over the scene's stress unit
E h/(6R): beyond it the local friction coefficient mu (p/p_ref)^-n (or tau_0 against p) is
under- or overflowing nonsense (p_ref = 5e-324 Pa divided by zero; 1e300 Pa never converged)."""
SHAPE_RATIO_MIN, SHAPE_RATIO_MAX = 1e-6, 1e6
"""Bounds on a 3D indenter's shape ratios (cylinder length / h, paraboloid radii / radius): a
subnormal length divided by zero, a subnormal radius_x never converged."""


SOFT_CONTACT_RANGES = {o.name: (*o.practice, o.unit) for o in _options.OPTIONS if o.practice}
"""Soft-contact practice (elastomer films, gels, skin): E from 1 kPa to 1 GPa, films from 1 um
to 10 cm, indenter radii from 1 um to 10 m, cylinder lengths from 10 um to 1 m.  A value
outside is accepted (the model is scale-free) with one warning: it is most often a units slip
(thickness=2 meant in mm, E in MPa)."""


class UnitsWarning(UserWarning):
    """A value outside ``SOFT_CONTACT_RANGES``; ``option`` is the parameter's Python name (the
    command line names it as typed)."""

    def __init__(self, message, option=None):
        super().__init__(message)
        self.option = option


def _warn_units(scene) -> None:
    import warnings

    for name, (lo, hi, unit) in SOFT_CONTACT_RANGES.items():
        v = getattr(scene, name, None)
        if v is not None and not lo <= v <= hi:
            warnings.warn(UnitsWarning(f"{name} = {v:g} {unit} is outside soft-contact practice "
                                       f"[{lo:g}, {hi:g}] {unit}: is it in SI units?", name),
                          stacklevel=4)


def _check_law_scales(scene) -> None:
    """The friction law's stresses within LAW_SCALE_MAX of the stress unit (tau_0 may be 0)."""
    law, unit = scene.friction, scene.stress_unit
    for value, name, symbol in ((law.pref, "friction_pref", "p_ref"),
                                (law.shear_strength, "shear_strength", "tau_0")):
        if value is None or (value == 0.0 and name == "shear_strength"):
            continue
        ratio = abs(value) / unit
        if not 1.0 / LAW_SCALE_MAX <= ratio <= LAW_SCALE_MAX:
            raise InputError(f"{named(name)} ({symbol}) = {value:g} Pa is out of range: |value| / "
                             f"(E h/(6R) = {unit:.3g} Pa) = {ratio:.3g} must be in "
                             f"[{1 / LAW_SCALE_MAX:g}, {LAW_SCALE_MAX:g}]")


def _take_film_fields(scene) -> None:
    """A scene given a film kind that stands for scene fields (``Film.scene_fields``: a
    ``ViscoelasticFilm``'s thickness, poisson, E_inf, Prony terms and speed [m/s]): they become
    the scene's fields and the scene builds the film itself (one path: ``Scene.core_film``)."""
    film = scene.film
    if not isinstance(film, Film):
        return  # (_take_film names the type)
    fields = film.scene_fields()
    if not fields:
        return
    for name, its in fields.items():
        mine = getattr(scene, name)
        if name in ("speed", "prony"):
            given = mine is not None and (len(mine) > 0 if name == "prony" else mine != 0.0)
            if given:
                raise InputError(f"{named(name)} and {named('film')} ({type(film).__name__}) "
                                 f"given both: give it once (in the film, or by name without "
                                 f"film=)")
        elif mine != its and mine != default(name):
            raise InputError(f"{named(name)} = {mine:g} and {named('film')}.{name} = {its:g}: "
                             f"give the film's {name} once, in the film")
        object.__setattr__(scene, name, its)
    object.__setattr__(scene, "film", None)


def _take_film(scene) -> None:
    """A scene given ``film=``: its thickness, young and poisson are the film's (the scene's own
    fields left at their defaults, or equal)."""
    film = scene.film
    if film is None:
        return
    if not isinstance(film, Film):
        raise InputError(f"{named('film')} must be a physics.film.Film (or a subclass); got "
                         f"{type(film).__name__}")
    if film.young is None:
        raise InputError(f"{named('film')}: a scene's film needs its Young modulus, "
                         f"Film(thickness=h [m], young=E [Pa], poisson=nu)")
    for name in ("thickness", "young", "poisson"):
        mine, its = getattr(scene, name), getattr(film, name)
        if mine != its and mine != default(name):
            raise InputError(f"{named(name)} = {mine:g} and {named('film')}.{name} = {its:g}: "
                             f"give the film's {name} once, in the film")
        object.__setattr__(scene, name, its)


def _custom(scene) -> str | None:
    if scene.film is not None and type(scene.film) is not Film:
        return f"a user-defined film ({type(scene.film).__name__})"
    if not hasattr(scene, "indenter") and scene.height is not None:  # a line scene's height
        return "a user-defined line indenter"
    return None


def _check_law_and_film(scene) -> None:
    """The friction law's parameters belong to the law (``FrictionLaw``), and tau_0 != 0 needs
    an incompressible film."""
    law = scene.friction  # validates the law's parameters: one-line InputError
    if law.law == "linear" and law.shear_strength != 0.0 and scene.poisson != 0.5:
        # measured: the outer iteration settles on coarse grids but not under refinement
        # (the edge nodes keep flipping at 131072 points, nu = 0.45): a compressible film's
        # sinking kinks under the shear step tau_0 at the edge (its shear kernel ~ sgn x)
        raise InputError(f"{named('shear_strength')} (tau_0) != 0 needs {named('poisson')} 0.5: "
                         "with the shear step at the contact edge the friction-law iteration does "
                         f"not settle on a compressible film; got poisson {scene.poisson:.10g}")


def _check_viscoelastic(scene):
    """speed and prony (issue 23): validated, prony as a tuple of pairs; one-line InputError
    naming the command-line options."""
    v = _options.option("speed").check(scene.speed)  # the table's parsers (physics.options)
    object.__setattr__(scene, "speed", v)
    object.__setattr__(scene, "prony", _options.option("prony").check(scene.prony))
    if not scene.prony:
        if v != 0.0:  # an elastic film's steady sliding does not depend on V: not silently
            raise InputError(f"--speed {v:g} m/s needs --prony (the viscoelastic film's terms "
                             f"E1,tau1[,...]): an elastic film does not depend on the speed "
                             f"(--speed 0 or no --speed is the elastic solve)")
        return
    if check_poisson(scene.poisson) != 0.5:
        raise InputError(f"--prony needs --poisson 0.5 (the viscoelastic film is incompressible: "
                         f"with an elastic bulk modulus its symbol is not a scaling of the "
                         f"elastic one); got --poisson {scene.poisson:.10g}")
    if scene.friction_law != "amontons" or scene.interface_compliance or \
            getattr(scene, "interface_law", "linear") != "linear":
        raise InputError("--prony takes the Amontons friction law and a rigid interface only "
                         "(--friction-law amontons, no --interface-compliance/--interface-law)")
    if scene.film is not None or (getattr(scene, "height", None) is not None
                                  and not getattr(scene, "indenter", "") == "function"):
        raise InputError("--prony (a viscoelastic film) takes the scene's built-in film and, on a "
                         "line, the cylinder: no film= or height= with it")
    mu = check_finite("mu (mu_d)", scene.mu, "a finite real")
    if mu * v < 0.0:
        raise InputError(f"--speed and --mu both give the sliding direction: they must have the "
                         f"same sign (or one be 0); got --speed {v:g}, --mu {mu:g}")
    _check_visco_scales(scene, v)
    _warn_inertia(scene, v)


DENSITY_ASSUMED = 1000.0  # kg/m^3: elastomers and gels (PDMS 965), for the inertia warning only
INERTIA_WARN = 0.1  # |V| / c_s from which the neglected inertia is flagged ((V/c_s)^2 ~ 1 %)


def _warn_inertia(scene, v) -> None:
    """The steady-sliding solve is quasi-static: a speed past INERTIA_WARN of the relaxed film's
    shear-wave speed c_s = sqrt(E_inf / (3 rho)) (rho = DENSITY_ASSUMED) is flagged (a
    UserWarning; the command line prints it as one line), not refused."""
    import warnings

    c_s = math.sqrt(scene.young / (3.0 * DENSITY_ASSUMED))
    if abs(v) > INERTIA_WARN * c_s:
        warnings.warn(f"--speed {v:g} m/s is {abs(v) / c_s:.2g} of the film's shear-wave speed "
                      f"sqrt(E_inf/(3 rho)) = {c_s:.3g} m/s (rho = {DENSITY_ASSUMED:g} kg/m^3 "
                      f"assumed): the solve neglects inertia (quasi-static film), whose effect "
                      f"grows as (V/c_s)^2", UserWarning, stacklevel=5)


PRONY_RATIO_RANGE = (1e-12, 1e12)
"""E_i / E_inf a Prony term may have (beyond, the symbols' arithmetic under- or overflows: 1e-20
Pa against 2.2 MPa was a math domain error, 1e308 Pa an overflow)."""
RELAXATION_LENGTH_RANGE = (1e-50, 1e50)
"""|V| tau_i / h a moving Prony film may have (beyond, the relaxation tail's margin and edge
scale under- or overflow: tau 1e-300 s or 1e308 s at 5 cm/s, V 1e308 m/s crashed)."""


def _check_visco_scales(scene, v):
    """Each Prony term's modulus ratio and relaxation length within the ranges above (one line
    naming the option, exit 2 on the command line)."""
    lo, hi = PRONY_RATIO_RANGE
    young, h = scene.young, scene.thickness
    if not all(isinstance(a, (int, float)) and math.isfinite(a) and a > 0 for a in (young, h)):
        return  # refused by the options' own check
    for e, t in scene.prony:
        ratio = e / young
        if not lo <= ratio <= hi:
            raise InputError(f"--prony term E = {e:g} Pa is {ratio:.3g} times --young {young:g} "
                             f"Pa (E_inf): each E_i / E_inf must be in [{lo:g}, {hi:g}]")
        if v != 0.0:
            length = abs(v) * t / h
            if not RELAXATION_LENGTH_RANGE[0] <= length <= RELAXATION_LENGTH_RANGE[1]:
                raise InputError(
                    f"--speed {v:g} m/s and --prony tau = {t:g} s make a relaxation length "
                    f"|V| tau / h = {length:.3g}: it must be in [{RELAXATION_LENGTH_RANGE[0]:g}, "
                    f"{RELAXATION_LENGTH_RANGE[1]:g}] (--speed 0 is the relaxed film)")
