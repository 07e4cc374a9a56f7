"""The FFT method registered by name ("fft", ``solvers.registry``): its options checked, then
the one driver (``fft_driver.run``) on a line (``solvers.fft.solve_fft``) or a surface
(``solvers.fft3d.solve_fft3d``)."""
from __future__ import annotations

from ..errors import ConvergenceError
from ..physics.viscoelastic import MERGE_FACTOR, merged_weights
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
        try:
            return _DRIVERS[scene.dimension](scene, self.check_model(model), self.tol,
                                             self.grid_points, self.domain_length,
                                             progress=progress)
        except ConvergenceError as exc:
            note = _beyond_verified(scene)
            if note is None:
                raise
            raise ConvergenceError(f"{exc} ({note})", exc.residuals, exc.iterations) from exc


def _verified_weight(dimension: str) -> float:
    """The heaviest Prony term E_i/E_inf the viscoelastic solves are verified for: lines, the
    trailing edges' layer fit (``solvers.fft._LineSolve.LAYER_FITTED_WEIGHT``); surfaces, the
    fits' E_0/E_inf (``solvers.fft3d._FITTED_MIN_RATIO``).  Heavier terms (rubber-like films,
    E_0/E_inf ~ 1e2 - 1e3) have their edge structure resolved and may not converge (exit 3):
    behind the trailing edge gap and pressure both stay ~0 over the long relaxation tail and
    the active set keeps changing there (studies/README, viscoelastic, rubber-like films)."""
    from .fft import _LineSolve
    from .fft3d import _FITTED_MIN_RATIO

    return _LineSolve.LAYER_FITTED_WEIGHT if dimension == "line" else 1.0 / _FITTED_MIN_RATIO - 1.0


def _beyond_verified(scene):
    """What a non-converged viscoelastic solve should be told: its Prony weight beyond the
    verified one (``_verified_weight``; lines: the heaviest term's E_i/E_inf with the terms of
    nearby tau, surfaces: their sum, E_0/E_inf - 1, as the surfaces' fits are bounded); else
    None."""
    if not scene.prony or scene.speed == 0.0:
        return None
    line = scene.dimension == "line"
    # lines: a term with those of nearby tau (``physics.viscoelastic.merged_weights``)
    w = (max(merged_weights(scene.prony, scene.young)) if line
         else sum(e / scene.young for e, _ in scene.prony))
    top = _verified_weight(scene.dimension)
    if w <= top * (1.0 + 1e-9):
        return None
    what = "a Prony term E_i/E_inf" if line else "the Prony terms' sum E_0/E_inf - 1"
    counted = f" (terms within a factor {MERGE_FACTOR:g} in tau counted as one)" if line else ""
    return (f"{what} = {w:.3g}, beyond the {top:.3g} the "
            f"viscoelastic solver is verified for{counted}: on films this much stiffer when glassy the "
            f"active set behind the trailing edge may not settle; a lower --speed (slow sliding) "
            f"or a higher one (the glassy film) may solve")


_DRIVERS = {"line": solve_fft, "surface": solve_fft3d}
