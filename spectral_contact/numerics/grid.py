"""Uniform periodic grid on the film surface (dimensionless: lengths in h)."""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

__all__ = ["Grid"]


@dataclass(frozen=True)
class Grid:
    """n points x_j = origin + j L/n on a period L (in h)."""

    n: int
    length: float
    origin: float = 0.0

    @property
    def dx(self) -> float:
        return self.length / self.n

    @cached_property
    def x(self) -> np.ndarray:
        return self.origin + np.arange(self.n) * self.dx

    @cached_property
    def k(self) -> np.ndarray:
        """Non-negative wavenumbers of the real FFT half spectrum (1/h)."""
        return 2.0 * np.pi * np.fft.rfftfreq(self.n, self.dx)

    def centered(n: int, length: float, center: float = 0.0) -> Grid:
        """A grid of n points whose middle point sits at ``center``."""
        return Grid(n, length, center - (n // 2) * (length / n))

    centered = staticmethod(centered)
