"""The physical scene in SI units, its validation, and the paper's dimensionless units.

Dimensionless core (the paper's, section "Exact model"):

* lengths in h (film thickness),
* displacements in h^2 / (2R),
* stresses in E h / (6R)  (= G h / (2R), G = E/3 the shear modulus of the incompressible film),
* lineic load P = P_L * 6R / (E h^2).

In these units the indenter profile is x^2 and the Hertz half-space pressure is 4 sqrt(a^2 - x^2).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["Scene", "Scene3D", "INDENTERS_3D", "PAPER_SCENE", "check_finite", "check_positive", "check_tol"]


def check_finite(name: str, value, accepted: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number ({accepted}); got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be finite ({accepted}); got {v}")
    return v


def check_positive(name: str, value, unit: str) -> float:
    v = check_finite(name, value, f"> 0 {unit}".strip())
    if v <= 0.0:
        raise InputError(f"{name} must be > 0 {unit}; got {v}".replace("  ", " "))
    return v


def check_tol(tol) -> float:
    """A relative accuracy target: a number in (0, 0.1)."""
    try:
        t = float(tol)
    except (TypeError, ValueError):
        raise InputError(f"tol must be a number in (0, 0.1); got {tol!r}") from None
    if not (math.isfinite(t) and 0.0 < t < 0.1):
        raise InputError(f"tol must be in (0, 0.1); got {tol}")
    return t


@dataclass(frozen=True)
class Scene:
    """A rigid cylinder sliding on an incompressible elastic film bonded to a rigid base.

    Parameters (SI)
    ---------------
    load : float
        P_L, normal load per unit length of cylinder [N/m], >= 0 (0 means no contact).
    mu : float
        mu_d, dynamic (Amontons) friction coefficient, signed: mu > 0 means the cylinder slides
        toward +x and drags the film surface toward +x (sigma_xz(x, h) = mu * p(x)); mu < 0 means
        sliding toward -x.
    young : float
        E, Young's modulus of the film [Pa] (Poisson ratio 1/2: incompressible).
    radius : float
        R, cylinder radius [m].
    thickness : float
        h, film thickness [m].
    """

    load: float = 200.0
    mu: float = 2.0
    young: float = 2.2e6
    radius: float = 0.130
    thickness: float = 0.002

    def __post_init__(self):
        object.__setattr__(self, "young", check_positive("young (E)", self.young, "Pa"))
        object.__setattr__(self, "radius", check_positive("radius (R)", self.radius, "m"))
        object.__setattr__(self, "thickness", check_positive("thickness (h)", self.thickness, "m"))
        load = check_finite("load (P_L)", self.load, ">= 0 N/m")
        if load < 0.0:
            raise InputError(f"load (P_L) must be >= 0 N/m; got {load}")
        object.__setattr__(self, "load", load)
        object.__setattr__(self, "mu", check_finite("mu (mu_d)", self.mu, "any finite real"))

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
    def stress_unit(self) -> float:
        """E h / (6R) [Pa]."""
        return self.young * self.thickness / (6.0 * self.radius)

    @property
    def P(self) -> float:
        """Dimensionless lineic load P = P_L 6R / (E h^2)."""
        return self.load / (self.stress_unit * self.length_unit)

    def with_(self, **changes) -> Scene:
        """A copy with some parameters changed."""
        from dataclasses import replace

        return replace(self, **changes)


PAPER_SCENE = Scene()
"""The paper's scene: E = 2.2 MPa, R = 130 mm, h = 2 mm, P_L = 200 N/m, mu_d = 2.0."""


INDENTERS_3D = ("sphere", "cylinder", "paraboloid", "function")


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

    Dimensionless core: as ``Scene``, and the force P = F 6R / (E h^3) (stresses integrate
    over an area in h^2).
    """

    indenter: str = "sphere"
    force: float = 1.0
    mu: float = 2.0
    young: float = 2.2e6
    radius: float = 0.130
    thickness: float = 0.002
    length: float = 0.008
    radius_x: float | None = None
    radius_y: float | None = None
    height: object = None
    extent: float | None = None

    def __post_init__(self):
        if self.indenter not in INDENTERS_3D:
            raise InputError(f"indenter must be one of {', '.join(INDENTERS_3D)} (or line in 2D); "
                             f"got {self.indenter!r}")
        for name, unit in (("young", "Pa"), ("radius", "m"), ("thickness", "m"), ("length", "m")):
            object.__setattr__(self, name, check_positive(name, getattr(self, name), unit))
        for name in ("radius_x", "radius_y"):
            v = getattr(self, name)
            object.__setattr__(self, name, self.radius if v is None else check_positive(name, v, "m"))
        force = check_finite("force", self.force, ">= 0 N")
        if force < 0.0:
            raise InputError(f"force must be >= 0 N; got {force}")
        object.__setattr__(self, "force", force)
        object.__setattr__(self, "mu", check_finite("mu (mu_d)", self.mu, "any finite real"))
        if self.indenter == "function":
            if not callable(self.height):
                raise InputError("indenter 'function' needs height: a callable height(x_m, y_m) [m]")
            ext = 2.0 * self.thickness if self.extent is None else self.extent
            object.__setattr__(self, "extent", check_positive("extent", ext, "m"))
        for name in ("length_unit", "displacement_unit", "stress_unit", "P"):
            v = getattr(self, name)
            if not (math.isfinite(v) and (v > 0 or (name == "P" and v == 0))):
                raise InputError(f"the scene's {name.replace('_', ' ')} is {v:g}: force, young, "
                                 f"radius or thickness out of range")

    length_unit = Scene.length_unit
    displacement_unit = Scene.displacement_unit
    stress_unit = Scene.stress_unit

    @property
    def P(self) -> float:
        """Dimensionless force P = F 6R / (E h^3)."""
        return self.force / (self.stress_unit * self.length_unit**2)

    def indenter_object(self):
        """The indenter in the core's units (``physics.indenters``), apex at the origin."""
        from .indenters import FiniteCylinder, HeightFunction, Paraboloid, Sphere

        h, R = self.thickness, self.radius
        if self.indenter == "sphere":
            return Sphere(0.0, self.P, 1.0)
        if self.indenter == "paraboloid":
            return Paraboloid(0.0, self.P, R / self.radius_x, R / self.radius_y)
        if self.indenter == "cylinder":
            return FiniteCylinder(0.0, self.P, 1.0, 0.5 * self.length / h)
        unit = self.displacement_unit

        def f(x, y):
            return np.asarray(self.height(x * h, y * h), dtype=float) / unit

        return HeightFunction(0.0, self.P, f, (self.extent / h, self.extent / h))

    def with_(self, **changes) -> Scene3D:
        from dataclasses import replace

        return replace(self, **changes)
