"""Reading measured (MEMS) profiles and radial profiles from CSV, with validation.

File format: comma-separated, one header row naming the columns (required), then numeric rows.
Lines starting with ``#`` (and anything after a ``#`` on a data line) are comments; blank lines
are skipped; extra columns are ignored.

* Line profiles (``read_measured_profile``): ``x_m, S_zz_Pa, S_xz_Pa`` (sensor stresses, S_zz > 0
  in compression) or ``x_m, U_zz_mV, U_xz_mV`` (raw sensor outputs).  ``x_m`` must be strictly
  increasing and uniformly spaced (steps equal within ``UNIFORM_RTOL``), with at least
  ``MIN_POINTS`` rows (integrals, FFT convolution and a 3-parameter fit need a few points).
* Radial profiles (``read_radial_profile``): ``r_m`` (>= 0, increasing, uniform) plus named value
  columns.

Every problem raises ``InputError`` with a one-line message naming the file (and the column or
line).  Nothing here writes files.
"""
from __future__ import annotations

import math
import stat
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..units import A_XZ_MV_PER_BAR, A_ZZ_MV_PER_BAR, PA_PER_BAR

__all__ = ["read_table", "read_measured_profile", "read_radial_profile", "MeasuredProfile",
           "check_uniform", "STRESS_COLUMNS", "VOLTAGE_COLUMNS", "MIN_POINTS", "UNIFORM_RTOL",
           "MAX_BYTES"]

STRESS_COLUMNS = ("x_m", "S_zz_Pa", "S_xz_Pa")
VOLTAGE_COLUMNS = ("x_m", "U_zz_mV", "U_xz_mV")
MIN_POINTS = 8
MAX_BYTES = 20 * 10**6
"""Largest measured file read (20 MB, ~300 000 rows of three doubles at full precision): a sensor
scan has thousands of rows, and a 200 MB file kept the reader and the comparison busy for over
10 minutes (issue 11)."""
UNIFORM_RTOL = 1e-3


def _short(s: str, n: int = 40) -> str:
    s = s.replace("\n", " ").replace("\r", " ")
    return repr(s if len(s) <= n else s[:n] + "...")


