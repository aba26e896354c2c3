"""The problem tables solved through lemke's public API (run by test_sanitized.py).

test_sanitized.py starts this script in a child Python whose ``lemke`` is a copy of the
package with a ``_core`` built with AddressSanitizer, UndefinedBehaviorSanitizer and index
checks (LEMKE_SANITIZE): an out-of-range read or write, a use after free or undefined
behaviour in the C++ core then stops the child with a report on stderr.  It solves:

* the goldens' problems (``golden.solve_all()``: the LCPs by both methods, the MLCPs, the
  QPs and a batch), whose answers the test compares with tests/data/golden.json;
* the stress families of stress_cases.py that are not built with lemke's answers (DART,
  Murty, Siconos, Drake, the integer families, their scaled and permuted copies), both
  methods, and the steps of a short contact scene (tests/contact_sim.py), cold and warm;
* box LCPs: test_blcp.py's seeded family, its small integer fuzz, friction contacts with a
  friction index, the contact scenes as friction-index box LCPs, examples/box_pile.py's
  steps cold and warm, extreme values;
* games: test_games.py's known games from every label (float and exact), tracing,
  warm starts from a basis, lemke_paths on small games, random games of its families;
* warm starts and relabels: LCP restarts, take, relabel by labels and by integer ids
  (duplicates included), batches and solve_lcp_many with their warm starts;
* array-likes: lists, tuples, int / bool / float32 arrays, Fortran-ordered, reversed,
  strided and unaligned arrays, scalar box bounds, through every entry point;
* sanitized_fuzz.py's seeded adversarial inputs: malformed lists and arrays through the
  entries' conversions, the batch helpers called directly with inconsistent offsets, the
  kept-matrix table's large slot (250-300 rows, forced hash collisions) and box islands of
  varying sizes, each of the last two compared with a fresh thread's solve, and blcp_pack's
  box islands in every form (bit for bit the float64 arrays') and malformed.

The statuses are not checked here (the other tests do); every solve runs, each exception is
reported with the problem that raised it, and each answer is reduced to a fingerprint
(status, pivots and the bits of its arrays), so that the test can compare them with the
same solves by the normal build (``run()`` in the test's own process).  ``python
sanitized_run.py OUT.json`` writes the summary (``solves``, ``errors``, ``fingerprints``,
``golden``, ``golden_versions``, ``core``: the file of the ``_core`` that ran) to OUT.json and
prints a one-line count; exit status 1 when a solve raised.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import sys
import time
import traceback
from fractions import Fraction
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))
# An editable install (scikit-build-core's) finds lemke through a finder on sys.meta_path,
# ahead of PYTHONPATH: take it out, so that the sanitized copy on PYTHONPATH is imported.
sys.meta_path[:] = [f for f in sys.meta_path if "ScikitBuild" not in type(f).__name__
                    and "skbc" not in type(f).__module__]

import lemke  # noqa: E402
import sanitized_fuzz  # noqa: E402

FIELDS = ("status", "pivots", "z", "w", "u", "v", "x", "y", "z0", "ray", "lo", "hi", "payoffs", "restarts",
          "warm_start", "basis")


def _feed(h, obj, depth=0):
    if depth > 6:
        h.update(b"deep")
    elif obj is None or isinstance(obj, (bool, int, float, str, Fraction, np.generic)):
        h.update(f"{type(obj).__name__}:{obj!r};".encode())
    elif isinstance(obj, np.ndarray):
        a = np.ascontiguousarray(obj)
        h.update(f"{a.dtype}{a.shape}".encode())
        h.update(a.tobytes() if a.dtype != object else repr(a.tolist()).encode())
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        for f in dataclasses.fields(obj):
            _feed(h, getattr(obj, f.name), depth + 1)
    elif isinstance(obj, (list, tuple)):
        h.update(f"seq{len(obj)}[".encode())
        for item in obj:
            _feed(h, item, depth + 1)
        h.update(b"]")
    elif any(hasattr(obj, name) for name in ("status", "pivots")):
        for name in FIELDS:
            try:
                value = getattr(obj, name)
            except Exception:  # a field this kind of result does not have
                continue
            h.update(name.encode())
            _feed(h, value, depth + 1)
    elif hasattr(obj, "__len__") and hasattr(obj, "__getitem__"):
        _feed(h, [obj[i] for i in range(len(obj))], depth + 1)
    else:
        h.update(repr(obj).encode())


def fingerprint(obj) -> str:
    """The bits of an answer (its status, pivots and arrays; a sequence of answers item by
    item) as a short digest."""
    h = hashlib.sha256()
    _feed(h, obj)
    return h.hexdigest()[:20]


class Runner:
    def __init__(self):
        self.errors = []
        self.fingerprints = {}
        self.solves = 0

    def attempt(self, label, fn):
        """Run ``fn()``; record its answer's fingerprint, or its exception.  The answer, or
        None when it raised."""
        self.solves += 1
        key = label
        while key in self.fingerprints:
            key += "'"
        try:
            answer = fn()
            self.fingerprints[key] = fingerprint(answer)
            return answer
        except Exception as e:  # every exception is a finding; go on with the next
            self.fingerprints[key] = f"raised {type(e).__name__}"
            self.errors.append({"case": label, "error": repr(e), "traceback": traceback.format_exc()[-2000:]})
            return None

    def lcp(self, label, M, q, **kw):
        for method in lemke.METHODS:
            self.attempt(f"{label} [{method}]", lambda method=method: lemke.solve_lcp(M, q, method=method, **kw))


def _relabel(ws, old, new):
    """relabel; the ValueError of a duplicated label is its answer, not a finding."""
    try:
        return ws.relabel(old, new)
    except ValueError as e:
        if "holds a label twice" not in str(e):
            raise
        return "ValueError: holds a label twice"


def lcps(run):
    import contact_sim
    import stress_cases

    # The stress families (their keys include the scaled and permuted copies), except the
    # contact scenes, which are advanced with lemke's own answers (a short one follows).
    for c in stress_cases.CASES:
        if not c.uses_lemke:
            run.lcp(c.key, *stress_cases.problem(c.key), options=dict(c.options) or None)
    dart = {c.name: stress_cases.problem(c.key) for c in stress_cases.BASE_CASES if c.family == "dart"}
    M12, q12 = dart["Lemke_12D"]
    # Extreme options on DART 12D (crashes in the options sweep of test_cycling.py).
    for t, p, mp in ((0.0, 0.0, None), (0.0, 0.0, 2), (0.0, 1e-300, None), (5e-324, 0.0, 1), (0.5, 0.5, 0),
                     (1e-14, None, None), (1e-6, None, None)):
        opts = {"tie_tol": t, "max_pivots": mp} | ({} if p is None else {"pivot_tol": p})
        run.lcp(f"dart/Lemke_12D {opts}", M12, q12, options=opts)
    # A contact scene: each step cold, and warm from the last step's basis carried over by
    # the contacts' labels (both the general relabel and the integer-id path).
    sc = contact_sim.Scene(3, 12, True)
    ws = labels = ids = None
    for step in range(40):
        M, q, apply = contact_sim.step_lcp(sc, step)
        run.lcp(f"contact scene 3 step {step} cold", M, q)
        if ws is not None:
            run.attempt(f"contact scene 3 step {step} relabel", lambda: _relabel(ws, labels, apply.labels))
            run.attempt(f"contact scene 3 step {step} relabel ids", lambda: _relabel(ws, ids, apply.id_array))
        start = None if ws is None else ws.relabel(labels, apply.labels)
        res = run.attempt(f"contact scene 3 step {step} warm", lambda: lemke.solve_lcp(M, q, warm_start=start))
        apply(res.z if res is not None and res.success else None)
        ws, labels, ids = (None if res is None else res.warm_start), apply.labels, apply.id_array
    # Warm starts: the same basis, a stale one, restarts after small changes, a permutation.
    rng = np.random.default_rng(8)
    for n in (1, 2, 5, 30, 80):
        M, q = lemke.problems.random_p_matrix(n, rng)
        for method in lemke.METHODS:
            cold = lemke.solve_lcp(M, q, method=method)
            for k, q2 in enumerate((q + 1e-9 * np.abs(q).max(), q + 0.05 * rng.standard_normal(n),
                                    rng.standard_normal(n), -q)):
                run.attempt(f"warm p-matrix n={n} change {k} [{method}]", lambda q2=q2, m=method, c=cold: (
                    lemke.solve_lcp(M, q2, method=m, warm_start=c.warm_start)))
            perm = rng.permutation(n)
            run.attempt(f"warm permuted n={n} [{method}]", lambda m=method, c=cold, p=perm: lemke.solve_lcp(
                M[np.ix_(p, p)], q[p], method=m, warm_start=c.warm_start.take(p)))
    for method in lemke.METHODS:
        run.attempt(f"warm start on singular M_bb [{method}]", lambda m=method: lemke.solve_lcp(
            np.zeros((3, 3)), [1.0, 2.0, 0.0], method=m, warm_start=lemke.WarmStart(3, (0, 1, 2))))
    # take and relabel (the hash tables of the integer-id path) on empty, disjoint, equal,
    # duplicated and large ids, other dtypes and strided arrays.
    ws5 = lemke.WarmStart(5, (0, 3, 4))
    for old, new in (([], []), ([1, 2, 3, 4, 5], []), ([1, 2, 3, 4, 5], [5, 4, 9, 1]),
                     ([1, 2, 3, 4, 5], list(range(7, 40))), ([1, 2, 3, 4, 1], [1]), ([1, 2, 3, 4, 5], [6, 6]),
                     ([-5, 2**40, 3 * 2**20, 4 * 2**20, 7], [7, 3 * 2**20, -5])):
        w = ws5 if len(old) == 5 else lemke.WarmStart(0, ())
        for dtype in (np.int64, np.int32, np.uint64):
            info = np.iinfo(dtype)
            if not all(info.min <= v <= info.max for v in old + new):
                continue
            o = np.repeat(np.array(old, dtype=dtype), 2)[::2]
            run.attempt(f"relabel({old}, {new}) {dtype.__name__}", lambda w=w, o=o, new=new, d=dtype: _relabel(
                w, o, np.array(new, dtype=d)))
        run.attempt(f"relabel({old}, {new}) lists", lambda w=w, old=old, new=new: _relabel(w, old, new))
    for t in range(60):
        n, fresh = int(rng.integers(0, 40)), int(rng.integers(0, 6))
        idv = rng.choice(10**6, size=n + fresh, replace=False).astype(np.int64) * 4
        old, extra = rng.permutation(idv[:n]), idv[n:]
        w = lemke.WarmStart(n, tuple(sorted(rng.permutation(n)[: int(rng.integers(0, n + 1))].tolist())))
        new = rng.permutation(np.concatenate([old[rng.permutation(n)[: int(rng.integers(0, n + 1))]], extra]))
        run.attempt(f"relabel random {t}", lambda w=w, o=old, nw=new: _relabel(w, o, nw))
        run.attempt(f"take random {t}", lambda w=w, k=len(new): w.take(
            [int(i) if i < w.n else -1 for i in np.random.default_rng(t).permutation(max(w.n, k))[:k]]))
    # Batches and solve_lcp_many (one thread and several), with their warm starts.
    qs = np.stack([q12, q12[::-1], np.abs(q12), -np.abs(q12)])
    for method in lemke.METHODS:
        for workers in (1, 2):
            run.attempt(f"solve_lcp_batch(Lemke_12D) [{method}] workers={workers}",
                        lambda m=method, w=workers: lemke.solve_lcp_batch(M12, qs, method=m, workers=w))
        w = lemke.solve_lcp_many([M12] * len(qs), list(qs), method=method, workers=1).warm_start
        run.attempt(f"solve_lcp_batch warm (WarmStartBatch) [{method}]", lambda m=method, w=w: lemke.solve_lcp_batch(
            M12, qs[::-1].copy(), method=m, warm_start=w, workers=1))
        run.attempt(f"solve_lcp_batch warm (list) [{method}]", lambda m=method, w=w: lemke.solve_lcp_batch(
            M12, qs[::-1].copy(), method=m, warm_start=[None, w[1], w[2], w[3]], workers=1))
        Ms = [dart[name][0] for name in sorted(dart)]
        Qs = [dart[name][1] for name in sorted(dart)]
        for workers in (1, 2):
            run.attempt(f"solve_lcp_many(dart) [{method}] workers={workers}",
                        lambda m=method, w=workers: list(lemke.solve_lcp_many(Ms, Qs, method=m, workers=w)))
        many = lemke.solve_lcp_many(Ms, Qs, method=method, workers=1)
        run.attempt(f"solve_lcp_many warm [{method}]", lambda m=method, many=many: list(lemke.solve_lcp_many(
            Ms, [-q for q in Qs], method=m, warm_start=many.warm_start, workers=1)))


def sizes(run):
    """Every size from 1 to 9 and some larger ones (the core's loops in blocks of 4 and 8
    and their remainders): LCPs, MLCPs and QPs with each kind of constraint, both methods."""
    import lemke._qp
    from lemke import problems

    for n in (*range(1, 10), 16, 33, 130):
        rng = np.random.default_rng([5, n])
        run.lcp(f"size {n} psd", *problems.random_psd(n, rng))
        run.lcp(f"size {n} p-matrix", *problems.random_p_matrix(n, rng))
        run.lcp(f"size {n} contact-like", *problems.contact_like(max(n, 2), rng))
        if n > 33:
            continue
        k = max(1, n // 2)
        Am = rng.standard_normal((k, k)) + k * np.eye(k)
        Cm, Dm = rng.standard_normal((k, n)), rng.standard_normal((n, k))
        Bm = problems.random_psd(n, rng)[0]
        am, bm = rng.standard_normal(k), rng.standard_normal(n)
        for method in lemke.METHODS:
            run.attempt(f"size {n} mlcp [{method}]", lambda m=method: lemke.solve_mlcp(
                Am, Bm, Cm, Dm, am, bm, method=m))
        for rank in (None, max(1, n // 2)):
            P, q, G, h, A, b, lb, ub = problems.random_convex_qp(n, rng, rank=rank)
            forms = [("G", (P, q, G, h)), ("G A", (P, q, G, h, A, b)), ("G A box", (P, q, G, h, A, b, lb, ub))]
            if n >= lemke._qp.BOX_FIRST:  # (smaller box-only QPs take the fused box kernel)
                forms += [("box", (P, q, None, None, None, None, lb, ub)),
                          ("lb", (P, q, None, None, None, None, lb, None)),
                          ("ub, no P", (0 * P, q, None, None, None, None, lb, ub))]
            for form, args in forms:
                for method in lemke.METHODS:
                    run.attempt(f"size {n} qp rank {rank} {form} [{method}]", lambda m=method, args=args:
                                lemke.solve_qp(*args, method=m))


def box_lcps(run):
    import contact_sim
    import test_blcp

    for seed in range(120):
        M, q, lo, hi = test_blcp.family(seed)
        r = run.attempt(f"blcp family {seed}", lambda: lemke.solve_blcp(M, q, lo, hi))
        if r is not None:
            run.attempt(f"blcp family {seed} warm", lambda: lemke.solve_blcp(M, q[::-1].copy(), lo, hi,
                                                                              warm_start=r.warm_start))
    rng = np.random.default_rng(12)
    for t in range(300):
        n = int(rng.integers(1, 7))
        M = rng.integers(-2, 3, (n, n)).astype(float)
        if rng.random() < 0.5:
            M = M @ M.T
        q = rng.integers(-2, 3, n).astype(float)
        lo = rng.choice([-np.inf, -2.0, -1.0, 0.0], n)
        hi = np.maximum(rng.choice([0.0, 1.0, 2.0, np.inf], n), lo)
        run.attempt(f"blcp integer fuzz {t}", lambda: lemke.solve_blcp(M, q, lo, hi))
    for i, (M, q, lo, hi) in enumerate((
            ([[1.0]], [1.0], [-1e308], [1e308]),
            ([[1e-300]], [-1.0], [-1e308], [1e308]),
            ([[1e300, -1e300], [1e300, 1e300]], [-1.0, 1.0], [-np.inf, 0.0], [np.inf, 5e-324]),
            ([[0.0]], [1.0], [-np.inf], [np.inf]))):
        run.attempt(f"blcp extreme {i}", lambda: lemke.solve_blcp(M, q, lo, hi))
    for seed in range(40):
        M, q, lo, hi, findex, _ = test_blcp.contacts(seed, 1 + seed % 6)
        r = run.attempt(f"blcp friction contacts {seed}", lambda: lemke.solve_blcp(M, q, lo, hi, findex=findex))
        if r is not None:
            run.attempt(f"blcp friction contacts {seed} warm", lambda: lemke.solve_blcp(
                M, q + 0.01, lo, hi, findex=findex, warm_start=r.warm_start))
    A = np.array([[2.0, 0.5, -0.3], [0.5, 1.0, 0.2], [-0.3, 0.2, 1.5]])
    for qf in ([-1.0, 0.5, -0.3], [-1.0, 3.0, -2.0], [1.0, 0.5, 0.0]):  # stick, slide, no contact
        run.attempt(f"blcp friction findex q={qf}", lambda qf=qf: lemke.solve_blcp(
            A, np.array(qf), [0.0, -0.5, -0.5], [np.inf, 0.5, 0.5], findex=[-1, 0, 0]))
    # The contact scenes as box LCPs with a friction index (test_blcp.py's
    # test_contact_scenes_with_friction_index), and without it (the same bounds fixed).
    for seed in (1, 2):
        for k, (M, q) in enumerate(contact_sim.step_lcps(seed, n_bodies=20, steps=30, boxes=True)):
            if q.size == 0 or k % 2:
                continue
            m = q.size // 4
            rows = np.concatenate([np.arange(m), m + 2 * np.arange(m)])
            Ab, b = M[np.ix_(rows, rows)], q[rows]
            mu = M[3 * m + np.arange(m), np.arange(m)]
            lo = np.concatenate([np.zeros(m), -mu])
            hi = np.concatenate([np.full(m, np.inf), mu])
            findex = np.concatenate([-np.ones(m, dtype=int), np.arange(m)])
            run.attempt(f"contact scene {seed} step {k} findex", lambda: lemke.solve_blcp(Ab, b, lo, hi, findex=findex))
            run.attempt(f"contact scene {seed} step {k} box", lambda: lemke.solve_blcp(Ab, b, lo, hi))
    # examples/box_pile.py's steps (with its friction index), cold and warm from the last step.
    ws = None
    for k, (A, b, lo, hi, findex) in enumerate(test_blcp.pile_steps(n_disks=6, steps=60)):
        fi = None if findex.ndim == 0 else findex
        cold = run.attempt(f"box pile step {k} cold", lambda: lemke.solve_blcp(A, b, lo, hi, findex=fi))
        if ws is not None and (cold is None or ws.n != cold.warm_start.n):
            ws = None  # the pile changed size (as test_pile_warm_starts_across_steps)
        warm = run.attempt(f"box pile step {k} warm", lambda: lemke.solve_blcp(A, b, lo, hi, findex=fi, warm_start=ws))
        ws = None if warm is None else warm.warm_start


def games(run):
    import test_games

    for name, (A, B, _) in sorted(test_games.KNOWN.items()):
        m, n = np.shape(A)
        for k in range(m + n):
            run.attempt(f"{name} label {k}", lambda: lemke.solve_bimatrix(A, B, init_label=k))
            run.attempt(f"{name} label {k} exact", lambda: lemke.solve_bimatrix(A, B, init_label=k, exact=True))
        run.attempt(f"{name} lemke_paths", lambda: lemke.lemke_paths(A, B))
        run.attempt(f"{name} lemke_paths exact", lambda: lemke.lemke_paths(A, B, exact=True))
        run.attempt(f"{name} tracing", lambda: lemke.solve_bimatrix(A, B, method="tracing"))
    A, B = test_games.STENGEL_A, test_games.STENGEL_B
    r = lemke.solve_bimatrix(A, B, init_label=0)
    for k in range(5):
        run.attempt(f"von Stengel warm label {k}", lambda: lemke.solve_bimatrix(A, B, init_label=k, warm_start=r.basis))
    rng = np.random.default_rng(7)
    for t in range(20):
        m, n = (int(v) for v in rng.integers(1, 12, 2))
        A, B = rng.integers(0, 5, (m, n)), rng.integers(0, 5, (m, n))
        p, q = rng.random(m), rng.random(n)
        run.attempt(f"tracing random {t}", lambda: lemke.solve_bimatrix(A, B, method="tracing", prior=(p, q)))
        run.attempt(f"tracing random {t} exact", lambda: lemke.solve_bimatrix(A, B, method="tracing", prior=(p, q),
                                                                               exact=True))
    for kind in ("unif", "int100", "int3"):
        for m, n, seed in ((1, 1, 0), (1, 7, 1), (6, 1, 2), (12, 12, 3), (9, 17, 4), (30, 30, 5)):
            A, B = test_games.family(kind, m, n, seed)
            for label in {0, m + n - 1, (m + n) // 2}:
                run.attempt(f"{kind} {m}x{n} label {label}", lambda: lemke.solve_bimatrix(A, B, init_label=label))
            if m * n <= 150:
                run.attempt(f"{kind} {m}x{n} exact", lambda: lemke.solve_bimatrix(A, B, exact=True))
                run.attempt(f"{kind} {m}x{n} lemke_paths", lambda: lemke.lemke_paths(A, B, max_equilibria=20))
        A, B = test_games.family(kind, 60, 60, 0)
        run.attempt(f"{kind} 60x60", lambda: lemke.solve_bimatrix(A, B))
    rng = np.random.default_rng(1)
    A, B = rng.integers(0, 3, (50, 50)).astype(float), rng.integers(0, 3, (50, 50)).astype(float)
    run.attempt("degenerate int3 50x50", lambda: lemke.solve_bimatrix(A, B))
    for A, B in (([[1.0]], [[1.0]]), (np.ones((3, 4)), np.ones((3, 4))), (np.zeros((2, 5)), np.eye(2, 5))):
        run.attempt(f"constant game {np.shape(A)}", lambda: lemke.solve_bimatrix(A, B))
        run.attempt(f"constant game {np.shape(A)} lemke_paths", lambda: lemke.lemke_paths(A, B))


def array_likes(run):
    """Inputs that are not float64 C arrays, which the native entries convert themselves
    (src/python_front.cpp, made_f64 and made_bound): lists of floats, ints and bools,
    tuples, int / uint / bool / float32 arrays, Fortran-ordered, reversed, strided and
    unaligned float64 arrays, scalar box bounds; each entry point and the few-problem
    calls."""
    from lemke import problems

    rng = np.random.default_rng(11)
    for n in (1, 2, 5, 9):
        M, q = problems.random_psd(n, rng)
        Mi = rng.integers(-3, 4, (n, n))
        Mi = Mi @ Mi.T + np.eye(n, dtype=np.int64)
        raw = np.frombuffer(b"\0" + np.ascontiguousarray(M).tobytes(), dtype=np.float64, offset=1)
        forms = {"lists": (M.tolist(), q.tolist()), "tuples": (tuple(map(tuple, M)), tuple(q)),
                 "int lists": (Mi.tolist(), [-1] * n), "int32": (Mi.astype(np.int32), q.astype(np.float32)),
                 "uint8 bool": (np.eye(n, dtype=np.uint8), np.arange(n) % 2 == 0),
                 "fortran": (np.asfortranarray(M), q[::-1].copy()[::-1]),
                 "reversed": (M[::-1, ::-1], np.repeat(q, 3)[::3]), "unaligned": (raw.reshape(n, n), q)}
        for name, (Mx, qx) in forms.items():
            for method in lemke.METHODS:
                run.attempt(f"array-like {name} n={n} [{method}]",
                            lambda Mx=Mx, qx=qx, m=method: lemke.solve_lcp(Mx, qx, method=m))
            ws = lemke.solve_lcp(M, q).warm_start
            run.attempt(f"array-like {name} n={n} warm", lambda Mx=Mx, qx=qx, ws=ws: lemke.solve_lcp(
                Mx, qx, warm_start=ws))
            run.attempt(f"array-like {name} n={n} box", lambda Mx=Mx, qx=qx: lemke.solve_blcp(
                Mx, qx, -1.0, 2))
            run.attempt(f"array-like {name} n={n} box lists", lambda Mx=Mx, qx=qx: lemke.solve_blcp(
                Mx, qx, [-1.0] * n, np.full(n, np.inf).tolist()))
            run.attempt(f"array-like {name} n={n} game", lambda Mx=Mx: lemke.solve_bimatrix(Mx, Mx))
            run.attempt(f"array-like {name} n={n} many", lambda Mx=Mx, qx=qx: list(lemke.solve_lcp_many(
                [Mx, Mx], [qx, qx])))
            run.attempt(f"array-like {name} n={n} box many", lambda Mx=Mx, qx=qx: list(lemke.solve_blcp_many(
                [Mx, Mx], [qx, qx], -1.0, 1.0)))
        P, qq, G, h, A, b, lb, ub = problems.random_convex_qp(n, rng)
        run.attempt(f"array-like qp lists n={n}", lambda a=(P, qq, G, h, A, b, lb, ub): lemke.solve_qp(
            *[x.tolist() for x in a]))
        run.attempt(f"array-like qp fortran n={n}", lambda a=(P, qq, G, h, A, b, lb, ub): lemke.solve_qp(
            *[np.asfortranarray(x) if x.ndim == 2 else x for x in a]))


def run_all() -> Runner:
    """Every solve but the goldens' (the test compares those with the golden record)."""
    run = Runner()
    lcps(run)
    sizes(run)
    box_lcps(run)
    games(run)
    array_likes(run)
    sanitized_fuzz.fuzz(run)
    return run


