"""The answers on the peer data are those recorded in tests/data/golden.json (see
tests/golden.py): bit for bit with the same numpy and scipy on the same CPU (a
record of this platform), else, against the newest record, the same statuses and LCP
pivots, arrays to 1e-8, and a QP's optimal value to 1e-8 (its x and multipliers need not be
unique)."""
import numpy as np
import pytest

import golden

RECORDS = golden.records()
_OWN = [r for r in RECORDS if r["versions"] == golden.versions()]
SAME_VERSIONS = bool(_OWN)
RECORD = _OWN[0] if _OWN else RECORDS[-1]


def test_records_answer_the_same_problems_alike():
    """Every platform's record holds the same problems, with the same statuses, and
    answers that agree to 1e-8 (so a record of another platform is a fair reference)."""
    first = RECORDS[0]["results"]
    for other in RECORDS[1:]:
        assert sorted(other["results"]) == sorted(first)
        for key, old in first.items():
            _assert_agree(key, other["results"][key], old)


def _assert_close(new, old):
    """Agreement to 1e-8 of a recorded field (a list of floats written with repr, or a
    number such as the pivots)."""
    a, b = np.atleast_1d(np.array(new, dtype=float)), np.atleast_1d(np.array(old, dtype=float))
    np.testing.assert_allclose(a, b, rtol=1e-8, atol=1e-8 * max(1.0, np.abs(b).max(initial=0.0)))


@pytest.fixture(scope="module")
def now():
    return golden.solve_all()


def test_the_same_problems(now):
    assert sorted(now) == sorted(RECORD["results"])


@pytest.mark.parametrize("key", sorted(RECORD["results"]))
def test_same_answer(now, key):
    old, new = RECORD["results"][key], now[key]
    if SAME_VERSIONS:
        assert new == old, key  # every field, bit for bit
    else:
        _assert_agree(key, new, old)


def _assert_agree(key, new, old):
    """Two platforms' answers agree: the same status; for a QP the same optimal value, for
    the others every array to 1e-8 (and an LCP's pivots exactly)."""
    assert new["status"] == old["status"], key
    if key.startswith("qp/"):
        if new["status"] != 0:
            return  # not solved (the same status): no optimal value to compare
        # Another platform: a QP's x and multipliers need not be unique (a singular P, or
        # dependent active rows: seen on Maros-Meszaros files), and rounding can pick
        # another of them, after other pivots; its optimal value is unique.  (Each
        # answer's KKT conditions are asserted by test_qp.py and test_maros_meszaros.py.)
        P, q = QP_DATA[key.split("/", 1)[1].rsplit("/", 1)[0]]
        f_old, size = _objective(P, q, old["x"])
        f_new, _ = _objective(P, q, new["x"])
        assert abs(f_new - f_old) <= 1e-8 * size, (key, f_new, f_old)
        return
    for field, values in old.items():
        if field == "status":
            continue
        if field == "pivots" and key.startswith(("lcp/", "batch/")):
            assert new[field] == values, (key, field)
        else:
            _assert_close(new[field], values)


QP_DATA = {name: (np.asarray(args[0], float), np.asarray(args[1], float)) for name, args in golden.qp_cases()}


def _objective(P, q, x):
    """0.5 x'Px + q'x of a recorded x, and the size of its terms (plus 1)."""
    x = np.array(x, dtype=float)
    quad, lin = 0.5 * x @ P @ x, q @ x
    return quad + lin, 1.0 + abs(quad) + abs(lin) + 0.5 * np.abs(x) @ np.abs(P) @ np.abs(x)
