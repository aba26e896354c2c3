"""Progress reports of long work (:func:`lemke.lemke_paths`, :func:`lemke.solve_lcp_batch`,
:func:`lemke.solve_lcp_many`, and single solves: :func:`lemke.solve_lcp`, ``solve_blcp``,
``solve_mlcp``, ``solve_qp``, through :func:`reported`).

A ``progress`` argument is None (silent), a callable (called in the calling thread with
the counts the function documents), or ``True``: a bar on stderr drawn by ``tqdm`` when it
is installed (``pip install lemke[progress]``), else a plain counter rewritten in place on
one stderr line.  The bar is closed (and the plain line ended) when the work stops, also
on an exception or Ctrl-C.
"""
from __future__ import annotations

import sys
import time


def check(progress, name: str = "progress"):
    """``progress`` if it is None, a bool or a callable; else a TypeError naming it."""
    if progress is None or isinstance(progress, bool) or callable(progress):
        return progress
    raise TypeError(f"{name} must be None, True/False or a callable, got {type(progress).__name__}")


class Reporter:
    """What a function calls as its work goes on: ``update(*counts)`` after each step,
    ``close()`` at the end (a context manager)."""

    def __init__(self, progress, what: str, total=None, unit: str = "", describe=None):
        """``progress``: checked by :func:`check`.  ``what``: the function's name (the
        bar's label).  ``total``: the number of steps, when known; ``unit``: the steps' name.
        ``describe(*counts)``: ``(done, text)``, the steps done and a short text of the other
        counts, for the bar (default: the first count, no text)."""
        self._call = progress if callable(progress) and progress is not True else None
        self._bar = None
        self._plain = False
        self._describe = describe or (lambda done, *rest: (done, ""))
        self._what = what
        self._unit = unit
        self._total = total
        self._last = 0.0
        self._done = None  # the steps done, last reported (the plain counter)
        self._text = ""
        self._width = 0  # of the plain line last written
        if progress is True:
            try:
                from tqdm import tqdm
            except ImportError:
                self._plain = True
            else:
                self._bar = tqdm(total=total, desc=what, unit=f" {unit}s" if unit else "it",
                                 file=sys.stderr, leave=True, dynamic_ncols=True)
        self.active = self._call is not None or self._bar is not None or self._plain

    def update(self, *counts):
        if self._call is not None:
            self._call(*counts)
            return
        done, text = self._describe(*counts)
        if self._bar is not None:
            if text:
                self._bar.set_postfix_str(text, refresh=False)
            self._bar.update(done - self._bar.n)
        elif self._plain:
            self._text = text
            self._done = done
            now = time.monotonic()
            if now - self._last >= PLAIN_INTERVAL:  # at most a few writes a second
                self._last = now
                self._write()

    def _write(self):
        of = f"/{self._total}" if self._total is not None else ""
        text = f", {self._text}" if self._text else ""
        line = f"{self._what}: {self._done}{of} {self._unit}s{text}"
        sys.stderr.write("\r" + line.ljust(self._width))  # covers a longer line before it
        sys.stderr.flush()
        self._width = len(line)

    def close(self):
        if self._bar is not None:
            self._bar.close()
            self._bar = None
        elif self._plain:
            if self._done is not None:
                self._write()
                sys.stderr.write("\n")
                sys.stderr.flush()
            self._plain = False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


#: Seconds between two writes of the plain counter.
PLAIN_INTERVAL = 0.2


#: Seconds between two reports of a single solve (its engines call back at most this often).
SOLVE_EVERY = 0.1


def reported(progress, what, solve, *args, **kwargs):
    """``solve(*args, **kwargs)`` reporting as it pivots: ``progress(pivots, seconds)`` (the
    pivots of the run in progress, which a recovery run starts again from 0, and the
    seconds since the call began) about every ``SOLVE_EVERY`` seconds, in the calling
    thread, while the solve runs in a thread of its own (with the caller's deadline) and
    records its pivots in a probe that the engines update at each look; a short solve makes
    no report.  An exception of the callback (or Ctrl-C) stops the solve and is raised.
    ``progress=True``: a bar or a counter.  (The callback may itself solve with lemke: it
    runs in another thread than the solve it reports on.)"""
    import threading

    from . import _core

    probe = _core.ProgressProbe()
    deadline = _core.deadline()
    box = {}

    def work():
        probe.attach()
        _core.restore_deadline(deadline)
        try:
            box["result"] = solve(*args, **kwargs)
        except BaseException as exc:  # raised in the calling thread
            box["error"] = exc
        finally:
            probe.detach()
            _core.restore_deadline(0)

    t0 = time.perf_counter()
    with Reporter(progress, what, unit="pivot",
                  describe=lambda pivots, seconds: (pivots, f"{seconds:.1f} s")) as report:
        worker = threading.Thread(target=work, name=f"lemke-{what}", daemon=True)
        worker.start()
        try:
            while True:
                worker.join(SOLVE_EVERY)
                if not worker.is_alive():
                    break
                report.update(probe.pivots(), time.perf_counter() - t0)
        except BaseException:
            probe.stop()  # the solve ends at its next look
            worker.join()
            raise
    if "error" in box:
        raise box["error"]
    return box["result"]
