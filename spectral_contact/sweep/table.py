"""The sweep's options and its table: option values, the Cartesian product of scenes, the
scene key, and the columns of the table (one name per quantity, with its unit).

Inputs are named as the options (``load``, ``--load``, the TOML spec's keys); the table names
each quantity as ``solve --json`` does (``load_N_per_m``): ``column(name)`` maps one to the other.
"""
from __future__ import annotations

import hashlib
import itertools
import json
import math
import os

from ..errors import InputError
from ..physics import options as _table

__all__ = ["OPTIONS", "STATUSES", "TIMING_COLUMNS", "EXTRA", "MAX_SCENES", "parse_values",
           "read_spec", "scenes", "plan", "scene_key", "table_columns", "column", "option_of",
           "check_product", "row_of"]

STATUSES = ("ok", "input_error", "not_converged", "crashed")
TIMING_COLUMNS = ("wall_time_s", "plan_time_s")
EXTRA = "pip install 'spectral_contact[sweep]'"
MAX_SCENES = 100_000
"""Largest Cartesian product of a sweep (the product of the option lists' lengths, checked before
it is enumerated): 10^5 scenes of ~10 ms are ~20 min on 1 core, and their table ~100 MB."""


def _options() -> dict:
    """name -> (type, default, unit or choices, help) of the options with ``sweep=True`` in the
    one declaration (``physics.options``), in its order (the column order).  A scene option
    that only one kind of indenter takes defaults to None here: filled per indenter by ``scenes``
    (``_fill``: a line's load, a 3D indenter's force) or left to ``solve``."""
    out = {}
    for o in _table.OPTIONS:
        if o.sweep:
            d = o.default if o.scenes in ("both", "solve") and o.kind is not tuple else None
            out[o.name] = (o.kind, d, o.choices if o.kind is str else o.unit, o.cli_help())
    return out


OPTIONS = _options()
SCENE_KEYS = tuple(k for k in OPTIONS if _table.option(k).scenes != "solve")
_LINE_DEFAULTS = {"load": _table.default("load"), "tol": 1e-4}
_3D_DEFAULTS = {"force": _table.default("force")}


def _fill(p: dict) -> dict:
    """Defaults that depend on the indenter (a line's load and tol, a 3D indenter's force)."""
    for k, v in (_LINE_DEFAULTS if p["indenter"] == "line" else _3D_DEFAULTS).items():
        if p[k] is None:
            p[k] = v
    return p


def defaults() -> dict:
    """Every option at its sweep default (None: per indenter or left to ``solve``)."""
    return {k: OPTIONS[k][1] for k in OPTIONS}


def fill(params: dict) -> dict:
    """``params`` (options by name) over the defaults, the indenter's defaults filled in;
    InputError for an unknown option."""
    unknown = [k for k in params if k not in OPTIONS]
    if unknown:
        raise InputError(f"unknown option {unknown[0]!r} (accepted: {', '.join(OPTIONS)})")
    return _fill({**defaults(), **params})


# --- specifications -----------------------------------------------------------------------------
def _flag(name: str) -> str:
    return name.replace("_", "-")


def _number(name: str, text: str, kind):
    try:
        v = int(text) if kind is int else float(text)
    except (TypeError, ValueError):
        what = "an integer" if kind is int else "a number"
        raise InputError(f"--{_flag(name)}: {text!r} is not {what} (values: v1,v2,... or "
                         f"start:stop:step)") from None
    if kind is float and not math.isfinite(v):
        raise InputError(f"--{_flag(name)}: values must be finite; got {text!r}")
    return v


def _range(name: str, text: str, kind) -> list:
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"--{_flag(name)}: a range is start:stop:step; got {text!r}")
    start, stop, step = (_number(name, p.strip(), kind) for p in parts)
    if step <= 0:
        raise InputError(f"--{_flag(name)}: the step of {text!r} must be > 0; got {step:g}")
    if stop < start:
        raise InputError(f"--{_flag(name)}: empty range {text!r} (stop < start)")
    n = int(math.floor((stop - start) / step * (1 + 1e-12) + 1e-9)) + 1
    if n > 1_000_000:
        raise InputError(f"--{_flag(name)}: {text!r} has {n} values (at most 1000000)")
    if kind is int:
        return [start + i * step for i in range(n)]
    return [float(f"{start + i * step:.12g}") for i in range(n)]


