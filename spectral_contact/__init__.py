"""spectral_contact: a rigid cylinder sliding with Amontons friction on an incompressible elastic
film bonded to a rigid base (plane strain) -- contact pressure, base stresses, MEMS sensor view.

Front door: ``solve(...) -> ContactResult``; ``Scene`` holds the SI inputs.
"""
from .api import METHODS, MODELS, solve
from .errors import ConvergenceError, InputError, SpectralContactError
from .physics.scene import PAPER_SCENE, Scene
from .result import ContactResult

__all__ = ["solve", "Scene", "PAPER_SCENE", "ContactResult", "InputError", "ConvergenceError",
           "SpectralContactError", "METHODS", "MODELS"]
__version__ = "0.1.0"
