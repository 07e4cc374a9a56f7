"""The FFT method registered by name ("fft", ``solvers.registry``): its options checked, then
the one driver (``fft_driver.run``) on a line (``solvers.fft.solve_fft``) or a surface
(``solvers.fft3d.solve_fft3d``)."""
from __future__ import annotations

import numpy as np

from ..errors import InputError, named
from ..physics.scene import Scene3D, check_positive
from .base import Method, check_grid_points, register
from .fft import MAX_POINTS, MIN_POINTS, solve_fft
from .fft3d import solve_fft3d

__all__ = ["FFTMethod"]

_BYTES_PER_POINT = 400  # peak Python-side memory of a fixed-N solve (tracemalloc, N = 2^14..2^18)


@register
class FFTMethod(Method):
    """The spectral method: periodic grid, film symbols by FFT, active set + GMRES.

    Options: ``grid_points`` (even, 64 ... 2^22; a power of two is fastest) and
    ``domain_length`` (the period, in h, > 0), each fixed instead of chosen from ``tol``."""

    name = "fft"

    def __init__(self, tol: float = 1e-4, grid_points=None, domain_length=None):
        super().__init__(tol)
        # the options' meaning depends on the scene: checked in solve (line: here; 3D: per axis,
        # by solvers.fft3d)
        self.grid_points = grid_points
        self.domain_length = domain_length

    def _line_options(self):
        grid_points, domain_length = self.grid_points, self.domain_length
        if np.ndim(grid_points) or np.ndim(domain_length):
            raise InputError("grid_points and domain_length are single numbers for a line "
                             "indenter (pairs [nx, ny], [Lx, Ly] are for 3D indenters)")
        shown = f"[{MIN_POINTS}, {MAX_POINTS}] (2^22)"
        big = check_grid_points(grid_points, MIN_POINTS, 2**62, "fft grid points", even=True,
                                shown=shown) \
            if isinstance(grid_points, (int, float)) and grid_points > MAX_POINTS else None
        if big is not None:  # before allocating anything
            raise InputError(
                f"{named('grid_points')} (fft grid points) must be in {shown}; {big} would need "
                f"~{big * _BYTES_PER_POINT / 1e9:.1f} GB")
        grid_points = check_grid_points(grid_points, MIN_POINTS, MAX_POINTS, "fft grid points",
                                        even=True, shown=shown)
        if domain_length is not None:
            domain_length = check_positive("domain_length", domain_length, "h")
        return grid_points, domain_length

    def solve(self, scene, model: str, progress=None):
        """A ContactResult for a plane-strain ``Scene``; a ContactResult3D for a ``Scene3D``."""
        model = self.check_model(model)
        if isinstance(scene, Scene3D):
            return solve_fft3d(scene, model, self.tol, self.grid_points, self.domain_length,
                               progress=progress)
        grid_points, domain_length = self._line_options()
        return solve_fft(scene, model, self.tol, grid_points, domain_length)
