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

from ..errors import InputError

__all__ = ["Scene", "PAPER_SCENE", "check_finite", "check_positive", "check_tol"]


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
