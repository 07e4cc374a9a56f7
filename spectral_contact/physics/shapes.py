"""The indenter as a user composes it, in SI: ``Shape`` (its kind and dimensions).

    >>> from spectral_contact import Shape, solve
    >>> solve(indenter=Shape.sphere(radius=0.05), force=0.2)
    >>> solve(indenter=Shape.line(radius=0.13), load=200.0)
    >>> solve(indenter=Shape.function(lambda x: x**2 / 0.26), load=200.0)   # any line shape

``solve``'s ``indenter=`` also takes the kind's name ("sphere") or the height function itself.
A ``Shape`` is the scene's indenter fields in one object (``Scene.radius``, ``Scene3D.length``,
..., ``height``, ``extent``): ``scene_fields`` gives them, the scene validates them
(``physics.options``), and the core's indenter (``physics.indenters``, lengths in h) is built
from the scene (``Scene.indenter_object``).
"""
from __future__ import annotations

from dataclasses import dataclass

from .options import INDENTERS, INDENTERS_3D

__all__ = ["Shape"]


@dataclass(frozen=True)
class Shape:
    """An indenter: ``kind`` ("line": the plane-strain cylinder, "sphere", "cylinder": finite,
    "paraboloid", or "function": any height function), its dimensions [m] (None: the scene's
    defaults) and, for a function, ``height`` (of x for a line indenter, of x and y for a
    surface) and ``extent`` (a bound of the contact's half-extent [m])."""

    kind: str = "line"
    radius: float | None = None
    length: float | None = None
    radius_x: float | None = None
    radius_y: float | None = None
    height: object = None
    extent: float | None = None

    @classmethod
    def line(cls, radius: float | None = None) -> Shape:
        """The paper's indenter: a cylinder along y (plane strain), loaded per unit length."""
        return cls("line", radius=radius)

    @classmethod
    def sphere(cls, radius: float | None = None) -> Shape:
        return cls("sphere", radius=radius)

    @classmethod
    def cylinder(cls, radius: float | None = None, length: float | None = None) -> Shape:
        """A cylinder of finite length along y with sharp ends (the paper's cover slide)."""
        return cls("cylinder", radius=radius, length=length)

    @classmethod
    def paraboloid(cls, radius_x: float | None = None, radius_y: float | None = None) -> Shape:
        return cls("paraboloid", radius_x=radius_x, radius_y=radius_y)

    @classmethod
    def function(cls, height, extent: float | None = None) -> Shape:
        """Any shape: height(x) [m] (a line indenter) or height(x, y) [m] (a surface one)."""
        return cls("function", height=height, extent=extent)

    def scene_fields(self) -> dict:
        """The scene's fields this shape sets: ``indenter`` (a name, or the height function)
        and the dimensions given."""
        if self.kind not in INDENTERS + INDENTERS_3D:
            from ..errors import InputError, named

            raise InputError(f"{named('indenter')} must be one of "
                             f"{', '.join(INDENTERS + INDENTERS_3D[-1:])}; got {self.kind!r}")
        out = {"indenter": self.height if self.kind == "function" else self.kind}
        for name in ("radius", "length", "radius_x", "radius_y", "extent"):
            if getattr(self, name) is not None:
                out[name] = getattr(self, name)
        return out