def _one(name: str, p, kind, choices) -> list:
    """The values of one piece of a spec (a choice, a number or a range)."""
    if kind is str:
        if not isinstance(p, str) or p not in choices:
            raise InputError(f"--{_flag(name)}: {p!r} is not one of {', '.join(choices)}")
        return [p]
    if isinstance(p, str) and ":" in p:
        return _range(name, p, kind)
    if p is None and OPTIONS[name][1] is None:
        return [None]
    if isinstance(p, bool):
        raise InputError(f"--{_flag(name)}: {p!r} is not a number")
    if kind is int and isinstance(p, float) and not p.is_integer():
        raise InputError(f"--{_flag(name)}: {p!r} is not an integer")
    return [_number(name, p, kind)]


def _is_pairs(value) -> bool:
    return isinstance(value, (list, tuple)) and all(
        isinstance(t, (list, tuple)) and len(t) == 2 and
        all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in t) for t in value)


def _structured(name: str, value) -> list:
    """The values of a structured option (``kind`` tuple: the Prony terms): a string of series
    separated by ';' ("2.2e6,0.01;1e6,0.1"), one series as pairs, or a list of series; each
    parsed by the option's own parser (``physics.options``) into a list of [E_i, tau_i]."""
    if isinstance(value, str):
        specs = [p.strip() for p in value.split(";")]
    elif value is None or _is_pairs(value):
        specs = [value]
    else:
        specs = list(value)
    out = []
    for spec in specs:
        if spec is None:
            out.append(None)
            continue
        terms = _table.option(name).check(spec) if spec != "" else None
        if not terms:
            raise InputError(f"--{_flag(name)}: an empty series in {value!r:.60}")
        out.append([list(t) for t in terms])
    return out


def parse_values(name: str, value) -> list:
    """The list of values of option ``name`` from a spec: a scalar, a list, or a string of comma
    separated numbers / choices / start:stop:step ranges (the Prony terms: series separated by
    ';').  Raises InputError naming the option."""
    if name not in OPTIONS:
        raise InputError(f"unknown option {name!r} (accepted: {', '.join(OPTIONS)})")
    kind, _, choices, _ = OPTIONS[name]
    if kind is tuple:
        return _unique(_structured(name, value))
    items = value if isinstance(value, (list, tuple)) else [value]
    out = []
    for item in items:
        if isinstance(item, str):
            pieces = [p.strip() for p in item.split(",")]
            if not all(pieces):
                raise InputError(f"--{_flag(name)}: empty value in {item!r}")
        else:
            pieces = [item]
        for p in pieces:
            out.extend(_one(name, p, kind, choices))
    if not out:
        raise InputError(f"--{_flag(name)}: no values")
    return _unique(out)


def _unique(values: list) -> list:
    """A value given twice is one scene (lists compared by their JSON)."""
    seen = {}
    for v in values:
        seen.setdefault(json.dumps(v) if isinstance(v, list) else v, v)
    return list(seen.values())


