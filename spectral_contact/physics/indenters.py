"""Rigid indenters: their height above the film on a grid, and a first guess of their pressure.

Dimensionless core: lengths in h, heights (like displacements) in h^2/(2R) with R the reference
radius of the scene, so the reference cylinder is f = x^2.  An indenter owns an apex position and
the normal load it carries (P, dimensionless: P_L 6R/(E h^2) for a line load).  Heights are
measured from the apex (f >= 0), at the nodes' periodic offsets from it; ``grid`` is any object
with ``periodic_offset(point)`` (numerics.grid.Grid).
"""
from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

__all__ = ["Indenter", "Cylinder"]


@dataclass(frozen=True)
class Indenter(ABC):
    """A rigid indenter at ``apex`` (first coordinate: x) pressed with load ``load``."""

    apex: float = 0.0
    load: float = 0.0

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
