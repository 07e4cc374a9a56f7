"""The film-indenter interface, as a user composes it: friction (Amontons' mu, or another
``FrictionLaw``) and closure (rigid, a linear compliance, or the exponential law), in SI.

    >>> from spectral_contact import solve, Interface, FrictionLaw
    >>> solve(interface=Interface(mu=0.5, compliance=1e-10), load=50.0)
    >>> solve(interface=Interface(mu=2.0, friction=FrictionLaw("power", exponent=0.1, pref=2e4)))

It is the scene's friction and interface fields in one object (``Scene.mu``,
``Scene.friction_law``, ..., ``Scene.interface_*``): ``scene_fields`` gives them, and the scene
validates them (``physics.options``), so messages name the scene's options.
"""
from __future__ import annotations

from dataclasses import dataclass

from .friction import AMONTONS, FrictionLaw
from .options import default

__all__ = ["Interface"]


@dataclass(frozen=True)
class Interface:
    """The interface: ``mu`` (mu_d, signed: > 0 slides toward +x), ``friction`` (a
    ``FrictionLaw``: Amontons by default; the power law's mu_d is ``mu``, the linear law has
    its own tau_0 and alpha), ``compliance`` C [m/Pa] >= 0 (the interface closes by C p), or
    ``law="exponential"`` with ``pressure`` p0 [Pa] and ``length`` lambda [m] (p = p0
    exp(-g/lambda) at an interface gap g; line indenters only)."""

    mu: float = default("mu")
    friction: FrictionLaw = AMONTONS
    compliance: float = default("interface_compliance")
    law: str = default("interface_law")
    pressure: float | None = None
    length: float | None = None

    def scene_fields(self) -> dict:
        """The scene's fields this interface sets (``Scene``; ``Scene3D`` without the
        exponential law's)."""
        f = self.friction if isinstance(self.friction, FrictionLaw) else FrictionLaw(self.friction)
        out = {"mu": self.mu, "friction_law": f.law, "friction_exponent": f.exponent,
               "friction_pref": f.pref, "shear_strength": f.shear_strength,
               "shear_slope": f.shear_slope, "interface_compliance": self.compliance}
        if self.law != "linear" or self.pressure is not None or self.length is not None:
            out |= {"interface_law": self.law, "interface_pressure": self.pressure,
                    "interface_length": self.length}
        return out
