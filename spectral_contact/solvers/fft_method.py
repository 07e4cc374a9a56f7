"""The FFT method registered by name ("fft", ``solvers.registry``): its options checked, then
the one driver (``fft_driver.run``) on a line (``solvers.fft.solve_fft``) or a surface
(``solvers.fft3d.solve_fft3d``)."""
from __future__ import annotations

from .base import Method, register
from .fft import MAX_POINTS, MIN_POINTS, solve_fft  # noqa: F401 (importable from here)
from .fft3d import solve_fft3d

__all__ = ["FFTMethod"]


@register
class FFTMethod(Method):
    """The spectral method: periodic grid, film symbols by FFT, active set + GMRES.

    Options: ``grid_points`` (even, 64 ... 2^22; a power of two is fastest) and
    ``domain_length`` (the period, in h, > 0), each fixed instead of chosen from ``tol``."""

    name = "fft"

    def __init__(self, tol: float = 1e-4, grid_points=None, domain_length=None):
        super().__init__(tol)
        # the options' meaning depends on the scene: checked by the scene's driver (line:
        # solvers.fft._check_fixed; 3D: per axis, solvers.fft3d._check_fixed)
        self.grid_points = grid_points
        self.domain_length = domain_length

    def solve(self, scene, model: str, progress=None):
        """A ContactResult for a plane-strain ``Scene``; a ContactResult3D for a ``Scene3D``
        (the driver of the scene's ``dimension``; each checks its own ``grid_points`` and
        ``domain_length``)."""
        return _DRIVERS[scene.dimension](scene, self.check_model(model), self.tol,
                                         self.grid_points, self.domain_length, progress=progress)


_DRIVERS = {"line": solve_fft, "surface": solve_fft3d}
