"""spectral_contact: a rigid cylinder sliding with Amontons friction on an incompressible elastic
film bonded to a rigid base (plane strain) -- contact pressure, base stresses, MEMS sensor view.

Front door: ``solve(...) -> ContactResult``; ``Scene`` holds the SI inputs;
``sensor(result) -> SensorView`` is the MEMS sensor's view (imported on first use).
``sweep(...)`` solves the Cartesian product of options (a pandas table; the optional extra
``[sweep]``): imported on first use, so ``import spectral_contact`` imports neither pandas nor
dask.distributed.
"""
from .api import METHODS, MODELS, solve
from .errors import ConvergenceError, InputError, SpectralContactError
from .physics.scene import PAPER_SCENE, Scene
from .result import ContactResult

__all__ = ["solve", "Scene", "PAPER_SCENE", "ContactResult", "InputError", "ConvergenceError",
           "SpectralContactError", "METHODS", "MODELS", "sensor", "SensorView", "sweep",
           "__version__"]
__version__ = "0.1.0"

_LAZY = {"sensor": "spectral_contact.instruments.mems_view",
         "SensorView": "spectral_contact.instruments.mems_view"}


def __getattr__(name):  # the sensor view needs scipy.special: imported on first use only
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    if name == "sweep":  # the module spectral_contact.sweep, callable as the function sweep(...)
        import importlib

        return importlib.import_module(".sweep", __name__)
    raise AttributeError(f"module 'spectral_contact' has no attribute {name!r}")
