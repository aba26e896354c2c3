"""The answers on the peer data are those recorded in tests/data/golden.json (see
tests/golden.py): bit for bit with the same numpy, scipy and numba, else to 1e-8."""
import json

import numpy as np
import pytest

import golden

RECORD = json.loads(golden.OUT.read_text())
SAME_VERSIONS = RECORD["versions"] == golden.versions()


@pytest.fixture(scope="module")
def now():
    return golden.solve_all()


def test_the_same_problems(now):
    assert sorted(now) == sorted(RECORD["results"])


@pytest.mark.parametrize("key", sorted(RECORD["results"]))
def test_same_answer(now, key):
    old, new = RECORD["results"][key], now[key]
    assert new["status"] == old["status"], key
    for field, values in old.items():
        if field == "status":
            continue
        if SAME_VERSIONS or (field == "pivots" and key.startswith(("lcp/", "batch/"))):
            assert new[field] == values, (key, field)
        else:
            a = np.array([float(x) for x in new[field]])
            b = np.array([float(x) for x in values])
            np.testing.assert_allclose(a, b, rtol=1e-8, atol=1e-8 * max(1.0, np.abs(b).max(initial=0.0)))
