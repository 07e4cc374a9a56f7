"""Writing results: profile CSV and JSON."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

__all__ = ["write_csv", "to_json"]


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
