"""Warm starts in the tableau method: the final basis handed back."""
import pickle
import threading

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from helpers import assert_lcp_solution, assert_ray

import lemke
from lemke import problems
from lemke._layout import RESTART_FROM


def test_same_basis_still_solves_gives_zero_pivots(method):
    rng = np.random.default_rng(5)
    M, q = problems.random_p_matrix(30, rng)
    cold = lemke.solve_lcp(M, q, method=method)
    assert cold.success and cold.pivots > 0
    warm = lemke.solve_lcp(M, q + 1e-9 * np.abs(q).max(), warm_start=cold.warm_start, method=method)
    assert warm.success and warm.pivots == 0
    assert_lcp_solution(M, q + 1e-9 * np.abs(q).max(), warm.z)


def test_stale_basis_falls_back_and_is_right(method):
    rng = np.random.default_rng(6)
    M, q = problems.random_psd(20, rng)
    cold = lemke.solve_lcp(M, q, method=method)
    other_q = rng.standard_normal(20)
    res = lemke.solve_lcp(M, other_q, warm_start=cold.warm_start, method=method)
    assert res.success
    assert_lcp_solution(M, other_q, res.z)


def test_warm_start_from_unrelated_singular_problem():
    ws = lemke.WarmStart(3, (0, 1, 2))
    M = np.zeros((3, 3))  # M_bb singular
    res = lemke.solve_lcp(M, [1.0, 2.0, 0.0], warm_start=ws)
    assert res.success and res.pivots == 0


def test_warm_start_is_a_plain_value():
    p = problems.cps_447()
    ws = lemke.solve_lcp(p.M, p.q).warm_start
    assert ws == pickle.loads(pickle.dumps(ws)) and hash(ws) == hash(lemke.WarmStart(3, ws.z_basic))
    assert ws.z_basic == (1, 2)
    with pytest.raises(AttributeError):
        ws.n = 4
    with pytest.raises(ValueError):
        lemke.WarmStart(3, (0, 3))
    with pytest.raises(ValueError):
        lemke.WarmStart(3, (1, 1))


@pytest.mark.parametrize("kind", ["q", "M and q"])
def test_small_change_restarts_from_the_old_basis(method, kind):
    """A change that moves the solution's basis costs a few pivots, not a cold solve."""
    rng = np.random.default_rng(8)
    n = 120
    M, q = problems.random_p_matrix(n, rng)
    prev = lemke.solve_lcp(M, q, method=method)
    restarts = []
    for step in range(10):
        q = q + 2e-2 * np.abs(q).max() * rng.standard_normal(n)
        if kind == "M and q":
            M = M + 2e-2 * np.abs(M).max() * rng.standard_normal((n, n)) / np.sqrt(n)
        cold = lemke.solve_lcp(M, q, method=method)
        res = lemke.solve_lcp(M, q, method=method, warm_start=prev.warm_start)
        assert res.success
        assert_lcp_solution(M, q, res.z)
        np.testing.assert_allclose(res.z, cold.z, atol=1e-8 * np.abs(cold.z).max())  # unique
        restarts.append(res.pivots)
        assert res.pivots < cold.pivots / 4, (res.pivots, cold.pivots)
        prev = res
    assert max(restarts) > 0  # the basis did change: the restart path was exercised


@pytest.mark.parametrize("n", [2, RESTART_FROM])
def test_restart_ray_is_checked_with_its_own_covering_vector(method, n):
    """An infeasible problem reached by a warm start ends on a ray valid for the column used
    (n = 2: below RESTART_FROM the problem goes cold at once; the 2 x 2 block padded with
    an identity to RESTART_FROM rows: Lemke restarts from the old basis first)."""
    M = np.eye(n)
    M[:2, :2] = [[1.0, -1.0], [-1.0, 1.0]]
    q1, q2 = np.ones(n), np.ones(n)
    q1[:2], q2[:2] = [1.0, -1.0], [-1.0, -1.0]
    first = lemke.solve_lcp(M, q1, method=method)
    assert first.success and first.warm_start.z_basic
    res = lemke.solve_lcp(M, q2, method=method, warm_start=first.warm_start)
    assert res.status == lemke.Status.RAY_TERMINATION
    assert_ray(M, q2, res.covering, res.z, res.z0, res.ray)


