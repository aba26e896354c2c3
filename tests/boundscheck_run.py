"""Run the degenerate families under numba's bounds checking (run by test_boundscheck.py).

Meant to be started with ``NUMBA_BOUNDSCHECK=1`` and a fresh, empty ``NUMBA_CACHE_DIR``:
every kernel is then compiled here with bounds checks, and an out-of-range index raises
IndexError instead of reading or writing memory that is not the array's.  The statuses do
not matter here (test_cycling.py checks them); every solve runs, and each exception is
reported with the problem that raised it.  The last line of stdout is a JSON summary
(``errors``, ``solves``, ``boundscheck_probe``, ``dispatchers``: the compile statistics of
every lemke kernel, so that the caller can check that nothing came from a cache).  Exit
status 1 when a solve raised.
"""
import contextlib
import importlib
import io
import json
import os
import pkgutil
import sys
import time
import traceback
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import lemke  # noqa: E402
import lemke.kernels  # noqa: E402
import stress_cases  # noqa: E402
from lemke import problems  # noqa: E402

errors = []
solves = 0


def attempt(label, fn):
    global solves
    solves += 1
    try:
        fn()
    except Exception as e:  # every exception is a finding; go on with the next
        errors.append({"case": label, "error": repr(e), "traceback": traceback.format_exc()[-1500:]})


def lcp(label, M, q, **kw):
    # Writable copies: a read-only array is another type to numba, and would compile every
    # kernel a second time.
    M, q = np.array(M), np.array(q)
    for method in lemke.METHODS:
        attempt(f"{label} [{method}] {kw.get('options') or ''}",
                lambda method=method: lemke.solve_lcp(M, q, method=method, **kw))


def _relabel_or_value_error(ws, old, new):
    """relabel; the ValueError of a duplicated label is its answer, not a finding."""
    try:
        ws.relabel(old, new)
    except ValueError as e:
        assert "holds a label twice" in str(e)


def probe():
    """Whether numba's bounds checking is in force in this process (a throw-away kernel
    indexing past the end of an array must raise IndexError)."""
    from numba import njit

    @njit
    def past_the_end(a):
        return a[a.shape[0] + 3]

    try:
        past_the_end(np.zeros(2))
    except IndexError:
        return True
    return False


def cli_stderr():
    """What ``lemke solve`` writes on stderr: on this empty cache, the notice that it compiles."""
    from lemke import _cli

    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        attempt("lemke solve", lambda: _cli.main(["solve"]))
    return err.getvalue()


