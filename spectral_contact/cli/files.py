"""Writing results: profile CSV and JSON, and all-or-nothing output files.

Every output of a command is written to a temporary file beside its target
(``Outputs.path``) and renamed into place only when all of them are complete
(``Outputs.commit``); on any error or interrupt the temporaries are removed and no target is
touched.  Paths are checked before any work (``check_outputs``): a folder that exists, not a
directory, not empty, no two outputs on the same file, a plot format matplotlib can write.
"""
from __future__ import annotations

import errno
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
           "Outputs", "meta_path", "write_meta_json", "json_ready", "plan_outputs",
           "write_outputs", "csv_file", "staged"]


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


def _identity(path):
    """What makes two paths one file: the resolved real path, and for an existing file its
    (device, inode) too (hard links, bind mounts, case-folding file systems)."""
    keys = {("path", os.path.realpath(path))}
    try:
        st = os.stat(path)
    except OSError:
        pass
    else:
        keys.add(("inode", st.st_dev, st.st_ino))
    return keys


def check_outputs(inputs=None, metas=(), **paths) -> dict:
    """Check every file a command will write, before any work (one ``InputError`` line, exit 2).

    ``paths``: {option: path or None}, the outputs as typed (``**{"--plot": "p.png"}``);
    ``metas``: the options whose CSV also gets an implicit ``.meta.json`` beside it
    (``meta_path``), checked as outputs too; ``inputs``: {option: path or None}, the files the
    command reads.  Refused: an output that is a directory, not a regular file, in a folder that
    does not exist; two outputs naming one file; an output naming an input (the same resolved
    path, or the same inode: a hard link).  Returns {option: Path} of the given outputs."""
    out = {}
    seen = {}
    for option, path in (inputs or {}).items():
        if path is None or not str(path).strip():
            continue
        for key in _identity(path):
            seen.setdefault(key, ("input", f"{option} {path}"))
    planned = []
    for option, path in paths.items():
        if path is None:
            continue
        p = check_output(path, option)
        out[option] = p
        planned.append((f"{option} {path}", p))
        if option in metas:
            m = meta_path(p)
            what = f"{option} {path}'s metadata"
            planned.append((f"{what} {m}", check_output(m, what)))
    for label, p in planned:
        keys = _identity(p)
        for key in keys:
            if key not in seen:
                continue
            kind, other = seen[key]
            if kind == "input":
                raise InputError(f"{label} would overwrite the input {other}: give another path")
            raise InputError(f"{other} and {label} are the same file: give different paths")
        for key in keys:
            seen[key] = ("output", label)
    return out


def plan_outputs(inputs=None, csvs=(), plots=(), npzs=(), **paths) -> dict:
    """The output check every command makes before any work: ``check_outputs`` (no output over
    an input or another output; ``csvs``: the options whose CSV gets an implicit ``.meta.json``)
    and, for each option of ``plots`` that is given, ``check_plot_path`` (a format matplotlib
    writes); each option of ``npzs`` given must name a ``.npz`` file (``invert`` sends files by
    that suffix to the maps' reader: an NPZ named ``maps.csv`` could not be read back).
    Returns {option: Path} of the outputs given, for ``write_outputs``."""
    outputs = check_outputs(inputs=inputs, metas=csvs, **paths)
    for option in plots:
        if paths.get(option) is not None:
            check_plot_path(paths[option], option)
    for option in npzs:
        path = paths.get(option)
        if path is not None and not str(path).lower().endswith(".npz"):
            raise InputError(f"{option} {path}: writes an NPZ archive; give a name ending in .npz")
    return outputs


def csv_file(columns, meta):
    """A writer for ``write_outputs``: the CSV ``columns`` ({name: 1D array}, or a function of
    no argument giving them) and its ``.meta.json`` holding ``meta`` (a dict, or a function of
    the columns giving it); the functions are called only when the option was given."""
    def write(outs, target):
        cols = columns() if callable(columns) else columns
        write_csv(outs.path(target), cols)
        add_meta(outs, target, meta(cols) if callable(meta) else meta)
    return write


def staged(write_to):
    """A writer for ``write_outputs``: ``write_to(path)`` writes the file (a figure, an NPZ) at
    the temporary path it is given."""
    def write(outs, target):
        write_to(outs.path(target))
    return write


def write_outputs(outputs: dict, writers: dict, stdout) -> None:
    """The one write step of a command: each writer whose option is in ``outputs`` (from
    ``plan_outputs``) writes its temporary, in the order of ``writers``; then ``stdout`` (text,
    or a function giving it) is printed and every file renamed into place -- or, on any error
    (stdout closed or full included), nothing is written (``Outputs``).

        write_outputs(outputs, {"--profiles": csv_file(cols, meta),
                                "--plot": staged(lambda p: fig.savefig(p))}, summary)
    """
    with Outputs() as outs:
        for option, write in writers.items():
            if outputs.get(option) is not None:
                write(outs, outputs[option])
        outs.print(stdout() if callable(stdout) else stdout)