@pytest.mark.parametrize("n", [3, 8, RESTART_FROM - 1])
def test_small_problem_whose_warm_basis_fails_goes_cold(method, n):
    """Below RESTART_FROM rows a warm start whose basis no longer solves the problem is not
    restarted from (the unrevised restart costs more than a cold solve there): the answer is
    the cold answer, bit for bit, and it solves the problem."""
    rng = np.random.default_rng([61, n])
    failed = 0
    for _ in range(20):
        A = rng.standard_normal((n, n))
        M, q = A @ A.T + 0.1 * np.eye(n), rng.standard_normal(n)
        ws = lemke.solve_lcp(M, q, method=method).warm_start
        q2 = q + 0.5 * rng.standard_normal(n)
        warm, cold = (lemke.solve_lcp(M, q2, method=method, warm_start=w) for w in (ws, None))
        assert warm.success
        assert_lcp_solution(M, q2, warm.z)
        if warm.pivots:  # the old basis failed
            failed += 1
            assert np.array_equal(warm.z, cold.z) and warm.pivots == cold.pivots
    assert failed > 0  # the cold path was exercised


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 30), st.sampled_from(lemke.METHODS))
def test_any_warm_start_gives_a_right_answer(seed, n, method):
    """A warm start from an unrelated problem (any basis at all) never gives a wrong answer
    or a crash: monotone feasible problems are still solved, and checked."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, max(1, n // 2)))
    B = rng.standard_normal((n, n))
    M = A @ A.T + B - B.T  # PSD plus skew, rank deficient: many singular blocks
    q = np.maximum(rng.standard_normal(n), 0.0) - M @ np.maximum(rng.standard_normal(n), 0.0)
    ws = lemke.WarmStart(n, tuple(np.flatnonzero(rng.random(n) < 0.5)))
    res = lemke.solve_lcp(M, q, method=method, warm_start=ws)
    assert res.status == lemke.Status.SOLVED, res
    assert_lcp_solution(M, q, res.z)


def _in_a_new_thread(f):
    """f() in a thread of its own: the core's per-thread kept matrices start empty there."""
    out = []
    t = threading.Thread(target=lambda: out.append(f()))
    t.start()
    t.join()
    return out[0]


