"""The package's version: a leaf module, read by the package root and by the modules that record
it (``sweep``'s store keys, ``cli.main``'s --version), so that no submodule imports the root."""
__version__ = "0.1.0"
