"""User options and their scale-aware defaults.

Every tolerance here is *relative*; the solver multiplies it by a scale taken from the data,
so multiplying M and q by any positive constant gives the same pivots and the same answer.

``max_pivots`` (default ``100 * (n + 1)``)
    The cap on pivots, counting the first pivot of the artificial variable and the last one.
    Lemke's method needs at most a handful of pivots per variable on most problems; the
    default leaves room for Murty's exponential example up to n = 10 (2**n pivots).
``pivot_tol`` (default ``1e-11``)
    An entry of the driving column takes part in the ratio test only when it is below
    ``-pivot_tol * max|column|`` (in the equilibrated units); smaller entries are treated
    as rounding noise, and so are entries of the basis inverse below ``pivot_tol`` in the
    lexicographic keys.
``tie_tol`` (default ``1e-11``)
    Two keys of the lexicographic ratio rule (the ratios first, then the entries of the
    basis inverse divided by the pivot entries) are tied when they agree to within
    ``tie_tol`` relative to their own size: ``x <= m + tie_tol * max(|x|, |m|)``; never
    because both are near zero.  0 asks for exact ties.  See ``src/lemke/pivoting.hpp`` for
    the rule and why the default sits above the rounding of well-conditioned bases.
``tol`` (default ``1e-9``)
    The acceptance test of an answer, made on the caller's data: each quantity that is zero
    (or non-negative) in exact arithmetic against ``tol`` times the size of the terms it is
    formed from, plus the rounding of forming it (an LCP's point row by row, with
    ``t = tol + (n + 2) eps`` times ``r_i = |M_i.| |z| + |q_i|``).  What it means for each
    kind (LCP, MLCP, box LCP, QP, game, rays and certificates) is stated once, in
    :mod:`lemke._certify`'s docstring, the module of every check.
``time_limit`` (default None: none)
    Seconds of wall-clock time for the whole call (a batch: for all its problems).  Every
    engine looks at the clock every few tens of microseconds of work, so the limit is kept to
    within about that much (plus one pivot on a very large problem); a solve that reaches it
    ends with ``Status.TIME_LIMIT`` (distinct from ``MAX_PIVOTS``), its pivots so far and the
    unchecked point where it stopped, and tries no recovery.  In a batch, the problems not
    reached end so too, with 0 pivots.  Independently of it, Ctrl-C stops a running solve
    (``Status.INTERRUPTED`` on its way out; from the main thread, Python's
    ``KeyboardInterrupt``).
"""
from __future__ import annotations

import contextlib
import math
import numbers
from dataclasses import fields, replace
from typing import Any, Mapping

from ._frozen import frozen


@frozen
class Options:
    """Solver options; every field is optional.  See the module docstring for the defaults."""

    max_pivots: int | None = None
    pivot_tol: float = 1e-11
    tie_tol: float = 1e-11
    tol: float = 1e-9
    time_limit: float | None = None

    def __post_init__(self):
        tl = self.time_limit
        if tl is not None:
            if isinstance(tl, bool) or not isinstance(tl, numbers.Real):
                raise TypeError(f"options.time_limit must be a number of seconds or None, got {tl!r}")
            tl = float(tl)
            if not tl >= 0.0:  # (NaN too)
                raise ValueError(f"options.time_limit must be >= 0 seconds, got {tl}")
            object.__setattr__(self, "time_limit", None if math.isinf(tl) else tl)
        mp = self.max_pivots
        if mp is not None:
            if isinstance(mp, bool) or not isinstance(mp, numbers.Integral):
                raise TypeError(f"options.max_pivots must be an integer or None, got {mp!r}")
            if int(mp) < 0:
                raise ValueError(f"options.max_pivots must be >= 0, got {mp}")
            object.__setattr__(self, "max_pivots", int(mp))
        for name in ("pivot_tol", "tie_tol", "tol"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real):
                raise TypeError(f"options.{name} must be a real number, got {v!r}")
            v = float(v)
            if not (math.isfinite(v) and 0.0 <= v < 1.0):
                raise ValueError(f"options.{name} must be finite and in [0, 1), got {v}")
            object.__setattr__(self, name, v)

    def pivot_limit(self, n: int) -> int:
        """The pivot cap in force for a problem of size ``n``."""
        return 100 * (n + 1) if self.max_pivots is None else self.max_pivots


def timed(opts: Options, solve, *args, **kwargs):
    """``solve(*args, options=..., **kwargs)`` under ``opts.time_limit``: the calling thread's
    deadline (read by every engine of the core, and handed by batches to their workers)
    is tightened for the call, then restored; the call gets the options without the limit,
    so that nested fronts do not start it again."""
    with deadline(opts.time_limit):
        return solve(*args, options=replace(opts, time_limit=None), **kwargs)


@contextlib.contextmanager
def deadline(seconds: float | None):
    """The calling thread's deadline at most ``seconds`` from now (None: unchanged) while
    the block runs: every engine of the core called from this thread in it reads it."""
    if seconds is None:
        yield
        return
    from . import _core

    before = _core.tighten_deadline(seconds)
    try:
        yield
    finally:
        _core.restore_deadline(before)


def time_limited(options) -> Options | None:
    """``options`` as :class:`Options` when they set a time limit (the front then runs
    itself through :func:`timed`), else None."""
    opts = as_options(options)
    return opts if opts.time_limit is not None else None


def as_options(options: Options | Mapping[str, Any] | None) -> Options:
    """Accept ``None``, an :class:`Options` or a mapping of its field names."""
    if options is None:
        return _DEFAULT
    if isinstance(options, Options):
        return options
    if isinstance(options, Mapping):
        known = {f.name for f in fields(Options)}
        unknown = sorted(set(options) - known)
        if unknown:
            raise ValueError(
                f"unknown option(s) {', '.join(map(repr, unknown))}; known: {', '.join(sorted(known))}"
            )
        return replace(Options(), **dict(options))
    raise TypeError(f"options must be None, a lemke.Options or a dict, got {type(options).__name__}")


_DEFAULT = Options()
