"""Progress of long commands on stderr.

The solvers and instruments log their steps with the standard ``logging`` module (logger names
under ``spectral_contact``, level INFO: refinement levels with their grid size, bootstrap
realisations, fit iterations); nothing is shown unless a handler is installed.  The command line
installs ``show_progress()``: silent for the first ``after`` seconds (fast commands print
nothing), then the latest step and every later one, each with the elapsed time.  In Python, use
``logging.basicConfig(level=logging.INFO)`` to see the same lines.
"""
from __future__ import annotations

import contextlib
import logging
import sys
import threading
import time

__all__ = ["show_progress"]


class _Handler(logging.Handler):
    def __init__(self, after: float, stream, skip=()):
        super().__init__(logging.INFO)
        self.t0 = time.time()
        self.stream = stream
        self.skip = tuple(skip)
        try:  # a terminal: one line rewritten in place and erased at the end (as calibrate's)
            self.tty = bool(stream.isatty())
        except (AttributeError, ValueError, OSError):
            self.tty = False
        self.dirty = False
        self.live = False
        self.pending = None
        self.timer = None
        if after != float("inf"):  # inf: never show (the command reports its own progress)
            self.timer = threading.Timer(after, self._wake)
            self.timer.daemon = True
            self.timer.start()

    def _line(self, record) -> str:
        return f"  [{record.created - self.t0:6.1f} s] {record.getMessage()}"

    def _write(self, text: str) -> None:
        try:
            self.stream.write(f"\r\x1b[K{text.strip()}" if self.tty else text + "\n")
            self.stream.flush()
            self.dirty = True
        except (OSError, ValueError):  # stderr closed: progress is not worth an error
            pass

    def _wake(self) -> None:
        with self.lock:
            self.live = True
            if self.pending is not None:
                self._write(self.pending + "  ...")
                self.pending = None

    def emit(self, record) -> None:
        if record.name.startswith(self.skip):
            return
        line = self._line(record)
        if self.live:
            self._write(line)
        else:
            self.pending = line

    def close(self) -> None:
        if self.timer is not None:
            self.timer.cancel()
        if self.tty and self.dirty:  # erase the progress line: stderr keeps its one-line promise
            try:
                self.stream.write("\r\x1b[K")
                self.stream.flush()
            except (OSError, ValueError):
                pass
        super().close()


@contextlib.contextmanager
def show_progress(after: float = 2.0, stream=None, skip=()):
    """Within the block, print the package's INFO log lines on stderr once ``after`` seconds
    have passed (``after=inf``: never); on a terminal as one line rewritten in place and erased
    at the end.  ``skip``: logger-name prefixes not shown (compare shows its fit solves, not
    each solve's refinement levels)."""
    logger = logging.getLogger("spectral_contact")
    handler = _Handler(after, stream or sys.stderr, skip)
    old_level = logger.level
    logger.addHandler(handler)
    if logger.getEffectiveLevel() > logging.INFO:
        logger.setLevel(logging.INFO)
    try:
        yield handler
    finally:
        logger.removeHandler(handler)
        logger.setLevel(old_level)
        handler.close()
