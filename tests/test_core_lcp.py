"""The C++ LCP driver (src/lemke/lcp.cpp: solve_one with its recovery ladder, the ray check,
the restart from a warm basis, and batch) against the frozen outputs of the kernels it
was ported from (tests/frozen.py, tests/data/frozen/test_core_lcp.json), bit for bit: every
returned number and every byte of the output buffer and of the basic z's, on the stress
suite's problems (DART, Murty, Siconos, Drake, integer families, contact steps and their
scaled copies: the problems that need the recoveries), at several tie tolerances, by both
methods, cold and warm (a restart from a basis at n >= 100, and the old basis's point
below), and through the batch kernel."""
import numpy as np
import pytest

import frozen
import stress_cases
from lemke import _core, _layout

NO_D = np.empty(0)
NO_I = np.zeros(0, dtype=np.int64)


def _keys():
    keys = [c.key for c in stress_cases.CASES if not c.uses_lemke]
    keys += [c.key for c in stress_cases.CASES if c.uses_lemke][::4]
    return keys


KEYS = _keys()


def _run(fn, method, M, q, beta, k, mp, ptol, ttol, tol):
    n = len(q)
    L = _layout.buffer_length(n)
    buf = np.full(L + n, np.nan)
    r = fn(method, M, q, NO_D, beta, k, mp, ptol, ttol, tol, buf, NO_I)
    out = tuple(float(x) if isinstance(x, float) else int(x) for x in r)
    k_out = out[2]
    # the fields and the basic z's written (the rest of the tail is scratch)
    return out, buf[:L].tobytes(), buf[L:L + k_out].tobytes()


def _both(method, M, q, beta=NO_I, k=0, tie_tol=1e-11, mp=None, label=""):
    """The core's solve_one, its every output checked against the frozen references."""
    n = len(q)
    mp = 100 * (n + 1) if mp is None else mp
    b = _run(_core.solve_one, method, M, q, beta, k, mp, 1e-11, tie_tol, 1e-9)
    return frozen.check(b, label)


@pytest.mark.parametrize("key", KEYS)
def test_solve_one_is_the_frozen_oracle_bit_for_bit(key):
    M, q = stress_cases.problem(key)
    M, q = np.ascontiguousarray(M, float), np.ascontiguousarray(q, float)
    opts = dict(stress_cases.ALL[key].options)
    mp = opts.get("max_pivots")
    for method in (0, 1):
        for tie in (1e-11, 0.0, 1e-9):
            _both(method, M, q, tie_tol=tie, mp=mp, label=(key, method, tie))


@pytest.mark.parametrize("n", [5, 24, 100, 140])
def test_warm_solve_one_is_the_frozen_oracle_bit_for_bit(n):
    """Warm starts: the old basis's point (it solves, or fails and goes cold below
    RESTART_FROM), and the restart from it at n >= 100, on moved q."""
    rng = np.random.default_rng(n)
    for trial in range(6):
        A = rng.standard_normal((n, n))
        M = A @ A.T + (0.1 if trial % 2 else 0.0) * np.eye(n)
        if trial >= 4:
            M = M + rng.standard_normal((n, n)) * 0.3  # not symmetric
        q = rng.standard_normal(n)
        a = _both(0, M, q, label=(n, trial))
        k = a[0][2]
        beta = np.frombuffer(a[2], dtype=np.int64).copy()
        for move in (1e-9, 1e-2, 0.5):
            q2 = q + move * rng.standard_normal(n)
            for method in (0, 1):
                _both(method, M, q2, beta, k, label=(n, trial, move, method))


def test_batch_is_the_frozen_oracle_bit_for_bit():
    """The batch kernel's layout: problems of different sizes end to end, some warm."""
    rng = np.random.default_rng(5)
    Ms, qs, betas, sizes = [], [], [], []
    for b in range(40):
        n = int(rng.integers(1, 30))
        A = rng.standard_normal((n, n))
        M = A @ A.T + 0.05 * np.eye(n)
        q = rng.standard_normal(n)
        Ms.append(M.ravel())
        qs.append(q)
        sizes.append(n)
        betas.append(np.arange(0, n, 2, dtype=np.int64) if b % 3 == 0 else NO_I)
    for key in ("murty/murty-12", "dart/Lemke_12D"):
        M, q = stress_cases.problem(key)
        Ms.append(np.ascontiguousarray(M, float).ravel())
        qs.append(np.asarray(q, float))
        sizes.append(len(q))
        betas.append(NO_I)
    B = len(sizes)
    qoff = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    mstart = np.concatenate([[0], np.cumsum([s * s for s in sizes])[:-1]]).astype(np.int64)
    boff = np.concatenate([[0], np.cumsum([len(x) for x in betas])]).astype(np.int64)
    buff = np.concatenate([[0], np.cumsum([_layout.buffer_length(s) for s in sizes])]).astype(np.int64)
    Mflat, qflat, beta = np.concatenate(Ms), np.concatenate(qs), np.concatenate(betas + [NO_I])
    mp = np.array([100 * (s + 1) for s in sizes], dtype=np.int64)
    mp[-2] = 2**12 + 100

    def run(fn, method):
        bufs = np.full(buff[-1], np.nan)
        basics = np.full(qoff[-1], -7, dtype=np.int64)
        out_i = np.zeros((B, 5), dtype=np.int64)
        out_f = np.zeros((B, 2))
        fn(method, Mflat, mstart, qflat, qoff, beta, boff, 0, B, mp, 1e-11, 1e-11, 1e-9, bufs,
           buff, basics, out_i, out_f)
        ks = out_i[:, 2]
        used = np.concatenate([basics[qoff[b]:qoff[b] + ks[b]] for b in range(B)])
        return out_i.tobytes(), out_f.tobytes(), bufs.tobytes(), used.tobytes()

    for method in (0, 1):
        frozen.check(run(_core.batch, method), method)
