"""Rigid indenters: their height above the film on a grid, and a first guess of their pressure.

Dimensionless core: lengths in h, heights (like displacements) in h^2/(2R) with R the reference
radius of the scene, so the reference cylinder is f = x^2 and the reference sphere
f = x^2 + y^2.  An indenter owns an apex position and the normal load it carries (P,
dimensionless: P_L 6R/(E h^2) for a line load on a 1D grid; F 6R/(E h^3) for a force on a 2D
grid, where stresses integrate over an area).  Heights are
measured from the apex (f >= 0), at the nodes' periodic offsets from it; ``grid`` is any object
with ``periodic_offset(point)`` (numerics.grid.Grid).
"""
from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, named

__all__ = ["Indenter", "Cylinder", "Paraboloid", "Sphere", "FiniteCylinder", "HeightFunction",
           "LineHeightFunction"]


@dataclass(frozen=True)
class Indenter(ABC):
    """A rigid indenter at ``apex`` (first coordinate: x) pressed with load ``load``."""

    apex: float = 0.0
    load: float = 0.0

    #: True where the pressure is unbounded at an edge of the body (sharp ends): its peak
    #: pressure then grows with the resolution and is not a converged measure
    singular_peak = False

    @abstractmethod
    def offset(self, grid) -> tuple:
        """Broadcastable periodic offsets of the nodes from the apex, on the axes the shape
        depends on (the others broadcast)."""

    @abstractmethod
    def height(self, grid) -> np.ndarray:
        """f >= 0: the indenter's height above its apex at the nodes (broadcastable)."""

    @abstractmethod
    def initial_pressure(self, grid) -> np.ndarray:
        """A first guess of the pressure whose support contains the contact (the half-space
        solution, wider than the film's)."""

    def distance(self, grid) -> np.ndarray:
        """Periodic distance of the nodes to the apex (nodes are owned by the nearest apex)."""
        return np.sqrt(sum(o * o for o in self.offset(grid)))


@dataclass(frozen=True)
class Cylinder(Indenter):
    """A parabolic cylinder f = c (x - x_apex)^2, its axis along y (plane strain in 1D; in 2D
    the same height at every y).  ``curvature`` c = R / R_m for a cylinder of radius R_m."""

    curvature: float = 1.0

    def offset(self, grid) -> tuple:
        return grid.periodic_offset((self.apex,) + (0.0,) * (len(grid.shape) - 1))[:1]

    def height(self, grid) -> np.ndarray:
        rel = self.offset(grid)[0]
        return self.curvature * rel**2

    def distance(self, grid) -> np.ndarray:
        return np.abs(self.offset(grid)[0])

    def initial_pressure(self, grid) -> np.ndarray:
        """Hertz half-space pressure 4c sqrt(a^2 - x^2), P = 2 pi c a^2 (line load)."""
        rel = self.offset(grid)[0]
        a = math.sqrt(self.load / (2 * math.pi * self.curvature)) if self.load > 0 else 0.0
        inside = np.abs(rel) < a
        return np.where(inside, 4 * self.curvature * np.sqrt(np.maximum(a * a - rel**2, 0.0)), 0.0)


def _hertz_sphere_guess(r2, c: float, load: float):
    """Hertz half-space pressure of a paraboloid of revolution f = c r^2 carrying ``load``
    (dimensionless: p = (16 c a / pi) sqrt(1 - r^2/a^2), a^3 = 3 P / (32 c); E* = 4E/3)."""
    if load <= 0:
        return np.zeros(np.shape(r2))
    a = (3.0 * load / (32.0 * c)) ** (1.0 / 3.0)
    return (16.0 * c * a / math.pi) * np.sqrt(np.maximum(1.0 - r2 / (a * a), 0.0))


@dataclass(frozen=True)
class Paraboloid(Indenter):
    """An elliptical paraboloid f = cx (x - x_apex)^2 + cy y^2 (2D grids): cx = R / R_x,
    cy = R / R_y for principal radii R_x (along the sliding direction) and R_y."""

    cx: float = 1.0
    cy: float = 1.0

    def offset(self, grid) -> tuple:
        return grid.periodic_offset((self.apex, 0.0))

    def height(self, grid) -> np.ndarray:
        x, y = self.offset(grid)
        return self.cx * x**2 + self.cy * y**2

    def initial_pressure(self, grid) -> np.ndarray:
        """Hertz pressure of the sphere of the same mean curvature c = sqrt(cx cy), on the
        ellipses of equal height (a first guess: only its support matters)."""
        x, y = self.offset(grid)
        c = math.sqrt(self.cx * self.cy)
        return _hertz_sphere_guess((self.cx * x**2 + self.cy * y**2) / c, c, self.load)

    def extent_bound(self) -> tuple:
        """Upper bounds of the contact's half-extents (x, y) in h: the half-space (Hertz)
        contact of the flattest sphere below the paraboloid (the film is stiffer)."""
        a = (3.0 * max(self.load, 0.0) / (32.0 * min(self.cx, self.cy))) ** (1.0 / 3.0)
        return a, a


class Sphere(Paraboloid):
    """A sphere in the paraboloid approximation, f = c ((x - x_apex)^2 + y^2), c = R / R_s."""

    def __init__(self, apex: float = 0.0, load: float = 0.0, curvature: float = 1.0):
        super().__init__(apex, load, curvature, curvature)


