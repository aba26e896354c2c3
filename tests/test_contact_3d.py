"""examples/contact_3d.py, a short run: every island of every step solved, its answer checked
here with numpy in the friction pyramid's own terms (not the example's natural-map check);
warm starts carried by label as a dict would carry them; and a warm solve's z bit-identical
to a fresh solve from the same basis."""
import sys
from pathlib import Path

import numpy as np
import pytest

import lemke

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))
import contact_3d  # noqa: E402


@pytest.fixture(scope="module")
def run():
    record = []
    hist = contact_3d.simulate(bodies=8, steps=50, cold=False, record=record)
    return hist, record


def pyramid_ok(A, b, lo, hi, findex, z, tol=1e-8):
    """The conditions of a friction step, one row at a time: z_n >= 0 with w_n >= 0 and
    z_n w_n = 0; |z_t| <= mu z_n with w_t = 0 strictly inside, w_t <= 0 at +mu z_n and
    w_t >= 0 at -mu z_n.  ``tol`` relative to the data's scale."""
    w = A @ z + b
    eps = tol * max(1.0, np.abs(b).max(), np.abs(A).max() * np.abs(z).max())
    for i in range(z.size):
        f = findex[i]
        if f < 0:
            assert lo[i] == 0.0 and hi[i] == np.inf
            if not (z[i] >= -eps and w[i] >= -eps and min(abs(z[i]), abs(w[i])) <= eps):
                return False
        else:
            cap = hi[i] * z[f]
            assert lo[i] == -hi[i]
            if abs(z[i]) > cap + eps:
                return False
            if abs(z[i]) < cap - eps and abs(w[i]) > eps:
                return False
            if z[i] >= cap - eps and cap > eps and w[i] > eps:
                return False
            if z[i] <= -cap + eps and cap > eps and w[i] < -eps:
                return False
    return True


def test_every_step_is_solved_and_passes_an_independent_check(run):
    hist, record = run
    assert len(hist["rows"]) == 50
    assert record and all(pyramid_ok(r["A"], r["b"], r["lo"], r["hi"], r["findex"], r["z"]) for r in record)
    big = max(record, key=lambda r: r["b"].size)  # the check can fail: a wrong z does
    z = big["z"].copy()
    z[np.argmax(z)] *= 1.01
    assert not pyramid_ok(big["A"], big["b"], big["lo"], big["hi"], big["findex"], z)
    assert sum(hist["refused"]) == 0  # every island SOLVED by lemke's own check too (this run)
    # the scene is what it says: contacts appear and vanish, islands merge and split
    assert sum(hist["changed"][1:]) >= 5
    assert len(set(hist["islands"])) >= 3


def _by_step(record):
    out = {}
    for r in record:
        out.setdefault(r["step"], []).append(r)
    return out


def test_warm_starts_are_carried_by_label_across_contact_changes(run):
    hist, record = run
    by_step = _by_step(record)
    across_change = 0
    for s, isl in by_step.items():
        if s - 1 not in by_step:
            continue
        state = {}  # last step's row states by label, in a plain dict
        for r in by_step[s - 1]:
            state.update(zip(r["labels"].tolist(), r["final"].row_states().tolist()))
        old = set(state)
        for r in isl:
            # a new row starts cold: at lo (code 0), a friction row with its variables at 0 (3)
            want = [state.get(lab, 3 if f >= 0 else 0) for lab, f in zip(r["labels"].tolist(), r["findex"])]
            got = r["carried"]
            assert got.row_states().tolist() == want
            assert got.friction == tuple(np.flatnonzero(r["findex"] >= 0).tolist())
            across_change += not set(r["labels"].tolist()) <= old and any(lab in old for lab in r["labels"].tolist())
    assert across_change >= 1


def _again(r, ws):
    return lemke.solve_blcp(r["A"], r["b"], r["lo"], r["hi"], findex=r["findex"], warm_start=ws)


def test_warm_z_is_bit_identical_to_a_fresh_solve_from_the_same_basis(run):
    hist, record = run
    warm = 0
    for r in record:
        ws = r["start"]
        fresh = None if ws is None else lemke.BoxWarmStart(ws.n, ws.z_basic, ws.at_upper, ws.friction)
        again = _again(r, fresh)
        assert again.success
        assert np.asarray(again.z).tobytes() == r["z"].tobytes()
        warm += ws is not None
    assert warm >= len(record) // 2


@pytest.mark.parametrize("workers", [1, 2])
def test_islands_in_one_call_are_bit_identical_to_single_solves(run, workers):
    hist, record = run
    by_step = _by_step(record)
    several = 0
    for s, isl in by_step.items():
        batch = isl[0]["batch"]
        many = lemke.solve_blcp_many([r["A"] for r in isl], [r["b"] for r in isl], [r["lo"] for r in isl],
                                     [r["hi"] for r in isl], findex=[r["findex"] for r in isl],
                                     warm_start=batch, workers=workers)
        for k, r in enumerate(isl):
            one = _again(r, None if batch is None else batch[k])
            assert many[k].status == one.status and many[k].pivots == one.pivots
            assert np.asarray(many[k].z).tobytes() == np.asarray(one.z).tobytes()
        several += len(isl) > 1
    assert several >= 5