def _is_number(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return False


def read_table(path, *, required=(), any_of=(), what: str = "columns") -> dict:
    """Read a headed numeric CSV; return {column name: float array} for every column.

    required : names that must all be present.
    any_of : a sequence of alternative name groups; at least one group must be fully present.
    Raises InputError (one line, naming the file) on any problem.
    """
    path = Path(path)
    name = str(path)
    try:
        st = path.stat()
        if not stat.S_ISREG(st.st_mode):  # a FIFO or a device would block or never end
            raise InputError(f"{name}: not a regular file")
        if st.st_size > MAX_BYTES:
            raise InputError(f"{name}: {st.st_size / 1e6:.0f} MB exceeds the {MAX_BYTES / 1e6:.0f} MB "
                             f"limit on measured files (~{MAX_BYTES // 60:,} rows)")
        with path.open("rb") as fh:
            raw = fh.read(MAX_BYTES + 1)
        if len(raw) > MAX_BYTES:
            raise InputError(f"{name}: exceeds the {MAX_BYTES / 1e6:.0f} MB limit on measured files")
        text = raw.decode("utf-8-sig")  # a byte-order mark (spreadsheet export) is accepted
    except UnicodeDecodeError:
        raise InputError(f"{name}: not a UTF-8 text file") from None
    except OSError as exc:
        raise InputError(f"{name}: cannot read ({exc.strerror or exc})") from None
    header = None
    rows: list[tuple[int, list[str]]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        cells = [c.strip() for c in line.split(",")]
        if header is None:
            if all(_is_number(c) for c in cells if c):
                raise InputError(f"{name}: missing header line (line {lineno} is numeric; "
                                 f"expected {what})")
            if any(not c for c in cells):
                raise InputError(f"{name}: empty column name in the header (line {lineno})")
            dup = sorted({c for c in cells if cells.count(c) > 1})
            if dup:
                raise InputError(f"{name}: duplicate column {dup[0]!r} in the header")
            header = (lineno, cells)
            continue
        rows.append((lineno, cells))
    if header is None:
        raise InputError(f"{name}: empty file (no header; expected {what})")
    names = header[1]
    missing = [c for c in required if c not in names]
    if missing:
        raise InputError(f"{name}: missing column {', '.join(missing)} (expected {what})")
    if any_of and not any(all(c in names for c in group) for group in any_of):
        groups = " or ".join("(" + ", ".join(g) + ")" for g in any_of)
        raise InputError(f"{name}: missing columns: need {groups}; found {', '.join(names)}")
    if not rows:
        raise InputError(f"{name}: no data rows after the header")
    data = np.empty((len(rows), len(names)))
    for i, (lineno, cells) in enumerate(rows):
        if len(cells) != len(names):
            raise InputError(f"{name} line {lineno}: {len(cells)} cells, the header has "
                             f"{len(names)}")
        for j, c in enumerate(cells):
            try:
                v = float(c)
            except ValueError:
                raise InputError(f"{name} line {lineno}, column {names[j]}: not a number: "
                                 f"{_short(c)}") from None
            if not math.isfinite(v):
                raise InputError(f"{name} line {lineno}, column {names[j]}: not finite ({c})")
            data[i, j] = v
    return {n: data[:, j].copy() for j, n in enumerate(names)}


def check_uniform(x: np.ndarray, name: str, column: str, min_points: int = MIN_POINTS) -> float:
    """Check that x is strictly increasing and uniform; return the step."""
    if x.size < min_points:
        raise InputError(f"{name}: only {x.size} data rows; need at least {min_points} to "
                         f"integrate and fit")
    d = np.diff(x)
    if np.any(d <= 0):
        i = int(np.argmax(d <= 0))
        raise InputError(f"{name} column {column}: not strictly increasing (row {i + 2} of the "
                         f"data: {x[i]:g} then {x[i + 1]:g})")
    step = (x[-1] - x[0]) / (x.size - 1)
    dev = np.max(np.abs(d - step)) / step
    if dev > UNIFORM_RTOL:
        raise InputError(f"{name} column {column}: non-uniform spacing (steps {d.min():.6g} to "
                         f"{d.max():.6g}; must agree within {UNIFORM_RTOL:.1%})")
    return float(step)


@dataclass
class MeasuredProfile:
    """A measured line profile (apex offset unknown), as read from a file.

    x_m : uniform, increasing positions [m]; kind : "S" (stresses, Pa) or "U" (outputs, mV);
    zz, xz : the two components in the file's units (S_zz > 0 in compression).
    """

    path: str
    x_m: np.ndarray
    kind: str
    zz: np.ndarray
    xz: np.ndarray

    @property
    def dx(self) -> float:
        return float((self.x_m[-1] - self.x_m[0]) / (self.x_m.size - 1))

    def stresses(self, A_zz_mV_per_bar: float = A_ZZ_MV_PER_BAR,
                 A_xz_mV_per_bar: float = A_XZ_MV_PER_BAR):
        """(S_zz_Pa, S_xz_Pa): the file's stresses, or its outputs divided by A [mV/Pa]."""
        if self.kind == "S":
            return self.zz.copy(), self.xz.copy()
        return (self.zz / (A_zz_mV_per_bar / PA_PER_BAR),
                self.xz / (A_xz_mV_per_bar / PA_PER_BAR))


def read_measured_profile(path, min_points: int = MIN_POINTS) -> MeasuredProfile:
    """Read ``x_m, S_zz_Pa, S_xz_Pa`` or ``x_m, U_zz_mV, U_xz_mV`` (if both sets are present the
    stresses are used)."""
    what = "x_m, S_zz_Pa, S_xz_Pa or x_m, U_zz_mV, U_xz_mV"
    cols = read_table(path, required=("x_m",), any_of=(STRESS_COLUMNS, VOLTAGE_COLUMNS), what=what)
    x = cols["x_m"]
    check_uniform(x, str(path), "x_m", min_points)
    if all(c in cols for c in STRESS_COLUMNS):
        return MeasuredProfile(str(path), x, "S", cols["S_zz_Pa"], cols["S_xz_Pa"])
    return MeasuredProfile(str(path), x, "U", cols["U_zz_mV"], cols["U_xz_mV"])


def read_radial_profile(path, candidates, min_points: int = MIN_POINTS):
    """Read ``r_m`` and the first present column among ``candidates``.

    Returns (r_m, values, column_name).  r_m must be >= 0, strictly increasing and uniform.
    """
    what = "r_m and one of " + ", ".join(candidates)
    cols = read_table(path, required=("r_m",), any_of=tuple((c,) for c in candidates), what=what)
    r = cols["r_m"]
    if np.any(r < 0):
        raise InputError(f"{path} column r_m: negative radius ({r.min():g}); radial profiles "
                         f"need r >= 0")
    check_uniform(r, str(path), "r_m", min_points)
    for c in candidates:
        if c in cols:
            return r, cols[c], c
    raise AssertionError("unreachable")  # pragma: no cover