def sanitizer_probe() -> dict:
    """Whether the sanitizers' runtimes are in this process: AddressSanitizer's allocator
    serves malloc (a block just freed is poisoned: in its quarantine) and UBSan's handlers
    are loaded."""
    import ctypes

    here = ctypes.CDLL(None)
    out = {"asan": hasattr(here, "__asan_init"), "ubsan": hasattr(here, "__ubsan_handle_add_overflow")}
    if out["asan"]:
        here.malloc.restype, here.malloc.argtypes = ctypes.c_void_p, [ctypes.c_size_t]
        here.free.argtypes = [ctypes.c_void_p]
        here.__asan_address_is_poisoned.argtypes = [ctypes.c_void_p]
        p = here.malloc(64)
        out["live_block_poisoned"] = bool(here.__asan_address_is_poisoned(p))
        here.free(p)
        out["freed_block_poisoned"] = bool(here.__asan_address_is_poisoned(p))
    return out


def main(out):
    import golden

    probe = sanitizer_probe()
    t0 = time.perf_counter()
    golden_results, golden_error = None, None
    try:
        golden_results = golden.solve_all()
    except Exception:
        golden_error = traceback.format_exc()[-3000:]
    t1 = time.perf_counter()
    run = run_all()
    from lemke import _core

    summary = {"solves": run.solves + len(golden_results or ()), "golden_solves": len(golden_results or ()),
               "errors": run.errors, "golden_error": golden_error, "fingerprints": run.fingerprints,
               "golden": golden_results, "golden_versions": golden.versions(), "core": _core.__file__, "probe": probe,
               "lemke": lemke.__file__, "seconds": {"golden": t1 - t0, "rest": time.perf_counter() - t1}}
    Path(out).write_text(json.dumps(summary))
    print(f"{summary['solves']} solves ({summary['golden_solves']} of the goldens), "
          f"{len(run.errors) + (golden_error is not None)} raised, {time.perf_counter() - t0:.1f} s")
    return 1 if run.errors or golden_error else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
