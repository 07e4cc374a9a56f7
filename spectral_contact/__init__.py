"""spectral_contact: a rigid cylinder sliding with Amontons friction on an incompressible elastic
film bonded to a rigid base (plane strain) -- contact pressure, base stresses, MEMS sensor view.

Front door: ``solve(...) -> ContactResult``; ``Scene`` holds the SI inputs.
``sweep(...)`` solves the Cartesian product of options (a pandas table; the optional extra
``[sweep]``): imported on first use, so ``import spectral_contact`` imports neither pandas nor dask.
"""
from .api import METHODS, MODELS, solve
from .errors import ConvergenceError, InputError, SpectralContactError
from .physics.scene import PAPER_SCENE, Scene
from .result import ContactResult

__all__ = ["solve", "Scene", "PAPER_SCENE", "ContactResult", "InputError", "ConvergenceError",
           "SpectralContactError", "METHODS", "MODELS", "sweep"]
__version__ = "0.1.0"


def __getattr__(name):
    if name == "sweep":  # the module spectral_contact.sweep, callable as the function sweep(...)
        import importlib

        return importlib.import_module(".sweep", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
