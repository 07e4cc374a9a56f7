"""spectral_contact: a rigid indenter sliding with friction on an elastic film bonded to a rigid
base -- contact pressure, base stresses, MEMS sensor view; plane strain (a line indenter, the
paper's model) or 3D (a sphere, a finite cylinder, a paraboloid, any shape).

Front door: ``solve(...) -> ContactResult`` (``ContactResult3D`` for a 3D indenter:
``solve(indenter="sphere", force=1.0, mu=1.0)``); ``Scene`` / ``Scene3D`` hold the SI inputs,
or ``solve(film=Film(...), indenter=..., interface=Interface(...), load=...)`` composes them;
``sensor(result) -> SensorView`` is the MEMS sensor's view (imported on first use).
``sweep(...)`` solves the Cartesian product of options (a pandas table; the optional extra
``[sweep]``): imported on first use, so ``import spectral_contact`` imports neither pandas nor
dask.distributed.
"""
from ._version import __version__
from .api import METHODS, MODELS, solve
from .errors import ConvergenceError, InputError, SpectralContactError
from .physics.film import Film
from .physics.friction import FrictionLaw
from .physics.interface import Interface
from .physics.scene import PAPER_SCENE, Scene, Scene3D
from .physics.shapes import Shape
from .result import ContactResult, ContactResult3D
from .solvers.onset import OnsetResult, onset  # noqa: F401 (issue 22: the onset of sliding)

__all__ = ["solve", "Scene", "Scene3D", "PAPER_SCENE", "ContactResult", "ContactResult3D",
           "Film", "Shape", "Interface", "FrictionLaw", "InputError", "ConvergenceError",
           "SpectralContactError", "METHODS", "MODELS", "sensor", "invert", "SensorView", "sweep",
           "__version__"]


def __getattr__(name):  # the sensor view needs scipy.special: imported on first use only
    if name in ("sensor", "SensorView"):
        from .instruments import mems_view

        value = getattr(mems_view, name)
        globals()[name] = value
        return value
    if name == "invert":  # issue 21: the inverse, from base stresses to tractions (lines, maps)
        from .instruments.inverse_maps import invert

        globals()[name] = invert
        return invert
    if name == "sweep":  # the module spectral_contact.sweep, callable as the function sweep(...)
        import spectral_contact.sweep as module  # (the import system sets the attribute)

        return module
    raise AttributeError(f"module 'spectral_contact' has no attribute {name!r}")