def read_spec(path) -> dict:
    """The options of a TOML spec file (top-level keys = option names, values as in
    ``parse_values``: numbers, lists, or strings such as "20:380:40")."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10: the same parser as the tomli package
        try:
            import tomli as tomllib
        except ModuleNotFoundError:
            raise InputError("--spec needs Python >= 3.11 (tomllib) or the tomli package") from None
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise InputError(f"--spec {path}: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"--spec {path}: not valid TOML ({exc})") from None
    for k, v in data.items():
        if k not in OPTIONS:
            raise InputError(f"--spec {path}: unknown option {k!r} (accepted: {', '.join(OPTIONS)})")
        if isinstance(v, dict):
            raise InputError(f"--spec {path}: option {k!r} must be a value or a list, not a table")
    return data


def check_product(given: dict) -> int:
    """The number of scenes of ``given`` ({option: values}), InputError above MAX_SCENES."""
    n = 1
    for v in given.values():
        n *= len(v)
    if n > MAX_SCENES:
        sizes = " x ".join(f"{len(v)} (--{_flag(k)})" for k, v in given.items() if len(v) > 1)
        raise InputError(f"the sweep has {sizes} = {n:.4g} scenes: at most {MAX_SCENES} (split it "
                         f"into several sweeps sharing --out)")
    return n


def scenes(options: dict) -> list[dict]:
    """The Cartesian product of the options' values, defaults filled in: a list of parameter
    dicts (plain Python values) in ``OPTIONS`` order, the first given option varying slowest."""
    unknown = [k for k in options if k not in OPTIONS]
    if unknown:
        raise InputError(f"unknown option {unknown[0]!r} (accepted: {', '.join(OPTIONS)})")
    given = {k: parse_values(k, v) for k, v in options.items() if v is not None}
    _table.check_needs(given)  # --prony needs --speed, as on solve's command line
    check_product(given)  # issue 24: before enumerating
    names = list(given)
    rows = []
    for combo in itertools.product(*(given[n] for n in names)):
        p = defaults()
        p.update(zip(names, combo))
        rows.append(_fill({k: p[k] for k in OPTIONS}))
    return rows


def plan(spec=None, **options) -> list[dict]:
    """The scenes of a sweep (spec file or dict, then ``options`` over it), checked."""
    merged = {}
    if spec is not None:
        merged.update(read_spec(spec) if isinstance(spec, (str, os.PathLike)) else dict(spec))
    merged.update({k: v for k, v in options.items() if v is not None})
    return scenes(merged)


def package_version() -> str:
    from .._version import __version__

    return __version__


def scene_key(params: dict, version: str | None = None) -> str:
    """The store key of a scene: sha256 of its sorted parameters and the package version."""
    text = json.dumps({"params": params, "version": version or package_version()}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


# --- the table's columns ------------------------------------------------------------------------
CHOSEN = ("model", "method", "grid_points", "domain_length")
"""Options the solver may choose when the request leaves them empty (or says "auto"): the table
has the request (``model``, ``grid_points``, ...) and what was used (``solved_model``,
``solved_grid_points``, ...)."""
_PER_AXIS = {"grid_points": "grid_points_y", "domain_length_m": "domain_length_y_m"}
"""Surface summaries give [x, y] pairs: the table has x under the name, y under the ``_y``
name (empty for a line), so that every column holds one number."""


def column(name: str) -> str:
    """The table column of option ``name``: the JSON key of ``solve`` with its unit
    (``load`` -> ``load_N_per_m``), or the name itself (``mu``, ``tol``)."""
    return _table.option(name).json or name


def option_of(text: str) -> str | None:
    """The option named by ``text``: an option name (``load``, ``radius-x``) or its column
    (``load_N_per_m``); None if neither."""
    name = text.replace("-", "_")
    if name in OPTIONS:
        return name
    return next((k for k in OPTIONS if column(k) == name), None)


def _summary_keys() -> list[str]:
    """Every JSON key of ``solve``'s summaries, line then 3D, in order."""
    from ..result import JSON_KEYS, JSON_KEYS_3D

    keys = list(JSON_KEYS)
    keys += [k for k in JSON_KEYS_3D if k not in keys]
    keys += ["length_m", "radius_x_m", "radius_y_m", "auto_reason", "speed_m_per_s",
             "prony_terms", "deformation_friction"]
    return list(dict.fromkeys(keys))


def _result_columns() -> list[str]:
    """The result columns: the summary keys an option's column does not already hold, with
    ``solved_`` before those the solver chooses, and their ``_y`` halves."""
    given = {column(k) for k in OPTIONS}
    chosen = {column(k) for k in CHOSEN}
    out = []
    for k in _summary_keys():
        if k in chosen:
            out.append(f"solved_{k}")
            if k in _PER_AXIS:
                out.append(f"solved_{_PER_AXIS[k]}")
        elif k not in given:
            out.append(k)
    return out


def table_columns() -> list[str]:
    """The table's columns, in order."""
    return ["key", *(column(k) for k in OPTIONS), "status", "message", *_result_columns()]


def row_of(key: str, params: dict, status: str, message: str, summary: dict) -> dict:
    """A table row: the options under their columns (an option left empty that the solve reports
    -- a paraboloid's radius_x -- holds the value used), the status, the summary's values."""
    row = {"key": key}
    chosen = {column(k) for k in CHOSEN}
    for k in OPTIONS:
        c = column(k)
        v = params[k]
        row[c] = summary.get(c) if v is None and c not in chosen else v
    row["status"], row["message"] = status, message
    for c in _result_columns():
        name = c[len("solved_"):] if c.startswith("solved_") else c
        base = next((b for b, y in _PER_AXIS.items() if y == name), None)
        v = summary.get(base if base else name)
        if isinstance(v, (list, tuple)) and name in _PER_AXIS:
            v = v[0]
        elif base is not None:
            v = v[1] if isinstance(v, (list, tuple)) else None
        row[c] = v
    return row
