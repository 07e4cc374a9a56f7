"""Writing results: profile CSV and JSON, and all-or-nothing output files.

Every output of a command is written to a temporary file beside its target
(``Outputs.path``) and renamed into place only when all of them are complete
(``Outputs.commit``); on any error or interrupt the temporaries are removed and no target is
touched.  Paths are checked before any work (``check_outputs``): a folder that exists, not a
directory, not empty, no two outputs on the same file, a plot format matplotlib can write.
"""
from __future__ import annotations

import json
import math
import os
import secrets
import signal
import threading
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["write_csv", "to_json", "check_plot_path", "check_output", "check_outputs",
           "Outputs", "meta_path", "write_meta_json", "json_ready"]


def check_plot_path(path, option: str = "--plot") -> Path:
    """A figure path whose extension matplotlib can write and whose folder exists."""
    from matplotlib.backend_bases import FigureCanvasBase

    path = check_output(path, option)
    formats = FigureCanvasBase.get_supported_filetypes()
    if path.suffix.lstrip(".").lower() not in formats:
        raise InputError(f"{option} {path}: unsupported format; use one of {', '.join(sorted(formats))}")
    return path


def check_output(path, option: str) -> Path:
    """An output path: not empty, not a directory, in a folder that exists."""
    if path is None:
        return None
    if not str(path).strip():
        raise InputError(f"{option}: empty file name")
    p = Path(path)
    if p.is_dir():
        raise InputError(f"{option} {path}: is a directory")
    if str(p.parent) not in ("", ".") and not p.parent.is_dir():
        raise InputError(f"{option} {path}: directory {p.parent} does not exist")
    if p.exists() and not p.is_file():
        raise InputError(f"{option} {path}: exists and is not a regular file")
    return p


def check_outputs(**paths) -> dict:
    """Check several outputs ({option: path or None}); refuse two options naming one file."""
    out = {}
    seen = {}
    for option, path in paths.items():
        if path is None:
            continue
        p = check_output(path, option)
        key = os.path.realpath(p)
        if key in seen:
            raise InputError(f"{seen[key]} and {option} name the same file {path}: give two "
                             f"different paths")
        seen[key] = option
        out[option] = p
    return out


COMMITTED: list[Path] = []
"""Targets renamed into place by Outputs.commit in this process (the command line clears it per
command, to say truthfully whether an interrupted command wrote anything)."""


class Outputs:
    """All-or-nothing output files.

        with Outputs() as outs:
            write_csv(outs.path("p.csv"), ...)
            fig.savefig(outs.path("p.png"))
        # both renamed into place here, or neither (and no temporary left) on any exception

    Temporaries are hidden files beside their targets, keeping the target's suffix (matplotlib
    picks the format from it), created with the mode a new file would get (umask).
    """

    def __init__(self):
        self._pending: list[tuple[Path, Path]] = []

    def path(self, target) -> Path:
        target = Path(target)
        for _ in range(100):
            tmp = target.with_name(f".{target.name}.{secrets.token_hex(4)}.tmp{target.suffix}")
            try:
                fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            except FileExistsError:
                continue
            except OSError as exc:  # name the user's file, not the temporary
                raise InputError(f"{target}: cannot write in {target.parent} "
                                 f"({exc.strerror or exc})") from None
            os.close(fd)
            self._pending.append((tmp, target))
            return tmp
        raise OSError(f"cannot create a temporary file beside {target}")

    def commit(self) -> None:
        """Rename every temporary onto its target (signals held off meanwhile)."""
        main = threading.current_thread() is threading.main_thread()
        sigs = {signal.SIGINT, signal.SIGTERM}
        if main:
            old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
        try:
            for tmp, target in self._pending:
                os.replace(tmp, target)
                COMMITTED.append(target)
            self._pending = []
        finally:
            if main:
                signal.pthread_sigmask(signal.SIG_SETMASK, old)

    def abort(self) -> None:
        for tmp, _ in self._pending:
            try:
                os.unlink(tmp)
            except OSError:
                pass
        self._pending = []

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            try:
                self.commit()
            except BaseException:
                self.abort()
                raise
        else:
            self.abort()
        return False


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
    """Strict JSON: a non-finite number (none is expected) becomes null, never NaN."""
    return json.dumps(json_ready(record), indent=2, sort_keys=False, allow_nan=False)


def json_ready(v):
    """``v`` with every non-finite float replaced by None (JSON has no NaN or Infinity)."""
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


def add_meta(outs, csv_target, record: dict) -> Path:
    """Write ``record`` as the JSON metadata of ``csv_target`` (``meta_path``) within the set of
    outputs ``outs`` (an ``Outputs``): renamed into place with the CSV, or not at all."""
    tmp = outs.path(meta_path(csv_target))
    tmp.write_text(json.dumps(json_ready(record), indent=2) + "\n", encoding="utf-8")
    return tmp
