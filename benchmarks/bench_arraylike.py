"""The public entry points per call with inputs that are not float64 C arrays.

    python benchmarks/bench_arraylike.py BEFORE_PYTHON AFTER_PYTHON [--rounds R] [--only PREFIX]
        [--differ CASE]

runs this file as a worker under two interpreters (lemke before and after a change) in
alternating processes, each round timing every case in one process, and prints a Markdown
table of the minima and medians over rounds of each case's per-call time (us) and their
ratios after / before.  Forms: float64 C arrays, lists of floats, lists of ints, float32 arrays,
Fortran-ordered float64 matrices (vectors plain).  Cases: ``solve_lcp`` (n = 2 and 10, cold
by the tableau and the unrevised method, warm from its own basis), ``solve_blcp`` (n = 4,
cold; also scalar bounds), ``solve_bimatrix`` (3 x 2), ``solve_qp`` (3 variables, G, h, A,
b, bounds; also scalar bounds), ``solve_lcp_many`` (2 problems, and 400 of 1-6 rows, one worker),
``solve_blcp_many`` (400 box islands of 1-6 rows, bounds per island or scalar, one worker).  Every form
must give the float64 call's answer bit for bit, and both interpreters the same (checked;
``--differ CASE``: a case whose answers the change is known to change, named under the table
instead: ``solve_qp n=3 scalar bounds`` against a lemke before branch qpfront, where scalar
bounds took the KKT-MLCP path, not the float64 arrays' fused one).  ``--only PREFIX``: the
cases whose names start with it.
"""
import hashlib
import json
import statistics
import subprocess
import sys

import numpy as np

from bench_blcp_front import per_call  # (seconds a call: the median of 5 timed loops)

FORMS = ("float64", "list", "int list", "float32", "fortran")


def _lcp(n, seed=1):
    rng = np.random.default_rng(seed)
    A = rng.integers(-3, 4, (n, n))
    return (A @ A.T + np.eye(n, dtype=np.int64)).astype(float), rng.integers(-9, 9, n).astype(float)


def form(a, name):
    if name == "float64":
        return a
    if name == "list":
        return a.tolist()
    if name == "int list":
        return a.astype(np.int64).tolist()
    if name == "float32":
        return a.astype(np.float32)
    return np.asfortranarray(a) if a.ndim == 2 else a.copy()


def cases(lemke):
    """(name, function of a form name -> a call)."""
    out = []
    for n in (2, 10):
        M, q = _lcp(n)
        for method in ("tableau", "unrevised"):
            out.append((f"solve_lcp n={n} {method}", lambda f, M=M, q=q, m=method: (
                lambda Mf=form(M, f), qf=form(q, f): lemke.solve_lcp(Mf, qf, method=m))))
        ws = lemke.solve_lcp(M, q).warm_start
        out.append((f"solve_lcp n={n} warm", lambda f, M=M, q=q, ws=ws: (
            lambda Mf=form(M, f), qf=form(q, f): lemke.solve_lcp(Mf, qf, warm_start=ws))))
    M, q = _lcp(4, 3)
    lo, hi = -np.ones(4), np.full(4, 2.0)
    out.append(("solve_blcp n=4", lambda f: (
        lambda a=[form(x, f) for x in (M, q, lo, hi)]: lemke.solve_blcp(*a))))
    out.append(("solve_blcp n=4 scalar bounds", lambda f: (
        lambda a=[form(x, f) for x in (M, q)]: lemke.solve_blcp(*a, -1.0, 2.0))))
    A = np.array([[3.0, 3.0], [2.0, 5.0], [0.0, 6.0]])
    B = np.array([[3.0, 2.0], [2.0, 6.0], [3.0, 1.0]])
    out.append(("solve_bimatrix 3x2", lambda f: (
        lambda a=form(A, f), b=form(B, f): lemke.solve_bimatrix(a, b))))
    qp = (np.array([[4.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 3.0]]), np.array([1.0, 1.0, -2.0]),
          np.array([[1.0, 1.0, 1.0], [-1.0, 0.0, 2.0]]), np.array([1.0, 2.0]),
          np.array([[1.0, -1.0, 0.0]]), np.array([0.0]), np.full(3, -2.0), np.full(3, 2.0))
    out.append(("solve_qp n=3", lambda f: (
        lambda a=[form(x, f) for x in qp]: lemke.solve_qp(*a))))
    out.append(("solve_qp n=3 scalar bounds", lambda f: (
        lambda a=[form(x, f) for x in qp[:6]]: lemke.solve_qp(*a, -2.0, 2.0))))
    for B_ in (2, 400):
        probs = [_lcp(1 + b % 6, b) for b in range(B_)]
        out.append((f"solve_lcp_many B={B_}", lambda f, probs=probs: (
            lambda Ms=[form(p[0], f) for p in probs], qs=[form(p[1], f) for p in probs]:
            lemke.solve_lcp_many(Ms, qs, workers=1))))
    probs = [_lcp(1 + b % 6, b) for b in range(400)]
    isl = [(M, q, -np.ones(len(q)), np.full(len(q), 2.0)) for M, q in probs]
    out.append(("solve_blcp_many B=400", lambda f: (
        lambda a=[[form(i[k], f) for i in isl] for k in range(4)]: lemke.solve_blcp_many(*a, workers=1))))
    out.append(("solve_blcp_many B=400 scalar bounds", lambda f: (
        lambda a=[[form(i[k], f) for i in isl] for k in range(2)]: lemke.solve_blcp_many(*a, -1.0, 2.0, workers=1))))
    return out


def digest(r):
    h = hashlib.sha256()
    items = list(r) if hasattr(r, "offsets") else [r]
    for it in items:
        h.update(repr(it._keys()).encode())
    return h.hexdigest()[:16]


def worker():
    import lemke
    out = {}
    only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else ""
    for name, make in [c for c in cases(lemke) if c[0].startswith(only)]:
        want = None
        for f in FORMS:
            call = make(f)
            d = digest(call())
            want = want or d
            assert d == want, (name, f)  # every form: the float64 call's answer
            out[f"{name}|{f}"] = (per_call(call) * 1e6, d)
    print(json.dumps(out))


def main():
    before, after = sys.argv[1], sys.argv[2]
    rounds = int(sys.argv[sys.argv.index("--rounds") + 1]) if "--rounds" in sys.argv else 3
    got = {before: [], after: []}
    for _ in range(rounds):
        for py in (before, after):
            res = subprocess.run([py, __file__, "--worker", *sys.argv[3:]], capture_output=True,
                                 text=True, check=True)
            got[py].append(json.loads(res.stdout))
    keys = list(got[before][0])
    differ = {sys.argv[i + 1] for i, a in enumerate(sys.argv) if a == "--differ"}
    changed = [k for k in keys if got[before][0][k][1] != got[after][0][k][1]]
    for k in changed:
        assert k.split("|")[0] in differ, k  # the same answers
    print("| case | form | before us (min / median) | after us (min / median) | after / before (min, median) |")
    print("| --- | --- | ---: | ---: | ---: |")
    for k in keys:
        b = [r[k][0] for r in got[before]]
        a = [r[k][0] for r in got[after]]
        bm, am = statistics.median(b), statistics.median(a)
        name, f = k.split("|")
        print(f"| {name} | {f} | {min(b):.2f} / {bm:.2f} | {min(a):.2f} / {am:.2f} | "
              f"{min(a) / min(b):.2f}, {am / bm:.2f} |")
    if changed:
        print(f"\nAnswers that differ between the two (--differ): {', '.join(changed)}")


if __name__ == "__main__":
    worker() if "--worker" in sys.argv else main()
