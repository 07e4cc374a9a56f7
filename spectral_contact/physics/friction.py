"""Friction laws: the surface shear q(x) = sigma_xz(x, h) inside the contact as a function of the
local pressure p(x) (issue 14).  Outside the contact q = 0.

* ``amontons`` (the paper's):  q = mu_d p.
* ``power``:   q = mu(p) p with mu(p) = mu_d (p / p_ref)^(-n), 0 <= n < 1 (the local friction
  coefficient falls with pressure for n > 0, as the paper's Q/P falls with P; q still rises
  with p and vanishes at the contact edge).  n = 0 is Amontons exactly.
* ``linear``:  q = tau_0 + alpha p inside the contact (the form reported for PDMS on glass);
  tau_0 [Pa] and alpha of the same sign (their sign is the sliding direction), so that the shear
  never reverses.  tau_0 = 0 is Amontons with mu_d = alpha.

Sign: q > 0 drags the film surface toward +x (the cylinder slides toward +x), as mu_d > 0 does.
SI parameters here; ``FrictionLaw.dimensionless(stress_unit, mu)`` gives the law in the core's
stress unit (``Scene.stress_unit``), with mu_d the scene's friction coefficient.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, named
from .options import FRICTION_LAWS, option

__all__ = ["FrictionLaw", "FRICTION_LAWS", "ShearLaw", "AMONTONS"]


@dataclass(frozen=True)
class FrictionLaw:
    """A friction law in SI.

    law : "amontons" | "power" | "linear"
    exponent : n of the power law, in [0, 1) (power only)
    pref : p_ref of the power law [Pa], > 0 (power only)
    shear_strength : tau_0 of the linear law [Pa] (linear only)
    shear_slope : alpha of the linear law, same sign as tau_0 (linear only)

    Parameters of another law than the chosen one must be left at their defaults (None):
    ``FrictionLaw("amontons", exponent=0.2)`` is refused (one line naming the option).
    """

    law: str = "amontons"
    exponent: float | None = None
    pref: float | None = None
    shear_strength: float | None = None
    shear_slope: float | None = None

    def __post_init__(self):
        option("friction_law").check(self.law)
        own = {"amontons": (), "power": ("exponent", "pref"),
               "linear": ("shear_strength", "shear_slope")}[self.law]
        for name, opt in _OPTION_OF.items():
            if getattr(self, name) is not None and name not in own:
                raise InputError(f"{named(opt)} applies to {named('friction_law')} "
                                 f"{'power' if name in ('exponent', 'pref') else 'linear'} only; "
                                 f"the law is {self.law}")
        if self.law == "power":
            n = option("friction_exponent").check(0.0 if self.exponent is None else self.exponent)
            if self.pref is None:
                o = option("friction_pref")
                raise InputError(f"{named(o.name)} ({o.what}) is required by "
                                 f"{named('friction_law')} power ({o.accepted()})")
            object.__setattr__(self, "exponent", n)
            object.__setattr__(self, "pref", option("friction_pref").check(self.pref))
        if self.law == "linear":
            if self.shear_strength is None and self.shear_slope is None:  # else: no friction at all
                raise InputError(f"{named('friction_law')} linear needs its parameters: "
                                 f"{named('shear_strength')} (tau_0) [Pa] and/or "
                                 f"{named('shear_slope')} (alpha), same sign; {named('mu')} is "
                                 f"not used by this law")
            tau0 = option("shear_strength").check(self.shear_strength or 0.0)
            alpha = option("shear_slope").check(self.shear_slope or 0.0)
            if tau0 * alpha < 0.0:
                raise InputError(f"{named('shear_strength')} (tau_0 = {tau0:g} Pa) and "
                                 f"{named('shear_slope')} (alpha = {alpha:g}) must have the same "
                                 "sign (else the shear reverses within the contact)")
            object.__setattr__(self, "shear_strength", tau0)
            object.__setattr__(self, "shear_slope", alpha)

    @property
    def is_amontons(self) -> bool:
        return self.law == "amontons"

    def dimensionless(self, stress_unit: float, mu: float) -> ShearLaw:
        """The law in the core's stress unit [Pa] with mu_d = ``mu`` (amontons, power)."""
        if self.law == "amontons":
            return ShearLaw("amontons", mu=mu)
        if self.law == "power":
            return ShearLaw("power", mu=mu, exponent=self.exponent, pref=self.pref / stress_unit)
        return ShearLaw("linear", mu=self.shear_slope, tau0=self.shear_strength / stress_unit)

    def describe(self) -> dict:
        """The law's parameters for the JSON record (SI)."""
        out = {"friction_law": self.law}  # the options' JSON keys (physics.options)
        own = {"power": ("exponent", "pref"), "linear": ("shear_strength", "shear_slope")}
        for name in own.get(self.law, ()):
            out[option(_OPTION_OF[name]).json] = getattr(self, name)
        return out


_OPTION_OF = {"exponent": "friction_exponent", "pref": "friction_pref",
              "shear_strength": "shear_strength", "shear_slope": "shear_slope"}
"""FrictionLaw's fields as the scene's options (``physics.options``)."""
AMONTONS = FrictionLaw()


@dataclass(frozen=True)
class ShearLaw:
    """A friction law in the core's units: ``shear(p)`` gives q on the grid (0 where p <= 0).

    amontons: q = mu p;  power: q = mu p (p / pref)^(-exponent);  linear: q = tau0 + mu p."""

    law: str
    mu: float = 0.0
    exponent: float = 0.0
    pref: float = 1.0
    tau0: float = 0.0

    @property
    def proportional(self) -> bool:
        """True when q = mu p exactly (Amontons, power with n = 0, linear with tau0 = 0)."""
        return self.law == "amontons" or (self.law == "power" and self.exponent == 0.0) or (
            self.law == "linear" and self.tau0 == 0.0)

    def shear(self, p: np.ndarray) -> np.ndarray:
        p = np.asarray(p, dtype=float)
        inside = p > 0.0
        if self.law == "amontons" or self.proportional:
            return np.where(inside, self.mu * p, 0.0)
        if self.law == "power":
            ps = np.where(inside, p, 1.0)
            return np.where(inside, self.mu * p * (ps / self.pref) ** (-self.exponent), 0.0)
        return np.where(inside, self.tau0 + self.mu * p, 0.0)

    def slope(self, p: float) -> float:
        """dq/dp at the pressure p > 0 (the linear part kept implicit by the outer iteration)."""
        if self.law == "power" and self.exponent != 0.0:
            return (1.0 - self.exponent) * self.mu * (p / self.pref) ** (-self.exponent)
        return self.mu