@dataclass(frozen=True)
class FiniteCylinder(Indenter):
    """A cylinder of curvature c (f = c (x - x_apex)^2) and half-length ``half_length`` along
    y, centred on y = 0, with sharp ends: no contact beyond |y| > half_length (its height is
    +inf there).  On a 1D grid it is meaningless: use ``Cylinder``."""

    curvature: float = 1.0
    half_length: float = 1.0
    singular_peak = True

    def offset(self, grid) -> tuple:
        return grid.periodic_offset((self.apex, 0.0))

    def height(self, grid) -> np.ndarray:
        x, y = self.offset(grid)
        return np.where(np.abs(y) <= self.half_length, self.curvature * x**2, np.inf)

    def initial_pressure(self, grid) -> np.ndarray:
        """The line-load Hertz pressure of P / (2 half_length) on every row within the ends."""
        x, y = self.offset(grid)
        line = self.load / (2.0 * self.half_length)
        a = math.sqrt(line / (2 * math.pi * self.curvature)) if line > 0 else 0.0
        p = 4 * self.curvature * np.sqrt(np.maximum(a * a - x**2, 0.0))
        return np.where(np.abs(y) <= self.half_length, p, 0.0)

    def extent_bound(self) -> tuple:
        line = max(self.load, 0.0) / (2.0 * self.half_length)
        # the ends carry more than the mean line load: twice the Hertz width as a bound
        return 2.0 * math.sqrt(line / (2 * math.pi * self.curvature)), self.half_length


def user_heights(function, *xy) -> np.ndarray:
    """A user's height function at the nodes: numbers, finite or +inf (no indenter there), of
    the nodes' shape, else one-line InputError."""
    try:
        f = np.asarray(function(*xy), dtype=float)
    except InputError:
        raise
    except (TypeError, ValueError) as exc:
        raise InputError(f"{named('indenter')}: the height function must return numbers [m]; "
                         f"{type(exc).__name__}: {str(exc)[:80]}") from None
    if f.shape != np.broadcast(*xy).shape:
        raise InputError(f"{named('indenter')}: the height function returned shape {f.shape} "
                         f"for nodes of shape {np.broadcast(*xy).shape}: it must act elementwise")
    bad = ("NaN" if np.isnan(f).any() else "-inf" if (f == -np.inf).any() else
           "+inf everywhere (no finite one: no indenter on the grid)" if not np.isfinite(f).any() else None)
    if bad:
        raise InputError(f"{named('indenter')}: the height function must return finite heights "
                         f"(or +inf where there is no indenter); got {bad}")
    return f


@dataclass(frozen=True)
class HeightFunction(Indenter):
    """Any rigid shape: ``function(x, y)`` gives the height f >= 0 above the apex (in the
    core's units: x, y in h, f in h^2/(2R)) at offsets (x, y) from (apex, 0); +inf where the
    indenter does not exist.  ``half_extent`` bounds the contact's half-extents (x, y) [h]."""

    function: object = None
    half_extent: tuple = (1.0, 1.0)

    def offset(self, grid) -> tuple:
        return grid.periodic_offset((self.apex, 0.0))

    def height(self, grid) -> np.ndarray:
        x, y = self.offset(grid)
        f = user_heights(self.function, x + 0 * y, y + 0 * x)
        return f - np.min(f)

    def initial_pressure(self, grid) -> np.ndarray:
        """A pressure on the nodes whose height is below the median of the window's, scaled
        to the load (only its support matters: it is the first active set)."""
        f = self.height(grid)
        x, y = self.offset(grid)
        inside = (np.abs(x) <= self.half_extent[0]) & (np.abs(y) <= self.half_extent[1])
        sel = inside & np.isfinite(f)
        if not sel.any():
            return np.zeros(f.shape)
        cut = np.median(f[sel])
        return np.where(sel & (f <= cut), 1.0, 0.0)

    def extent_bound(self) -> tuple:
        return tuple(self.half_extent)


@dataclass(frozen=True)
class LineHeightFunction(Indenter):
    """Any rigid line shape (plane strain, its axis along y): ``function(x)`` gives the height
    f above the apex (in the core's units: x in h, f in h^2/(2R)) at offsets x from the apex,
    +inf where the indenter does not exist; ``half_extent`` [h] bounds the contact's
    half-width.  ``load``: per unit length, as ``Cylinder``'s."""

    function: object = None
    half_extent: float = 1.0

    def offset(self, grid) -> tuple:
        return grid.periodic_offset((self.apex,) + (0.0,) * (len(grid.shape) - 1))[:1]

    def height(self, grid) -> np.ndarray:
        (x,) = self.offset(grid)
        f = user_heights(self.function, x)
        return f - np.min(f)

    def distance(self, grid) -> np.ndarray:
        return np.abs(self.offset(grid)[0])

    def initial_pressure(self, grid) -> np.ndarray:
        """sqrt(f_c - f) carrying the load, f_c the highest height in the window |x| <=
        half_extent (the Hertz profile's shape for a parabola): its support, the window that
        bounds the contact, is the first active set, and its peak at the lowest node starts
        the exponential interface's Newton iteration, which takes the indentation there."""
        f = self.height(grid)
        (x,) = self.offset(grid)
        sel = (np.abs(x) <= self.half_extent) & np.isfinite(f)
        if not sel.any() or self.load <= 0:
            return np.zeros(f.shape)
        p = np.where(sel, np.sqrt(np.maximum(np.max(f[sel]) - f, 0.0)), 0.0)
        if not p.any():  # a flat window: uniform on it
            p = sel.astype(float)
        return p * (self.load / (p.sum() * grid.cell))

    def extent_bound(self) -> float:
        return self.half_extent
