"""Figures of the command line, written to files: the same code as ``ContactResult.plot``."""
from __future__ import annotations

__all__ = ["plot_result", "plot_maps"]


def plot_result(result, path, sensor=None):
    """Write ``result.plot(sensor=sensor)`` to ``path`` (format from the extension)."""
    fig = result.plot(sensor=sensor)
    fig.savefig(path, dpi=120)
    return path


def plot_maps(result, path, sensor: dict | None = None, window: float = 3.0):
    """Write ``result.plot(sensor=sensor)`` of a 3D result (maps) to ``path``."""
    result.plot(sensor=sensor, window=window).savefig(path, dpi=110)
    return path
