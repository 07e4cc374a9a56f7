"""The sweep's store and its files: ``out/scenes/<key>.json`` per finished scene (what a rerun
reuses), the profiles, and the tables (``summary.csv``, ``summary.parquet``,
``profiles/index.csv``).  Every file is written whole or not at all (a temporary beside it,
renamed); a failure names the user's file, never the temporary.
"""
from __future__ import annotations

import errno
import hashlib
import json
import os
import tempfile
from pathlib import Path

import numpy as np

from ..errors import InputError
from .table import OPTIONS, column, table_columns
from .table import package_version as _version

__all__ = ["Store", "write_tables", "write_profile_index", "plain"]


def _atomic_write(path: Path, write, binary: bool = False) -> None:
    """Write ``path`` whole or not at all: ``write(fh)`` into a temporary beside it, renamed.
    An OSError names ``path`` (issue 24: not the temporary)."""
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
    try:
        with (os.fdopen(fd, "wb") if binary else
              os.fdopen(fd, "w", encoding="utf-8", newline="")) as fh:
            write(fh)
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError):
            raise OSError(exc.errno or errno.EIO, exc.strerror or str(exc), str(path)) from None
        raise


class Store:
    """``out/scenes/<key>.json`` per finished scene; ``out/profiles/<key>.csv`` when asked.
    The folder and the files the sweep writes are checked when it is made (before any work):
    InputError naming --out and the file."""

    def __init__(self, out, profiles: bool):
        if out is not None and not str(out).strip():  # issue 24: Path("") is the current folder
            raise InputError("--out: empty folder name")
        self.out = Path(out) if out is not None else None
        self.profiles = profiles
        if self.out is None:
            return
        if self.out.exists() and not self.out.is_dir():
            raise InputError(f"--out {out}: exists and is not a directory")
        if not self.out.parent.is_dir():
            raise InputError(f"--out {out}: directory {self.out.parent} does not exist")
        self.scenes = self.out / "scenes"
        self.prof = self.out / "profiles"
        folders = (self.scenes, self.prof) if profiles else (self.scenes,)
        for d in folders:
            if d.exists() and not d.is_dir():
                raise InputError(f"--out {out}: {d} exists and is not a directory")
        files = [self.out / "summary.csv", self.out / "summary.parquet"]
        if profiles:
            files.append(self.prof / "index.csv")
        for f in files:
            if f.exists() and not f.is_file():
                raise InputError(f"--out {out}: {f} exists and is not a regular file")

    def prepare(self):
        """Make the folders (an OSError names the folder)."""
        if self.out is not None:
            self.scenes.mkdir(parents=True, exist_ok=True)
            if self.profiles:
                self.prof.mkdir(exist_ok=True)

    def load(self, key: str, params: dict):
        """The stored row of ``key``, or None (absent, unreadable, other parameters, version or
        columns)."""
        if self.out is None:
            return None
        try:
            rec = json.loads((self.scenes / f"{key}.json").read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        if (not isinstance(rec, dict) or rec.get("version") != _version()
                or rec.get("params") != params or not isinstance(rec.get("row"), dict)
                or list(rec["row"]) != table_columns()):
            return None
        if self.profiles and rec["row"].get("status") == "ok" and not all(
                _file_digest(self.prof / f"{key}{ext}") == rec.get("files", {}).get(f"{key}{ext}")
                for ext in self.kinds(params)):
            # stored by a run without profiles, or a profile file missing, truncated or changed
            # since (issue 24: every reused file is verified against its recorded sha256)
            return None
        return rec["row"]

    @staticmethod
    def kinds(params):
        return (".csv",) if params.get("indenter", "line") == "line" else (".csv", ".npz")

    def save(self, row: dict, params: dict, prof) -> None:
        if self.out is None or row["status"] == "crashed":
            return
        key = row["key"]
        files = {}
        if prof is not None:
            maps = None
            if "maps" in prof:
                prof, maps = prof["profiles"], prof["maps"]
            _atomic_write(self.prof / f"{key}.csv", lambda fh: _write_profiles(fh, prof))
            if maps is not None:
                _atomic_write(self.prof / f"{key}.npz",
                              lambda fh: np.savez_compressed(fh, **maps), binary=True)
            files = {f"{key}{ext}": _file_digest(self.prof / f"{key}{ext}")
                     for ext in self.kinds(params)}
        rec = {"key": key, "version": _version(), "params": params, "row": row, "files": files}
        _atomic_write(self.scenes / f"{key}.json", lambda fh: json.dump(rec, fh, indent=1))


def _file_digest(path: Path):
    """sha256 of a file's bytes (None if it cannot be read): a reused profile must match the
    digest recorded with its scene."""
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def _write_profiles(fh, prof: dict) -> None:
    names = list(prof)
    fh.write(",".join(names) + "\n")
    for vals in zip(*(prof[n] for n in names)):
        fh.write(",".join(repr(float(v)) for v in vals) + "\n")


# --- the tables ---------------------------------------------------------------------------------
def plain(v):
    """A cell as plain text for the files: lists (contact_intervals_m) as JSON with ';' for ','
    (``json.loads(cell.replace(";", ","))`` reads it back), commas in text as ';' (so that
    readers without quoting, numpy.genfromtxt, split the columns right)."""
    if isinstance(v, (list, tuple)):
        return json.dumps(v, separators=(";", ":"))
    if isinstance(v, str):
        return v.replace(",", ";")
    return v


def write_profile_index(df, folder: Path) -> None:
    """``profiles/index.csv`` (issue 24): which file holds which scene -- the file names (a
    hash each) with the options that vary across the sweep (their table columns) and the
    status, in the table's order.  Scenes without profiles (failed) have an empty file name."""
    varying = [column(k) for k in OPTIONS if df[column(k)].astype(str).nunique() > 1] or ["indenter"]
    rows = []
    for _, r in df.iterrows():
        ok = r["status"] == "ok"
        kinds = Store.kinds({"indenter": r["indenter"]})
        rows.append({"file": f"{r['key']}.csv" if ok else "",
                     "maps_file": f"{r['key']}.npz" if ok and ".npz" in kinds else "",
                     **{k: r[k] for k in varying}, "status": r["status"]})
    import pandas as pd

    index = pd.DataFrame(rows)
    for c in index.columns:
        index[c] = [plain(v) for v in index[c]]
    _atomic_write(folder / "index.csv", lambda fh: index.to_csv(fh, index=False))


def write_tables(df, out: Path) -> None:
    """``out/summary.csv`` and, with pyarrow, ``out/summary.parquet``."""
    from pandas.api.types import is_numeric_dtype

    df = df.copy()
    for c in df.columns:  # text and list columns (object, or pandas' string dtype)
        if not is_numeric_dtype(df[c]):
            df[c] = [plain(v) for v in df[c]]
    _atomic_write(out / "summary.csv", lambda fh: df.to_csv(fh, index=False))
    try:
        import pyarrow  # noqa: F401
    except ModuleNotFoundError:
        return
    for c in df.columns:  # a column of mixed kinds (numbers and text) as text for Arrow
        if not is_numeric_dtype(df[c]):
            kinds = {type(v) for v in df[c] if v is not None and v == v}
            if len(kinds) > 1:
                df[c] = [None if v is None else str(v) for v in df[c]]
    _atomic_write(out / "summary.parquet", lambda fh: df.to_parquet(fh, index=False), binary=True)
