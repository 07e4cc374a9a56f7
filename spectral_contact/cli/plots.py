"""Figures of the command line, written to files: the same code as ``ContactResult.plot``."""
from __future__ import annotations

__all__ = ["plot_result"]


def plot_result(result, path, sensor=None):
    """Write ``result.plot(sensor=sensor)`` to ``path`` (format from the extension)."""
    fig = result.plot(sensor=sensor)
    fig.savefig(path, dpi=120)
    return path
