"""A separate process that runs lemke for the stress suite, so that a crash of a kernel
(a segmentation fault on a degenerate problem) fails the case that caused it instead of
ending the test session.

The parent (:class:`Solver`) sends requests over the child's stdin and reads answers from
its stdout, each a pickle preceded by its length (8 bytes, little-endian).  Requests:

* ``("problem", key)``: ``(M, q)`` of a case of stress_cases (for the cases built with
  lemke's answers, which the parent does not build itself);
* ``("contact", seed, bodies, steps, boxes)``: ``contact_sim.step_lcps(...)``;
* ``("solve", key, method, options)``: solve case ``key``;
* ``("solve_data", M, q, method, options)``: solve the given problem.

A result is an :class:`Outcome`, plain data.  When the child dies (or takes longer than
``timeout`` for one request), the request gets an Outcome with ``status=None`` and a
message naming the signal and the end of the child's stderr (with faulthandler's
traceback), and the next request starts a new child.
"""
from __future__ import annotations

import os
import pickle
import select
import signal
import struct
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent


@dataclass(frozen=True)
class Outcome:
    """What the tests need of an LCPResult; ``status`` is a lemke.Status, or None when the
    solver process crashed or hung."""

    status: object
    pivots: int
    residual: float
    message: str
    z: object = None
    w: object = None
    z0: float = 0.0
    ray: object = None
    covering: object = None
    z_basic: tuple = ()

    def short(self):
        return "CRASH" if self.status is None else f"{self.status.name} after {self.pivots} pivots"

    def describe(self):
        if self.status is None:
            return self.message
        return f"{self.status.name} after {self.pivots} pivots (residual {self.residual:.3g}): {self.message}"


def outcome(res) -> Outcome:
    return Outcome(res.status, int(res.pivots), float(res.residual), res.status.message, res.z.copy(),
                   res.w.copy(), float(res.z0), None if res.ray is None else res.ray.copy(),
                   res.covering.copy(), tuple(res.warm_start.z_basic))


def _send(stream, obj):
    data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    stream.write(struct.pack("<Q", len(data)))
    stream.write(data)
    stream.flush()


def _read_exact(fd, k):
    chunks = []
    while k:
        b = os.read(fd, min(k, 1 << 20))
        if not b:
            raise EOFError
        chunks.append(b)
        k -= len(b)
    return b"".join(chunks)


class Solver:
    """The parent's side: one child at a time, restarted after a crash."""

    def __init__(self, timeout=300.0):
        self.timeout = timeout
        self.proc = None
        self.crashes = 0

    def _start(self):
        self.log = tempfile.TemporaryFile()
        env = dict(os.environ)
        env["PYTHONFAULTHANDLER"] = "1"
        self.proc = subprocess.Popen([sys.executable, str(Path(__file__).resolve())], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=self.log, env=env, cwd=str(HERE))

    def close(self):
        if self.proc is not None:
            try:
                self.proc.stdin.close()
                self.proc.wait(timeout=30)
            except Exception:
                self.proc.kill()
                self.proc.wait()
            self.proc = None

    def _fail(self, why):
        self.proc.kill()
        rc = self.proc.wait()
        self.log.seek(0)
        tail = self.log.read().decode(errors="replace")[-3000:]
        self.proc = None
        self.crashes += 1
        if rc < 0:
            why = f"{why}: the solver process died of {signal.Signals(-rc).name}"
        return why + ("\n" + tail if tail else "")

    def request(self, *req):
        if self.proc is None:
            self._start()
        try:
            _send(self.proc.stdin, req)
            fd = self.proc.stdout.fileno()
            ready, _, _ = select.select([fd], [], [], self.timeout)
            if not ready:
                return None, self._fail(f"no answer within {self.timeout} s (hung), request {req[:1] + req[2:4]}")
            (size,) = struct.unpack("<Q", _read_exact(fd, 8))
            kind, value = pickle.loads(_read_exact(fd, size))
        except (EOFError, BrokenPipeError):
            self.proc.poll()
            return None, self._fail("CRASH")
        if kind == "error":
            raise RuntimeError(f"the solver process raised: {value}")
        return value, None

    def problem(self, key):
        value, crash = self.request("problem", key)
        if crash:
            raise RuntimeError(f"building {key} crashed the solver process: {crash}")
        return value

    def contact(self, seed, bodies, steps, boxes=True):
        """``contact_sim.step_lcps(seed, bodies, steps, boxes)``, run in the solver process."""
        value, crash = self.request("contact", seed, bodies, steps, boxes)
        if crash:
            raise RuntimeError(f"the contact simulation crashed the solver process: {crash}")
        return value

    def _solve(self, *req):
        value, crash = self.request(*req)
        return value if crash is None else Outcome(None, -1, float("nan"), crash)

    def solve(self, key, method, options=()):
        return self._solve("solve", key, method, tuple(options))

    def solve_data(self, M, q, method, options=()):
        return self._solve("solve_data", M, q, method, tuple(options))


def main():
    import faulthandler
    import traceback

    faulthandler.enable()
    out = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)  # stray prints must not corrupt the answers
    import lemke
    import stress_cases

    inp = sys.stdin.buffer
    while True:
        head = inp.read(8)
        if len(head) < 8:
            return
        (size,) = struct.unpack("<Q", head)
        req = pickle.loads(inp.read(size))
        try:
            if req[0] == "problem":
                answer = stress_cases.problem(req[1])
            elif req[0] == "contact":
                import contact_sim

                answer = contact_sim.step_lcps(req[1], req[2], req[3], req[4])
            elif req[0] == "solve":
                _, key, method, options = req
                M, q = stress_cases.problem(key)
                answer = outcome(lemke.solve_lcp(M, q, method=method, options=dict(options) or None))
            else:
                _, M, q, method, options = req
                answer = outcome(lemke.solve_lcp(M, q, method=method, options=dict(options) or None))
            _send(out, ("ok", answer))
        except Exception:
            _send(out, ("error", traceback.format_exc()))


if __name__ == "__main__":
    # Run as the module ``stress_worker`` (not ``__main__``), so that the Outcomes it
    # pickles are found under that name by the parent.
    sys.path.insert(0, str(HERE))
    import stress_worker

    stress_worker.main()
