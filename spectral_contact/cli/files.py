"""Writing results: profile CSV and JSON."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

__all__ = ["write_csv", "to_json", "check_plot_path"]


def check_plot_path(path) -> Path:
    """A figure path whose extension matplotlib can write and whose folder exists."""
    from matplotlib.backend_bases import FigureCanvasBase

    from ..errors import InputError

    path = Path(path)
    formats = FigureCanvasBase.get_supported_filetypes()
    if path.suffix.lstrip(".").lower() not in formats:
        raise InputError(f"--plot {path}: unsupported format; use one of {', '.join(sorted(formats))}")
    if str(path.parent) not in ("", ".") and not path.parent.is_dir():
        raise InputError(f"--plot {path}: directory {path.parent} does not exist")
    return path


def write_csv(path, columns: dict, header_comment: str | None = None) -> Path:
    """Write equal-length 1D arrays as CSV with a header row (full double precision)."""
    path = Path(path)
    names = list(columns)
    data = np.column_stack([np.asarray(columns[n], dtype=float) for n in names])
    with path.open("w", encoding="utf-8") as fh:
        if header_comment:
            for line in header_comment.splitlines():
                fh.write(f"# {line}\n")
        fh.write(",".join(names) + "\n")
        np.savetxt(fh, data, delimiter=",", fmt="%.17g")
    return path


def to_json(record: dict) -> str:
    return json.dumps(record, indent=2, sort_keys=False)
