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
import numbers
from dataclasses import dataclass

from ..errors import InputError

__all__ = ["Scene", "PAPER_SCENE", "check_finite", "check_positive", "check_tol", "MU_MAX",
           "A_OVER_H_MAX", "TOL_MIN"]


def check_finite(name: str, value, accepted: str) -> float:
    """A real number (int, float, numpy scalar; not bool, str or bytes), finite as a float."""
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
        raise InputError(f"{name} must be > 0 {unit}; got {v}".replace("  ", " "))
    return v


TOL_MIN = 1e-14
"""Smallest relative tolerance: differences of a few round-offs (2.2e-16) cannot be resolved."""


def check_tol(tol) -> float:
    """A relative accuracy target: a number in [TOL_MIN, 0.1)."""
    t = check_finite("tol", tol, f"in [{TOL_MIN:g}, 0.1)")
    if not (math.isfinite(t) and TOL_MIN <= t < 0.1):
        raise InputError(f"tol must be in [{TOL_MIN:g}, 0.1); got {tol}")
    return t


MU_MAX = 1e3
"""Largest |mu_d| accepted: the FFT solver is verified to |mu| = 100 (and fails to converge,
exit 3, from ~1e3 on the paper's scene); beyond 1e3 round-off breaks the linear algebra."""
A_OVER_H_MAX = 1e8
"""Largest Hertz half-width a_H/h = sqrt(P / 2 pi) accepted: the FFT solver is verified to 1e8
frictionless (with friction it stops converging, exit 3, from ~1e3); beyond, the film's scales
leave floating-point range."""
_TYPICAL = {"load": 200.0, "young": 2.2e6, "radius": 0.130, "thickness": 0.002}
_LABEL = {"load": "load (P_L)", "young": "young (E)", "radius": "radius (R)",
          "thickness": "thickness (h)"}
_UNIT = {"load": "N/m", "young": "Pa", "radius": "m", "thickness": "m"}


@dataclass(frozen=True)
class Scene:
    """A rigid cylinder sliding on an incompressible elastic film bonded to a rigid base.

    Parameters (SI)
    ---------------
    load : float
        P_L, normal load per unit length of cylinder [N/m], >= 0 (0 means no contact).
    mu : float
        mu_d, dynamic (Amontons) friction coefficient, in [-MU_MAX, MU_MAX], signed: mu > 0 means the cylinder slides
        toward +x and drags the film surface toward +x (sigma_xz(x, h) = mu * p(x)); mu < 0 means
        sliding toward -x.
    young : float
        E, Young's modulus of the film [Pa] (Poisson ratio 1/2: incompressible).
    radius : float
        R, cylinder radius [m].
    thickness : float
        h, film thickness [m].

    The derived units (h^2/2R, E h/6R) must be finite and > 0, and the Hertz half-width
    sqrt(P / 2 pi) at most A_OVER_H_MAX film thicknesses; else InputError names the parameter
    farthest (in decades) from the paper's value.
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
        mu = check_finite("mu (mu_d)", self.mu, f"in [-{MU_MAX:g}, {MU_MAX:g}]")
        if abs(mu) > MU_MAX:
            raise InputError(f"mu (mu_d) must be in [-{MU_MAX:g}, {MU_MAX:g}]; got {mu:g}")
        object.__setattr__(self, "mu", mu + 0.0)  # + 0.0: no -0
        object.__setattr__(self, "load", load + 0.0)
        self._check_scales()

    def extreme_parameter(self, names=("load", "young", "thickness", "radius")) -> str:
        """"name = value unit" of the parameter among ``names`` farthest (in decades) from the
        paper's value: the one to name when a derived quantity is out of range."""
        far = max(names, key=lambda n: abs(math.log10(getattr(self, n) / _TYPICAL[n]))
                  if getattr(self, n) > 0 else math.inf)
        return f"{_LABEL[far]} = {getattr(self, far):g} {_UNIT[far]}"

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