@pytest.mark.parametrize("n", [1, 2, 3, 5, 12, 17, 24, 40, 300])  # 300: the large slot, above 256 rows
def test_a_repeated_matrix_gives_the_same_bits(n, method):
    """A warm start's first stage keeps, per thread, what the equilibration's sweeps found
    of M and the last basis block's factors (equilibrate_finite_kept, solve_gathered_kept)
    and reuses them when M repeats bit for bit: a re-solve right after one on the same M
    with another q (sweeps and factors reused, or found stale: the trajectory of the scales
    can part where q's terms differ) is the same result, bit for bit, as one in a new thread
    (all computed afresh); on a basis that fits, one that no longer does and a singular
    block. Every solved answer is checked."""
    rng = np.random.default_rng(1000 + n)
    A = rng.standard_normal((n, n))
    M = A @ A.T + 0.1 * np.eye(n)
    q = rng.standard_normal(n)
    q[0] = -1.0 - abs(q[0])
    S = rng.standard_normal((n, max(1, n // 2)))
    M_sing = S @ S.T  # rank deficient: singular blocks
    D = 10.0 ** rng.uniform(-3, 3, n)
    M_bad = D[:, None] * M * D  # badly scaled: q's terms steer the scales
    starts = [lemke.solve_lcp(data, q, method=method).warm_start for data in (M, M_bad)]
    qs = (q + 1e-9, q + 1e-3 * rng.standard_normal(n), -np.abs(q),
          q * 10.0 ** rng.uniform(-8, 8, n), q * 10.0 ** rng.uniform(-8, 8, n))
    scales = set()
    for data, start in ((M, starts[0]), (M_bad, starts[1]),
                        (M_sing, lemke.WarmStart(n, tuple(range(n))))):
        for qb in qs:
            fresh = _in_a_new_thread(
                lambda: lemke.solve_lcp(data, qb, warm_start=start, method=method))
            scales.add((data is M_bad, fresh.row_scale.tobytes(), fresh.col_scale.tobytes()))
            if fresh.status == lemke.Status.SOLVED:
                assert_lcp_solution(data, qb, fresh.z)
            for qa in qs:
                lemke.solve_lcp(data, qa, warm_start=start, method=method)
                again = lemke.solve_lcp(data, qb, warm_start=start, method=method)
                assert again == fresh
                for name in ("z", "w", "row_scale", "col_scale", "covering", "ray"):
                    a, b = getattr(again, name), getattr(fresh, name)
                    assert (a is None and b is None) or a.tobytes() == b.tobytes()
    if n > 2:  # the scales' trajectories part between some of the q's on M_bad
        assert len([s for s in scales if s[0]]) > 1


def test_islands_kept_apart_give_the_same_bits():
    """Many matrices kept at once (the table's slots, islands of a batch): warm re-solves of
    300 small problems in turn, twice, give the bits of the same re-solves each in a new
    thread."""
    rng = np.random.default_rng(77)
    probs = []
    for i in range(300):
        n = 1 + i % 12
        A = rng.standard_normal((n, n))
        M = A @ A.T + 0.1 * np.eye(n)
        q = rng.standard_normal(n)
        probs.append((M, q, lemke.solve_lcp(M, q).warm_start))
    fresh = _in_a_new_thread(lambda: [
        _in_a_new_thread(lambda: lemke.solve_lcp(M, q + 1e-3, warm_start=ws))
        for M, q, ws in probs[:40]])
    for _ in range(2):
        again = [lemke.solve_lcp(M, q + 1e-3, warm_start=ws) for M, q, ws in probs]
        assert again[:40] == fresh
    batch = lemke.solve_lcp_many([p[0] for p in probs], [p[1] + 1e-3 for p in probs],
                                 warm_start=[p[2] for p in probs])
    assert list(batch) == again
    for (M, q, _), r in zip(probs, again):
        if r.status == lemke.Status.SOLVED:
            assert_lcp_solution(M, q + 1e-3, r.z)


# --- warm starts across changes of size (WarmStart.take / relabel) ------------------------

def test_take_and_relabel():
    ws = lemke.WarmStart(4, (0, 2, 3))
    assert ws.take([3, -1, 0]) == lemke.WarmStart(3, (0, 2))
    assert ws.take([1, 2]) == lemke.WarmStart(2, (1,))
    assert ws.relabel("abcd", "dxa") == lemke.WarmStart(3, (0, 2))
    assert ws.take([]) == lemke.WarmStart(0, ())
    for bad, exc in (([4], ValueError), ([-2], ValueError), ([0, 0], ValueError), ([0.5], TypeError)):
        with pytest.raises(exc):
            ws.take(bad)
    with pytest.raises(ValueError):
        ws.relabel("abc", "ab")
    with pytest.raises(ValueError):
        ws.relabel("aacd", "ab")
    with pytest.raises(ValueError, match="new_labels"):
        ws.relabel("abcd", "abca")  # a label twice: two new rows from one old row


def test_relabel_is_take_by_position():
    """relabel (its own pure-Python path) against take (numpy) on random label lists: rows
    kept, dropped, permuted and new, labels of several types."""
    rng = np.random.default_rng(11)
    for _ in range(300):
        n = int(rng.integers(0, 30))
        old = [("c", int(i), (int(i) % 3, "t")) for i in rng.permutation(60)[:n]]
        ws = lemke.WarmStart(n, tuple(sorted(rng.permutation(n)[: int(rng.integers(0, n + 1))].tolist())))
        kept = [old[j] for j in rng.permutation(n)[: int(rng.integers(0, n + 1))]]
        fresh = [("c", 100 + int(i), (0, "t")) for i in range(int(rng.integers(0, 5)))]
        new = [kept[i] if i < len(kept) else fresh[i - len(kept)] for i in rng.permutation(len(kept) + len(fresh))]
        positions = [old.index(label) if label in old else -1 for label in new]
        got = ws.relabel(iter(old), new)
        assert got == ws.take(positions)
        assert all(type(i) is int for i in got.z_basic)


def test_relabel_by_integer_arrays_is_take_by_position():
    """relabel with 1-D integer arrays (one kernel call, carry.cpp's hash tables)
    against take (numpy) on random ids: rows kept, dropped, permuted and new; ids that
    share their low bits (contact ids times 4), negative ids, uint64 ids above 2**63, other
    integer dtypes; a WarmStart made by hand as well as one read from a result."""
    rng = np.random.default_rng(12)
    for t in range(400):
        n, fresh = int(rng.integers(0, 40)), int(rng.integers(0, 6))
        ids = rng.choice(10**6, size=n + fresh, replace=False).astype(np.int64) * 4
        if t % 3 == 1:
            ids -= 2 * 10**6
        old, extra = rng.permutation(ids[:n]), ids[n:]
        ws = lemke.WarmStart(n, tuple(sorted(rng.permutation(n)[: int(rng.integers(0, n + 1))].tolist())))
        kept = old[rng.permutation(n)[: int(rng.integers(0, n + 1))]]
        new = rng.permutation(np.concatenate([kept, extra]))
        positions = [int(np.flatnonzero(old == label)[0]) if label in old else -1 for label in new]
        want = ws.take(positions)
        got = ws.relabel(old, new)
        assert got == want == ws.relabel(old.tolist(), new.tolist())
        assert got.__dict__["_beta"].tolist() == list(got.z_basic)
        assert all(type(i) is int for i in got.z_basic)
        if t % 3 == 2:  # other integer dtypes, read-only and strided arrays
            o32 = np.repeat(old.astype(np.int32), 2)[::2]
            o32.setflags(write=False)
            assert ws.relabel(o32, new.astype(np.int64).astype(np.uint64)) == want
    big = np.array([2**63 + 5, 2**63 + 9, 7], dtype=np.uint64)
    assert lemke.WarmStart(3, (0, 2)).relabel(big, big[::-1].copy()) == lemke.WarmStart(3, (0, 2))
    with pytest.raises(ValueError, match="old_labels holds a label twice"):
        lemke.WarmStart(3, ()).relabel(np.array([1, 2, 1]), np.array([1]))
    with pytest.raises(ValueError, match="new_labels holds a label twice"):
        lemke.WarmStart(2, ()).relabel(np.array([1, 2]), np.array([3, 3]))
    with pytest.raises(ValueError, match="old_labels has 2 labels"):
        lemke.WarmStart(3, ()).relabel(np.array([1, 2]), np.array([3]))
    # float arrays are labels too (hashable values): the general path takes them
    assert lemke.WarmStart(2, (1,)).relabel(np.array([0.5, 1.5]), np.array([1.5])) == lemke.WarmStart(1, (0,))


def test_a_permuted_problem_keeps_its_basis():
    rng = np.random.default_rng(5)
    A = rng.standard_normal((12, 12))
    M, q = A @ A.T + 0.1 * np.eye(12), rng.standard_normal(12)
    res = lemke.solve_lcp(M, q)
    perm = rng.permutation(12)
    again = lemke.solve_lcp(M[np.ix_(perm, perm)], q[perm], warm_start=res.warm_start.take(perm))
    assert again.success and again.pivots == 0
    np.testing.assert_allclose(again.z, res.z[perm], rtol=1e-12, atol=1e-14)


def test_pile_simulation_with_contacts_that_come_and_go():
    """A 2-D pile (tests/contact_sim.py): the step LCPs change size as contacts appear and
    vanish; each step starts warm from the last one's basis, carried over by the contacts'
    labels.  Every step is checked independently, and the warm steps take fewer pivots than
    cold solves of the same LCPs."""
    import contact_sim

    sc = contact_sim.Scene(3, 10, False)
    ws, labels, ids = None, [], None
    warm_pivots = cold_pivots = sizes_changed = 0
    for step in range(60):
        M, q, apply = contact_sim.step_lcp(sc, step)
        start = None if ws is None else ws.relabel(labels, apply.labels)
        # the same contacts as int64 ids carry the same basis (the kernel path)
        assert ws is None or ws.relabel(ids, apply.id_array) == start
        sizes_changed += ws is not None and ws.n != q.size
        res = lemke.solve_lcp(M, q, warm_start=start)
        cold = lemke.solve_lcp(M, q)
        assert res.success == cold.success, step
        if res.success:
            assert_lcp_solution(M, q, res.z)
        warm_pivots += res.pivots
        cold_pivots += cold.pivots
        apply(res.z if res.success else None)
        ws, labels, ids = res.warm_start, apply.labels, apply.id_array
    assert sizes_changed > 0
    assert warm_pivots < cold_pivots, (warm_pivots, cold_pivots)


def test_warm_starts_read_back_are_taken_as_they_are():
    """A warm start read from a result whose arrays were read first (its buffer read-only
    by then), or from a solve_lcp_many result's WarmStartBatch, goes to the core as it is,
    in a new process whose first solve_lcp call is such a warm start (with the former
    JIT-compiled kernels, a read-only index array compiled them a second time, some 20 s; the
    core takes read-only arrays)."""
    import subprocess
    import sys

    code = """
import numpy as np, lemke
rng = np.random.default_rng(3)
A = rng.standard_normal((6, 6))
M, q = A @ A.T + 0.1 * np.eye(6), rng.standard_normal(6)
many = lemke.solve_lcp_many([M, M], [q, q])
many.z
first = lemke.solve_lcp(M, q + 1e-3, warm_start=many.warm_start[1])
res = lemke.solve_lcp(M, q)
assert res.z.flags.writeable is False
for ws in (res.warm_start, many[0].warm_start, first.warm_start):
    again = lemke.solve_lcp(M, q + 1e-3, warm_start=ws)
    assert again.success and again == lemke.solve_lcp(M, q + 1e-3, warm_start=lemke.WarmStart(6, ws.z_basic))
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["ok"]


@pytest.mark.parametrize("n", [1, 3, 6, 12, 24, 40, 300])
def test_a_repeated_box_matrix_gives_the_same_bits(n):
    """The box LCP's 0-pivot warm path (no friction index) takes its check's scales and its
    basis block through the kept matrices too (boxed.check_scales_kept, basis_point with
    solve_gathered_kept): re-solves on the same M with other q's, one after another, give the
    bits of the same re-solve in a new thread (all computed afresh); on a basis that fits,
    one that no longer does (a run), a badly scaled M and a singular block. Every solved
    answer is checked (independently: box complementarity on the caller's data)."""
    from test_blcp import assert_box_solution
    rng = np.random.default_rng(2000 + n)
    A = rng.standard_normal((n, n))
    M = A @ A.T + 0.1 * np.eye(n)
    q = rng.standard_normal(n)
    lo = np.where(np.arange(n) % 2 == 0, 0.0, -0.5)
    hi = np.where(np.arange(n) % 2 == 0, np.inf, 0.5)
    S = rng.standard_normal((n, max(1, n // 2)))
    M_sing = S @ S.T
    D = 10.0 ** rng.uniform(-3, 3, n)
    M_bad = D[:, None] * M * D
    starts = [lemke.solve_blcp(data, q, lo, hi).warm_start for data in (M, M_bad)]
    qs = (q + 1e-9, q + 1e-3 * rng.standard_normal(n), -np.abs(q),
          q * 10.0 ** rng.uniform(-8, 8, n))
    zero_pivots = 0
    for data, start in ((M, starts[0]), (M_bad, starts[1]),
                        (M_sing, lemke.BoxWarmStart(n, tuple(range(n)), ()))):
        for qb in qs:
            fresh = _in_a_new_thread(lambda: lemke.solve_blcp(data, qb, lo, hi, warm_start=start))
            if fresh.success:
                assert_box_solution(data, qb, lo, hi, fresh.z, rtol=1e-7)
                zero_pivots += fresh.pivots == 0
            for qa in qs:
                lemke.solve_blcp(data, qa, lo, hi, warm_start=start)
                again = lemke.solve_blcp(data, qb, lo, hi, warm_start=start)
                assert (again.status, again.pivots) == (fresh.status, fresh.pivots)
                for name in ("z", "w", "row_scale", "col_scale", "covering", "ray"):
                    a, b = getattr(again, name), getattr(fresh, name)
                    assert (a is None and b is None) or a.tobytes() == b.tobytes()
                assert again.residual == fresh.residual or (again.residual != again.residual
                                                            and fresh.residual != fresh.residual)
    assert zero_pivots > 0  # the kept path was taken
