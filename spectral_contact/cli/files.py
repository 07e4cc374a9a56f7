"""Writing results: profile CSV and JSON."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

__all__ = ["write_csv", "to_json", "check_plot_path", "meta_path", "write_meta_json", "json_ready"]


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


def json_ready(v):
    """``v`` with every non-finite float replaced by None (JSON has no NaN or Infinity)."""
    import math

    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, dict):
        return {k: json_ready(w) for k, w in v.items()}
    if isinstance(v, (list, tuple)):
        return [json_ready(w) for w in v]
    return v


def meta_path(csv_path) -> Path:
    """Where the metadata of a CSV file goes: ``p.csv`` -> ``p.meta.json`` (beside it)."""
    p = Path(csv_path)
    return p.with_name((p.stem if p.suffix.lower() == ".csv" else p.name) + ".meta.json")


def write_meta_json(csv_path, record: dict) -> Path:
    """Write ``record`` as JSON beside ``csv_path`` (see ``meta_path``), whole or not at all
    (temporary file in the same folder, then renamed over the target).  The CSV files
    themselves carry no comment lines, so that ``pandas.read_csv(path)`` and
    ``numpy.genfromtxt(path, delimiter=',', names=True)`` open them with no other argument."""
    import os
    import tempfile

    path = meta_path(csv_path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(json.dumps(json_ready(record), indent=2) + "\n")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
