"""The physical scene in SI units, its validation, and the paper's dimensionless units.

Dimensionless core (the paper's, section "Exact model"):

* lengths in h (film thickness),
* displacements in h^2 / (2R),
* stresses in G h / (2R), G the film's shear modulus: G = E/3 for the incompressible film
  (nu = 1/2, the paper's E h / (6R)), G = E / (2(1 + nu)) in general,
* lineic load P = P_L * 2R / (G h^2) (= P_L 6R / (E h^2) at nu = 1/2).

In these units the indenter profile is x^2 and the Hertz half-space pressure is 4 sqrt(a^2 - x^2)
at nu = 1/2 (2/(1 - nu) sqrt(a^2 - x^2) in general, E* = 2G/(1 - nu)).  Keeping G (not E) in the
unit keeps the film's symbols free of nu at nu = 1/2 and O(1) for every nu: the compressible
film of the same E is stiffer in shear by 3/(2(1 + nu)) and its stress unit follows.

The validation of single values and of related fields is in ``physics.scene_checks`` (its names
importable from here too).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError, named
from . import options as _options
from .film import Film
from .friction import FrictionLaw
from .indenters import Cylinder, LineHeightFunction, user_heights
from .options import INDENTERS_3D, MU_MAX, TOL_MIN, check_prony, default  # noqa: F401
from .scene_checks import (  # noqa: F401  (the checks, importable from here as before)
    _TYPICAL,
    A_OVER_H_MAX,
    LAW_SCALE_MAX,
    PRONY_RATIO_RANGE,
    RELAXATION_LENGTH_RANGE,
    SHAPE_RATIO_MAX,
    SHAPE_RATIO_MIN,
    SOFT_CONTACT_RANGES,
    UnitsWarning,
    _check_law_and_film,
    _check_law_scales,
    _check_viscoelastic,
    _custom,
    _take_film,
    _take_film_fields,
    _warn_units,
    check_finite,
    check_poisson,
    check_positive,
    check_tol,
)

__all__ = ["Scene", "Scene3D", "INDENTERS_3D", "PAPER_SCENE", "check_finite", "check_positive",
           "check_tol", "check_poisson", "check_prony", "MU_MAX", "A_OVER_H_MAX", "TOL_MIN"]


@dataclass(frozen=True)
class Scene:
    """A rigid cylinder sliding on an elastic film (incompressible by default) bonded to a rigid
    base.

    Parameters (SI)
    ---------------
    load : float
        P_L, normal load per unit length of cylinder [N/m], >= 0 (0 means no contact).
    mu : float
        mu_d, dynamic (Amontons) friction coefficient, in [-MU_MAX, MU_MAX], signed: mu > 0 means the cylinder slides
        toward +x and drags the film surface toward +x (sigma_xz(x, h) = mu * p(x)); mu < 0 means
        sliding toward -x.
    young : float
        E, Young's modulus of the film [Pa].
    radius : float
        R, cylinder radius [m].
    thickness : float
        h, film thickness [m].
    poisson : float
        nu, the film's Poisson ratio, in [0, 0.5] (default 0.5: incompressible, the paper's
        assumption).  The shear modulus is G = E / (2(1 + nu)).
    friction_law : str
        "amontons" (default: q = mu p), "power" (q = mu (p/p_ref)^(-n) p) or "linear"
        (q = tau_0 + alpha p in the contact); ``physics.friction.FrictionLaw``.
    friction_exponent, friction_pref : float, optional
        n in [0, 1) and p_ref [Pa] > 0 of the power law (mu above is its mu_d).
    shear_strength, shear_slope : float, optional
        tau_0 [Pa] and alpha of the linear law (same sign; mu is then not used by the contact).
    interface_compliance : float
        C [m/Pa] >= 0, a linear compliance of the film-indenter interface (a rough or soft
        skin): the interface closes by C p, so the contact condition is f - d + w + C p = 0
        where p > 0 (default 0: rigid interface, the paper's).
    interface_law : str
        "linear" (default: ``interface_compliance``) or "exponential": the interface carries
        p = p0 exp(-g / lambda) at an interface gap g (the classical rough-contact form), with
    interface_pressure, interface_length : float, optional
        p0 [Pa] > 0 and lambda [m] > 0 of the exponential law (required by it, refused
        otherwise).  The exponential law has no sharp contact edges.
    height : callable, optional
        Any line indenter instead of the cylinder: height(x_m) -> f [m] above its lowest point
        (x an array of positions from the apex [m]; +inf where there is no indenter), loaded
        by ``load`` per unit length; ``radius`` is then only the unit of heights (h^2/2R).
        The FFT method only.
    extent : float, optional
        With ``height``: a bound of the contact's half-width [m] (default 2 h).
    film : physics.film.Film, optional
        The film's kind: a ``Film`` or a subclass supplying its own symbols (``Film.transfer``);
        its thickness, young and poisson are the scene's (given in one place: the film, or
        the scene's fields).  Default: the elastic film of ``poisson``.

    The derived units (h^2/2R, E h/6R) must be finite and > 0, and the Hertz half-width
    sqrt(P / 2 pi) at most A_OVER_H_MAX film thicknesses; else InputError names the parameter
    farthest (in decades) from the paper's value.
    """

    load: float = default("load")
    mu: float = default("mu")
    young: float = default("young")
    radius: float = default("radius")
    thickness: float = default("thickness")
    poisson: float = default("poisson")
    friction_law: str = default("friction_law")
    friction_exponent: float | None = None
    friction_pref: float | None = None
    shear_strength: float | None = None
    shear_slope: float | None = None
    interface_compliance: float = default("interface_compliance")
    interface_law: str = default("interface_law")
    interface_pressure: float | None = None
    interface_length: float | None = None
    height: object = None
    extent: float | None = None
    film: object = None
    speed: float = 0.0
    prony: tuple = ()

    dimension = "line"  # not a field: what the solvers dispatch on (Scene3D: "surface")

    def __post_init__(self):
        _take_film_fields(self)
        _check_viscoelastic(self)
        _take_film(self)
        for name, value in _options.validate(self, "line").items():  # the table's bounds
            object.__setattr__(self, name, value)
        if self.height is not None and not callable(self.height):
            raise InputError(f"{named('height')} must be a callable height(x_m) [m]; got "
                             f"{type(self.height).__name__}")
        if self.height is None and self.extent is not None:
            raise InputError(f"{named('extent')} bounds a height function's contact: give "
                             f"{named('height')} (or an indenter function) with it")
        if self.height is not None and self.extent is None:
            object.__setattr__(self, "extent", 2.0 * self.thickness)
        _check_law_and_film(self)
        self._check_scales()
        self._check_interface_law()
        _check_law_scales(self)
        _warn_units(self)

    def extreme_parameter(self, names=("load", "young", "thickness", "radius")) -> str:
        """"name = value unit" of the parameter among ``names`` farthest (in decades) from the
        paper's value: the one to name when a derived quantity is out of range."""
        # log10 of each factor, not of the ratio: a subnormal value over the typical one
        # underflows to 0 (log10(4.9e-324 / 200) is a domain error)
        far = max(names, key=lambda n: abs(math.log10(getattr(self, n)) - math.log10(_TYPICAL[n]))
                  if getattr(self, n) > 0 else math.inf)
        return f"{named(far)} = {getattr(self, far):g} {_options.option(far).unit}"

    def _check_scales(self):
        """Every derived scale finite and > 0, and the contact within the solvers' range; the
        message names the parameter farthest (in decades) from the paper's value."""
        blame = self.extreme_parameter

        for prop, what, names in (
                ("displacement_unit", "the displacement unit h^2/(2R) [m]", ("thickness", "radius")),
                ("stress_unit", "the stress unit E h/(6R) [Pa]", ("young", "thickness", "radius"))):
            try:
                value = getattr(self, prop)
            except OverflowError:  # float ** raises where * gives inf
                value = math.inf
            if not (math.isfinite(value) and value > 0.0):
                raise InputError(f"{blame(names)} is out of range: it makes {what} = {value:g}, "
                                 f"not a finite number > 0")
        if self.load > 0.0:
            P = self.P
            s = math.sqrt(P / (2.0 * math.pi)) if math.isfinite(P) else math.inf
            if not (P > 0.0 and s <= A_OVER_H_MAX):
                raise InputError(
                    f"{blame(('load', 'young', 'thickness', 'radius'))} is out of range: the "
                    f"dimensionless load P_L 6R/(E h^2) = {P:.3g} (Hertz half-width {s:.3g} h) "
                    f"must be > 0 with a Hertz half-width <= {A_OVER_H_MAX:g} film thicknesses")


    def _check_interface_law(self):
        if self.interface_law == "linear":
            for name in ("interface_pressure", "interface_length"):
                if getattr(self, name) is not None:
                    raise InputError(f"{named(name)} applies to {named('interface_law')} "
                                     f"exponential only")
            return
        for name in ("interface_pressure", "interface_length"):
            if getattr(self, name) is None:
                o = _options.option(name)
                raise InputError(f"{named(name)} ({o.what}) is required by {named('interface_law')}"
                                 f" exponential ({o.accepted()})")
        if self.interface_compliance:
            raise InputError(f"{named('interface_compliance')} (C) applies to "
                             f"{named('interface_law')} linear only; the law is exponential")
        if self.friction_law != "amontons":
            raise InputError(f"{named('interface_law')} exponential takes {named('friction_law')} "
                             f"amontons only; got {self.friction_law}")

    @property
    def interface_p0(self) -> float:
        """p0 of the exponential interface law in the core's stress unit."""
        return self.interface_pressure / self.stress_unit

    @property
    def interface_lambda(self) -> float:
        """lambda of the exponential interface law in the core's displacement unit."""
        return self.interface_length / self.displacement_unit

    @property
    def friction(self):
        """The friction law (``physics.friction.FrictionLaw``, SI)."""
        return FrictionLaw(self.friction_law, self.friction_exponent, self.friction_pref,
                           self.shear_strength, self.shear_slope)

    @property
    def viscoelastic(self) -> bool:
        """Whether the film has Prony terms (``prony``, issue 23): the JSON then reports the
        speed, the terms and the deformation friction."""
        return bool(self.prony)

    # --- units -------------------------------------------------------------------------------
    @property
    def length_unit(self) -> float:
        """h [m]."""
        return self.thickness

    @property
    def displacement_unit(self) -> float:
        """h^2 / (2R) [m]."""
        return self.thickness**2 / (2.0 * self.radius)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2(1 + nu)) [Pa] (E/3 at nu = 1/2)."""
        if self.poisson == 0.5:
            return self.young / 3.0
        return self.young / (2.0 * (1.0 + self.poisson))

    @property
    def stress_unit(self) -> float:
        """G h / (2R) [Pa] (written E h / (6R) at nu = 1/2, as before: bit-identical)."""
        if self.poisson == 0.5:
            return self.young * self.thickness / (6.0 * self.radius)
        return self.shear_modulus * self.thickness / (2.0 * self.radius)

    @property
    def interface(self) -> float:
        """The interface compliance in the core's units: C x stress unit / displacement unit."""
        if self.interface_compliance == 0.0:
            return 0.0
        return self.interface_compliance * self.stress_unit / self.displacement_unit

    @property
    def P(self) -> float:
        """Dimensionless lineic load P = P_L 2R / (G h^2) (= P_L 6R / (E h^2) at nu = 1/2)."""
        return self.load / (self.stress_unit * self.length_unit)

    def indenter_object(self):
        """The indenter in the core's units (``physics.indenters``), apex at the origin: the
        cylinder, or the user's height function."""
        if self.height is None:
            return Cylinder(0.0, self.P)
        h, unit, height = self.thickness, self.displacement_unit, self.height

        def f(x):
            return user_heights(height, x * h) / unit

        return LineHeightFunction(0.0, self.P, f, self.extent / h)

    def core_film(self) -> Film:
        """The film the solvers use, in the core's units (thickness 1, stresses in G, speeds in
        h/s): the scene's kind -- a user's film (``film=``), a viscoelastic film in sliding
        (``prony`` and ``speed`` != 0: ``ViscoelasticFilm``; at V = 0 the relaxed film, bit for
        bit the elastic solve with E = E_inf), else ``Film``.  The one place that builds it."""
        if self.film is not None:
            return self.film.core()
        if self.prony and self.speed != 0.0:
            from .viscoelastic import ViscoelasticFilm

            return ViscoelasticFilm(poisson=self.poisson, relaxed_young=self.young,
                                    prony=self.prony, speed=self.speed / self.thickness)
        return Film(poisson=self.poisson)

    def custom(self) -> str | None:
        """What of this scene only the FFT method solves (a user's indenter or film kind), in
        words; None for the built-in ones."""
        return _custom(self)

    def with_(self, **changes) -> Scene:
        """A copy with some parameters changed."""
        from dataclasses import replace

        return replace(self, **changes)


