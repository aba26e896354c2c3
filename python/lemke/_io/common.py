"""What the readers and writers share: the error type, size limits, atomic writing."""
from __future__ import annotations

import os
import secrets
from pathlib import Path

import numpy as np

from .._kinds import KINDS, infer
from .._problem import Problem

#: The most entries a dense matrix read from a file may have (2**26 float64: 512 MiB).  A file
#: that declares more is refused before anything is allocated.
MAX_ENTRIES = 2**26


class ProblemFormatError(ValueError):
    """A problem file could not be read: missing, unreadable, or not a valid problem.

    ``str(error)`` is one line, ``"<path>: <what is wrong>"``; the parts are ``error.path`` and
    ``error.reason``.  Every failure of :func:`lemke.read_problem` raises this type (the
    operating system's error, if any, is its ``__cause__``).
    """

    def __init__(self, path, reason: str):
        self.path = str(path)
        self.reason = " ".join(str(reason).split()) or "invalid file"  # always one line
        super().__init__(f"{self.path}: {self.reason}")


class BadFile(Exception):
    """Raised by a reader with what is wrong; read_problem adds the file's name."""


def check_size(rows: int, cols: int, what: str) -> None:
    """Refuse declared sizes that are negative or too large for a dense matrix."""
    if rows < 0 or cols < 0:
        raise BadFile(f"{what} has a negative size {rows} x {cols}")
    if rows * cols > MAX_ENTRIES:
        raise BadFile(f"{what} is {rows} x {cols}, too large for a dense solver (limit {MAX_ENTRIES} entries)")


def infer_kind(keys) -> str:
    """The kind of problem from the names of the arrays present."""
    keys = set(keys)
    kind = infer(keys)
    if kind is not None:
        return kind.name
    known = ", ".join("/".join(k.fields[:2]) for k in KINDS.values())
    raise BadFile(f"cannot tell the kind of problem: no 'kind' and none of the arrays {known}; found: "
                  f"{', '.join(sorted(map(str, keys))) or 'nothing'}")


def finite_or_none(lower: np.ndarray | None, upper: np.ndarray | None):
    """Bounds as read, with an all-infinite side given as None (no bound)."""
    if lower is not None and np.all(lower == -np.inf):
        lower = None
    if upper is not None and np.all(upper == np.inf):
        upper = None
    return lower, upper


def same_file(a, b) -> bool:
    """Whether two paths name the same existing file (or the same path)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return Path(os.path.abspath(a)) == Path(os.path.abspath(b))


def atomic_write(path, write) -> None:
    """Call ``write(binary_file)`` on a new file in ``path``'s directory, then move it over
    ``path`` in one step (``os.replace``): readers see the old file or the whole new one, never
    a part.  The new file gets the usual permissions (0o666 less the umask)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(6)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
    try:
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def make_problem(kind, arrays, path, what: str, *, name: str = "", source: str = "",
                 objective_constant: float = 0.0):
    """The Problem read from ``path`` (a ``what`` file); the name defaults to the file's stem
    and the source to the file."""
    return Problem(kind, arrays, name=name or Path(path).stem, source=source or f"{what} file {path}",
                   objective_constant=objective_constant)
