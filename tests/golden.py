"""Reference answers on the peer data, to show that a restructuring changed no bit.

``python tests/golden.py`` (from the repository root) solves every problem below with the
installed ``lemke`` and writes ``tests/data/golden.json``: per problem and method the status,
the pivots and the answer's arrays (floats written with ``repr``, so they read back exactly),
with the versions of numpy and scipy that produced them and the CPU they ran on (one record
per such platform; writing replaces this platform's).
``test_golden.py`` solves them again and asserts the same bits when a record is of this
platform (the kernels are deterministic; numpy's LAPACK, used by the MLCP and QP fronts,
may round differently in another version, and a CPU with wider vectors splits a
vectorized sum differently), and otherwise agreement to 1e-8 with the newest record, with
the same status (and the same pivots for the LCPs).

Regenerate only for a change that is *meant* to change answers, and say so in the commit
and in ``tests/GOLDEN-CHANGES.md`` (which records, what changed, why).
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
DATA = HERE / "data"
OUT = DATA / "golden.json"
METHODS = ("tableau", "unrevised")


def versions() -> dict:
    """What the bits depend on: numpy and scipy (the test data's random generators and
    matrix products, LAPACK in the MLCP and QP fronts), and the CPU (its name and a digest of
    the features numpy finds: BLAS and numpy's own loops split a vectorized sum differently
    with wider vector registers, and the core's kernels are compiled for several ISAs that
    must agree)."""
    import hashlib
    import platform

    import scipy

    try:
        from numpy._core._multiarray_umath import __cpu_features__ as features
    except ImportError:  # numpy < 2
        from numpy.core._multiarray_umath import __cpu_features__ as features
    name = platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                name = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    found = ",".join(sorted(k for k, v in features.items() if v))
    return {"numpy": np.__version__, "scipy": scipy.__version__,
            "cpu": f"{name} {hashlib.sha256(found.encode()).hexdigest()[:12]}"}


def records() -> list:
    """The recorded answers, one record per platform (``versions()``) they were made on."""
    data = json.loads(OUT.read_text())
    return data["records"] if "records" in data else [data]


def lcp_cases():
    """``(name, M, q)`` for the LCPs: Drake's and DART's cases, Siconos' .dat files, the
    built-in problems and seeded random families."""
    import lemke
    from lemke import problems

    for case in json.loads((DATA / "drake" / "cases.json").read_text()):
        n = case["n"]
        yield f"drake/{case['name']}", np.array(case["M"], float).reshape(n, n), np.array(case["q"], float)
    for case in json.loads((DATA / "dart" / "lemke_cases.json").read_text()):
        n = case["n"]
        yield f"dart/{case['name']}", np.array(case["M"], float).reshape(n, n), np.array(case["q"], float)
    for path in sorted((DATA / "siconos" / "lcp").glob("*.dat")):
        p = lemke.read_problem(path)
        yield f"siconos/{path.stem}", np.array(p.M), np.array(p.q)
    for name in ("cps_447", "murty", "degenerate", "contact_box"):
        p = getattr(problems, name)()
        yield f"builtin/{name}", np.array(p.M), np.array(p.q)
    for n in (5, 20, 60):
        rng = np.random.default_rng([7, n])
        M, q = problems.random_psd(n, rng)
        yield f"psd/{n}", M, q
        M, q = problems.contact_like(n, rng)
        yield f"contact/{n}", M, q


def mlcp_cases():
    import lemke

    for path in sorted((DATA / "siconos" / "mlcp").glob("*.dat")):
        p = lemke.read_problem(path)
        yield f"siconos/{path.stem}", [np.array(a) for a in p.arrays_in_order()]


def qp_cases():
    """``(name, args)`` for the QPs: the small Maros-Meszaros files, the built-in HS21 and
    seeded random convex QPs (full rank and rank-deficient)."""
    import lemke
    from lemke import problems

    for path in sorted((DATA / "maros-meszaros").glob("*.mat")):
        p = lemke.read_problem(path)
        if p.q.size <= 100:
            yield f"mm/{path.stem}", [None if a is None else np.array(a) for a in p.arrays_in_order()]
    p = problems.hs21()
    yield "builtin/hs21", [None if a is None else np.array(a) for a in p.arrays_in_order()]
    for n, rank in ((5, None), (20, None), (20, 10)):
        yield f"random/{n}/{rank}", list(problems.random_convex_qp(n, np.random.default_rng([11, n]), rank=rank))


def _floats(a) -> list:
    return [repr(float(x)) for x in np.ravel(a)]


def solve_all() -> dict:
    """Every problem solved by every method: ``{key: {status, pivots, arrays}}``."""
    import lemke

    out = {}
    for name, M, q in lcp_cases():
        for method in METHODS:
            r = lemke.solve_lcp(M, q, method=method)
            out[f"lcp/{name}/{method}"] = {"status": int(r.status), "pivots": r.pivots,
                                           "z": _floats(r.z), "w": _floats(r.w)}
    for name, args in mlcp_cases():
        for method in METHODS:
            r = lemke.solve_mlcp(*args, method=method)
            out[f"mlcp/{name}/{method}"] = {"status": int(r.status), "pivots": r.pivots,
                                            "u": _floats(r.u), "v": _floats(r.v)}
    for name, args in qp_cases():
        for method in METHODS:
            r = lemke.solve_qp(*args, method=method)
            out[f"qp/{name}/{method}"] = {"status": int(r.status), "pivots": r.pivots,
                                          "x": _floats(r.x), "y": _floats(r.y), "z": _floats(r.z)}
    # a batch (its own kernel loop) of the random LCPs of one size
    rng = np.random.default_rng(3)
    M, _ = lemke.problems.random_psd(12, rng)
    Q = rng.standard_normal((6, 12))
    b = lemke.solve_lcp_batch(M, Q, workers=1)
    out["batch/psd12"] = {"status": b.status.tolist(), "pivots": b.pivots.tolist(), "z": _floats(b.z)}
    return out


if __name__ == "__main__":
    sys.path.insert(0, str(HERE.parent))
    import lemke.problems  # noqa: F401

    # This platform's record replaces its old one; the other platforms' records stay while
    # they answer the same problems (their bits are checked when the tests run there).
    now = {"versions": versions(), "results": solve_all()}
    kept = [r for r in (records() if OUT.exists() else [])
            if r["versions"] != now["versions"] and sorted(r["results"]) == sorted(now["results"])]
    OUT.write_text(json.dumps({"records": kept + [now]}, indent=0) + "\n")
    print(f"wrote {OUT}: {len(kept) + 1} record(s)")
