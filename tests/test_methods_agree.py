"""Tableau and unrevised Lemke agree on every peer problem: the same status, the same pivot
count and the same z (all these problems are run with the same rules, so even where the
solution is not unique both methods must reach the same one)."""
import json
from pathlib import Path

import numpy as np
import pytest
from siconos_dat import read_lcp

import lemke

DATA = Path(__file__).parent / "data"


def _peer_problems():
    for case in json.loads((DATA / "drake" / "cases.json").read_text()):
        n = case["n"]
        yield pytest.param(np.array(case["M"], float).reshape(n, n), np.array(case["q"], float), id=case["name"])
    for path in sorted((DATA / "siconos" / "lcp").glob("*.dat")):
        M, q = read_lcp(path)
        yield pytest.param(M, q, id=path.stem)


@pytest.mark.parametrize("M, q", list(_peer_problems()))
def test_methods_agree_on_peer_problems(M, q):
    a = lemke.solve_lcp(M, q, method="tableau")
    b = lemke.solve_lcp(M, q, method="unrevised")
    assert a.status == b.status
    assert a.pivots == b.pivots
    scale = max([1.0, *np.abs(a.z)])
    np.testing.assert_allclose(b.z, a.z, rtol=1e-9, atol=1e-9 * scale)
    assert a.warm_start == b.warm_start