def main():
    t0 = time.perf_counter()
    on = probe()
    said = cli_stderr()
    dart = {c.name: tuple(map(np.array, stress_cases.problem(c.key)))
            for c in stress_cases.BASE_CASES if c.family == "dart"}
    M12, q12 = dart["Lemke_12D"]
    for t in (0.0, 1e-14, 1e-11, 1e-6):
        lcp("dart/Lemke_12D", M12, q12, options={"tie_tol": t})
    for name, (M, q) in dart.items():
        lcp(f"dart/{name}", M, q)
    murty = stress_cases.BY_KEY[f"murty/murty-{stress_cases.MURTY_N}"]
    lcp(murty.key, *stress_cases.problem(murty.key), options=dict(murty.options))
    for c in stress_cases.BASE_CASES:
        if c.family == "siconos":
            lcp(c.key, *stress_cases.problem(c.key))
    for key in ("int/n5-s0", "int/n9-s1", "int/n12-s2", "int-p/n7-s0", "int-p/n12-s3"):
        lcp(key, *stress_cases.problem(key))
    # A short scene of the contact simulation (its own solves run bounds-checked too).
    steps = []
    attempt("contact_sim.step_lcps(3, 12, 30)", lambda: steps.extend(
        stress_cases.contact_sim.step_lcps(3, 12, 30)))
    for k in range(10, len(steps), 4):
        lcp(f"contact seed 3 step {k}", *steps[k])
    # relabel's kernel (hash tables) on empty, disjoint, equal and duplicated id arrays
    ws5 = lemke.WarmStart(5, (0, 3, 4))
    for old, new in (([], []), ([1, 2, 3, 4, 5], []), ([1, 2, 3, 4, 5], [5, 4, 9, 1]),
                     ([1, 2, 3, 4, 5], [7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23]),
                     ([1, 2, 3, 4, 1], [1]), ([1, 2, 3, 4, 5], [6, 6])):
        w = ws5 if len(old) == 5 else lemke.WarmStart(0, ())
        attempt(f"relabel({old}, {new})", lambda w=w, old=old, new=new: _relabel_or_value_error(
            w, np.array(old, dtype=np.int64), np.array(new, dtype=np.int64)))
    # refined_solve: the LU kept for the refinement (pivots in pairs: odd and even sizes)
    for k in (0, 1, 2, 3, 5, 8):
        H = np.vander(np.linspace(1.0, 2.0, k), k) + np.eye(k)
        attempt(f"refined_solve (k = {k})", lambda H=H, k=k: lemke.kernels.linalg.refined_solve(
            H, np.ones(k), 2, np.empty(k), np.empty(k)))
    Kg = np.hstack([np.eye(3) + 0.5, np.ones((3, 2))])  # two given unknowns
    attempt("refined_solve (3 + 2 given)", lambda: lemke.kernels.linalg.refined_solve(
        Kg, np.ones(3), 2, np.array([0.0, 0.0, 0.0, 1.0, 2.0]), np.empty(3)))
    # Extreme options on DART 12D (crashes in the options sweep of test_cycling.py).
    for t, p, mp in ((0.0, 0.0, None), (0.0, 0.0, 2), (0.0, 1e-300, None), (5e-324, 0.0, 1), (0.5, 0.5, 0)):
        lcp("dart/Lemke_12D", M12, q12, options={"tie_tol": t, "pivot_tol": p, "max_pivots": mp})
    # The other entry points, one small problem each.
    for method in lemke.METHODS:
        qs = np.stack([q12, q12[::-1], np.abs(q12)])
        attempt(f"solve_lcp_batch(Lemke_12D) [{method}]", lambda m=method: lemke.solve_lcp_batch(M12, qs, method=m))
        M4, q4 = dart["Lemke_4D"]  # its basis does not solve the reversed q: a restart from it
        attempt(f"warm start restart (Lemke_4D) [{method}]", lambda m=method: lemke.solve_lcp(
            M4, q4[::-1].copy(), method=m, warm_start=lemke.solve_lcp(M4, q4, method=m).warm_start))
        attempt(f"solve_mlcp (2 x 2) [{method}]", lambda m=method: lemke.solve_mlcp(
            [[2.0]], [[1.0]], [[1.0]], [[-1.0]], [-1.0], [-1.0], method=m))
        hs21 = problems.hs21()
        attempt(f"solve_qp (hs21) [{method}]", lambda m=method: lemke.solve_qp(
            hs21.P, hs21.q, hs21.G, hs21.h, lb=hs21.lb, ub=hs21.ub, method=m))

    # Box LCPs (bounded kernel, friction index) and games (Lemke-Howson, tracing, exact).
    Mr, qr = np.array(M12), np.array(q12)
    n = len(qr)
    attempt("solve_blcp(Lemke_12D, -1 <= z <= 1)", lambda: lemke.solve_blcp(Mr, qr, -np.ones(n), np.ones(n)))
    attempt("solve_blcp(Lemke_12D, mixed infinite bounds)", lambda: lemke.solve_blcp(
        Mr, qr, np.where(np.arange(n) % 3 == 0, -np.inf, 0.0), np.where(np.arange(n) % 2 == 0, np.inf, 2.0)))
    for key in ("int/n9-s1", "int/n12-s2"):
        Mi, qi = map(np.array, stress_cases.problem(key))
        k = len(qi)
        attempt(f"solve_blcp({key}, box)", lambda Mi=Mi, qi=qi, k=k: lemke.solve_blcp(
            Mi, qi, -np.ones(k), np.ones(k)))
    A = np.array([[2.0, 0.5, -0.3], [0.5, 1.0, 0.2], [-0.3, 0.2, 1.5]])
    for qf in ([-1.0, 0.5, -0.3], [-1.0, 3.0, -2.0], [1.0, 0.5, 0.0]):  # stick, slide, no contact
        attempt(f"solve_blcp(friction, findex, q={qf})", lambda qf=qf: lemke.solve_blcp(
            A, np.array(qf), [0.0, -0.5, -0.5], [np.inf, 0.5, 0.5], findex=[-1, 0, 0]))
    rng = np.random.default_rng(0)
    for label, A, B in (("int3 12x12", rng.integers(0, 3, (12, 12)), rng.integers(0, 3, (12, 12))),
                        ("unif 7x9", rng.random((7, 9)), rng.random((7, 9)))):
        A, B = A.astype(float), B.astype(float)
        for lab in (0, 3):
            attempt(f"solve_bimatrix({label}, label {lab})", lambda A=A, B=B, lab=lab: lemke.solve_bimatrix(
                A, B, init_label=lab))
        attempt(f"solve_bimatrix({label}, tracing)", lambda A=A, B=B: lemke.solve_bimatrix(A, B, method="tracing"))
        attempt(f"solve_bimatrix({label}, exact)", lambda A=A, B=B: lemke.solve_bimatrix(A, B, exact=True))
        attempt(f"lemke_paths({label})", lambda A=A, B=B: lemke.lemke_paths(A, B))

    # Compile statistics of every lemke kernel that was used.
    dispatchers = {}
    for info in pkgutil.iter_modules(lemke.kernels.__path__):
        mod = importlib.import_module(f"lemke.kernels.{info.name}")
        for name, obj in vars(mod).items():
            stats = getattr(obj, "stats", None)
            if getattr(obj, "signatures", None) and stats is not None and hasattr(stats, "cache_hits"):
                dispatchers[f"{info.name}.{name}"] = {
                    "cache_path": str(stats.cache_path), "hits": sum(stats.cache_hits.values()),
                    "misses": sum(stats.cache_misses.values())}
    summary = {"errors": errors, "solves": solves, "boundscheck_probe": on, "dispatchers": dispatchers,
               "kernels_dir": str(Path(lemke.kernels.__file__).parent), "seconds": time.perf_counter() - t0,
               "cache_dir": os.environ.get("NUMBA_CACHE_DIR", ""), "cli_stderr": said}
    print(json.dumps(summary))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