COMMITTED: list[Path] = []
"""Targets renamed into place by Outputs.commit in this process (the command line clears it per
command, to say truthfully whether an interrupted command wrote anything)."""


class Outputs:
    """All-or-nothing output files, and the command's standard output with them.

        with Outputs() as outs:
            write_csv(outs.path("p.csv"), ...)
            fig.savefig(outs.path("p.png"))
            outs.print(summary)
        # here: the summary written to stdout, then every file renamed into place; or, on any
        # exception (stdout closed or full included), nothing: no target touched, no temporary left

    Temporaries are hidden files beside their targets, keeping the target's suffix (matplotlib
    picks the format from it), created with the mode a new file would get (umask).  An error
    while writing one names the user's file, never the temporary.  The renames are undone if one
    of them fails (a replaced file is kept as a hard link until all are done).
    """

    def __init__(self):
        self._pending: list[tuple[Path, Path]] = []
        self._stdout: list[str] = []

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

    def print(self, text: str) -> None:
        """Stage ``text`` (a line is added) for stdout: written at the commit, before the renames."""
        self._stdout.append(text + "\n")

    def _write_stdout(self) -> None:
        if not self._stdout:
            return
        import sys

        text, self._stdout = "".join(self._stdout), []
        if sys.stdout is None:
            raise OSError(errno.EBADF, "standard output is closed", "standard output")
        try:
            sys.stdout.write(text)
            sys.stdout.flush()
        except BrokenPipeError:
            raise
        except (OSError, ValueError) as exc:
            _silence_stdout()
            raise OSError(getattr(exc, "errno", None) or errno.EIO,
                          getattr(exc, "strerror", None) or str(exc), "standard output") from None

    def commit(self) -> None:
        """Write the staged stdout, then rename every temporary onto its target (signals held
        off meanwhile); if a rename fails, the targets already replaced are restored."""
        main = threading.current_thread() is threading.main_thread()
        sigs = {signal.SIGINT, signal.SIGTERM}
        if main:
            old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
        done, backups = [], []
        try:
            self._write_stdout()
            for tmp, target in self._pending:
                backup = None
                if os.path.lexists(target):
                    backup = target.with_name(f".{target.name}.{secrets.token_hex(4)}.bak")
                    try:
                        os.link(target, backup, follow_symlinks=False)
                    except OSError:
                        backup = None
                    backups.append(backup)
                try:
                    os.replace(tmp, target)
                except OSError as exc:
                    raise OSError(exc.errno, exc.strerror, str(target)) from None
                done.append((target, backup, os.path.lexists(target) and backup is not None))
            for target, _, _ in done:
                COMMITTED.append(target)
            self._pending = []
        except BaseException:
            for target, backup, _ in reversed(done):  # undo: the old file back, a new one removed
                try:
                    if backup is not None:
                        os.replace(backup, target)
                    else:
                        os.unlink(target)
                except OSError:
                    pass
            self._pending = [(t, g) for t, g in self._pending if os.path.lexists(t)]
            raise
        finally:
            for b in backups:
                if b is not None:
                    try:
                        os.unlink(b)
                    except OSError:
                        pass
            if main:
                signal.pthread_sigmask(signal.SIG_SETMASK, old)

    def abort(self) -> None:
        for tmp, _ in self._pending:
            try:
                os.unlink(tmp)
            except OSError:
                pass
        self._pending = []
        self._stdout = []

    def _user_error(self, exc):
        """``exc`` naming the user's file instead of a temporary (an error without a file
        name, "No space left on device", names the file being written: the last staged)."""
        if not isinstance(exc, OSError) or not self._pending:
            return None
        names = {str(tmp): target for tmp, target in self._pending}
        if exc.filename is None:
            target = self._pending[-1][1]
        elif str(exc.filename) in names:
            target = names[str(exc.filename)]
        else:
            return None
        return OSError(exc.errno, exc.strerror or str(exc), str(target))

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            try:
                self.commit()
            except BaseException:
                self.abort()
                raise
            return False
        user = self._user_error(exc)
        self.abort()
        if user is not None:
            raise user from None
        return False


def _silence_stdout() -> None:
    """stdout cannot be written (closed, full): point fd 1 at /dev/null so that the
    interpreter's final flush does not print a second error."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 1)
        os.close(devnull)
    except OSError:
        pass


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