PAPER_SCENE = Scene()
"""The paper's scene: E = 2.2 MPa, R = 130 mm, h = 2 mm, P_L = 200 N/m, mu_d = 2.0."""


_FRTH = ", ".join(named(n) for n in ("force", "young", "radius")) + " or " + named("thickness")
A_OVER_H_MIN_3D = 1e-3
"""Smallest Hertz radius / h a 3D scene may have (the decay margin of ~15 h around a contact
of 1e-3 h already needs ~10^5 cells per axis: the solver refuses before allocating)."""
A_OVER_H_MAX_3D = 1e3
"""Largest Hertz radius / h of a 3D scene (beyond, the grid over the contact alone exceeds
8192^2 points)."""


@dataclass(frozen=True)
class Scene3D:
    """A rigid indenter of finite size sliding toward +x on the film (3D; the surface is 2D).

    Parameters (SI)
    ---------------
    indenter : {"sphere", "cylinder", "paraboloid", "function"}
        "sphere": radius ``radius`` (paraboloid approximation, f = r^2 / 2R); "cylinder": the
        paper's indenter, a cylinder of radius ``radius`` and length ``length`` along y with
        sharp ends (no contact beyond |y| > length/2); "paraboloid": principal radii
        ``radius_x`` (along x, the sliding direction) and ``radius_y``; "function": any shape,
        ``height(x, y)`` [m] (x, y arrays in m from the apex, +inf where there is no indenter).
    force : float
        F, total normal force [N], >= 0.
    mu : float
        mu_d, Amontons friction coefficient, signed (mu > 0 slides toward +x), as in 2D.
    young, radius, thickness : float
        E [Pa] (nu = 1/2), R [m] (the sphere's or cylinder's radius; the unit of heights for
        the others), h [m].
    length : float
        Cylinder length [m] (default 8 mm: the paper's cover slide).
    radius_x, radius_y : float, optional
        Paraboloid radii [m] (default ``radius``).
    height : callable, optional
        For "function": height(x_m, y_m) -> f [m] above the lowest point.
    extent : float, optional
        For "function": a bound of the contact's half-extent [m] (default 2 h).
    poisson : float
        nu, the film's Poisson ratio in [0, 0.5] (default 0.5), as ``Scene.poisson``: the
        stress unit is G h/(2R), G = E/(2(1 + nu)).
    friction_law, friction_exponent, friction_pref, shear_strength, shear_slope,
    interface_compliance :
        As ``Scene`` (issue 14): the friction law q(p) along x, a linear interface compliance.
    film : physics.film.Film, optional
        The film's kind, as ``Scene.film``.

    Dimensionless core: as ``Scene``, and the force P = F 6R / (E h^3) (stresses integrate
    over an area in h^2).
    """

    indenter: str = "sphere"
    force: float = default("force")
    mu: float = default("mu")
    young: float = default("young")
    radius: float = default("radius")
    thickness: float = default("thickness")
    length: float = default("length")
    radius_x: float | None = None
    radius_y: float | None = None
    height: object = None
    extent: float | None = None
    poisson: float = default("poisson")
    friction_law: str = default("friction_law")
    friction_exponent: float | None = None
    friction_pref: float | None = None
    shear_strength: float | None = None
    shear_slope: float | None = None
    interface_compliance: float = default("interface_compliance")
    film: object = None
    speed: float = 0.0
    prony: tuple = ()

    def __post_init__(self):
        _take_film_fields(self)
        _check_viscoelastic(self)
        _take_film(self)
        if self.indenter not in INDENTERS_3D:
            raise InputError(f"{named('indenter')} must be one of {', '.join(INDENTERS_3D)} (or "
                             f"line in 2D); got {self.indenter!r}")
        for name, value in _options.validate(self, "surface").items():  # the table's bounds
            object.__setattr__(self, name, value)
        _check_law_and_film(self)
        for name in ("radius_x", "radius_y"):
            if getattr(self, name) is None:
                object.__setattr__(self, name, self.radius)
        if self.indenter == "function":
            if not callable(self.height):
                raise InputError(f"{named('indenter')} 'function' needs height: a callable "
                                 f"height(x_m, y_m) [m]")
            if self.extent is None:
                object.__setattr__(self, "extent", 2.0 * self.thickness)
        for name in ("length_unit", "displacement_unit", "stress_unit", "P"):
            try:
                v = getattr(self, name)
            except OverflowError:  # float ** raises where * gives inf
                v = math.inf
            if not (math.isfinite(v) and (v > 0 or (name == "P" and v == 0))):
                raise InputError(f"the scene's {name.replace('_', ' ')} is {v:g}: {_FRTH} out of "
                                 f"range")
        if self.P > 0:
            # the Hertz radius (3P/32)^(1/3) in film thicknesses: within what a 2D grid of at
            # most 8192^2 points can hold with the film's decay margin around it
            s = (3.0 * self.P / 32.0) ** (1.0 / 3.0)
            if not A_OVER_H_MIN_3D <= s <= A_OVER_H_MAX_3D:
                raise InputError(
                    f"{_FRTH} out of range for 3D: the Hertz contact "
                    f"radius would be {s:.3g} film thicknesses; the 3D solver takes "
                    f"{A_OVER_H_MIN_3D:g} ... {A_OVER_H_MAX_3D:g} (smaller: use model hertz)")

        _check_law_scales(self)
        _warn_units(self)
        for name, ratio, what in (
                ("length", self.length / self.thickness, "length / thickness"),
                ("radius_x", self.radius_x / self.radius, "radius_x / radius"),
                ("radius_y", self.radius_y / self.radius, "radius_y / radius")):
            if not SHAPE_RATIO_MIN <= ratio <= SHAPE_RATIO_MAX:
                raise InputError(f"{name} = {getattr(self, name):g} m is out of range: {what} = "
                                 f"{ratio:.3g} must be in [{SHAPE_RATIO_MIN:g}, "
                                 f"{SHAPE_RATIO_MAX:g}]")

    length_unit = Scene.length_unit
    viscoelastic = Scene.viscoelastic
    displacement_unit = Scene.displacement_unit
    stress_unit = Scene.stress_unit
    shear_modulus = Scene.shear_modulus
    friction = Scene.friction
    interface = Scene.interface
    interface_law = "linear"  # not a field: the exponential law is for the line indenter only
    dimension = "surface"  # not a field: what the solvers dispatch on
    core_film = Scene.core_film
    custom = Scene.custom

    @property
    def P(self) -> float:
        """Dimensionless force P = F 6R / (E h^3)."""
        return self.force / (self.stress_unit * self.length_unit**2)

    def indenter_object(self):
        """The indenter in the core's units (``physics.indenters``), apex at the origin."""
        from .indenters import FiniteCylinder, HeightFunction, Paraboloid, Sphere, user_heights

        h, R = self.thickness, self.radius
        if self.indenter == "sphere":
            return Sphere(0.0, self.P, 1.0)
        if self.indenter == "paraboloid":
            return Paraboloid(0.0, self.P, R / self.radius_x, R / self.radius_y)
        if self.indenter == "cylinder":
            return FiniteCylinder(0.0, self.P, 1.0, 0.5 * self.length / h)
        unit = self.displacement_unit

        def f(x, y):
            return user_heights(self.height, x * h, y * h) / unit

        return HeightFunction(0.0, self.P, f, (self.extent / h, self.extent / h))

    def with_(self, **changes) -> Scene3D:
        from dataclasses import replace

        return replace(self, **changes)
