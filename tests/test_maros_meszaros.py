"""solve_qp on the 62 dense Maros-Meszaros problems (tests/data/maros-meszaros).

Each solved problem must pass the tests' own KKT check and match the reference optimum of
the data's README.  VALUES is the one exception: its P is indefinite as stored, and
solve_qp refuses it."""
import sys
from pathlib import Path

import numpy as np
import pytest

import lemke
from helpers import assert_qp_kkt

HERE = Path(__file__).resolve().parent
DATA = HERE / "data" / "maros-meszaros"
sys.path.insert(0, str(HERE.parent / "benchmarks"))
from maros_meszaros import load, references  # noqa: E402

REFS = references(DATA / "README.md")
NAMES = sorted(p.stem for p in DATA.glob("*.mat"))


def test_all_62_are_here():
    assert len(NAMES) == 62


@pytest.mark.parametrize("name", NAMES)
def test_problem(name):
    problem, r = load(DATA / f"{name}.mat")
    if name == "VALUES":
        with pytest.raises(ValueError, match="not positive semidefinite"):
            lemke.solve_qp(*problem)
        return
    res = lemke.solve_qp(*problem)
    assert res.status == lemke.Status.SOLVED, res
    assert_qp_kkt(*problem, res, rtol=1e-8)
    ref = REFS[name]
    f = res.obj + r
    if ref is not None:
        assert f == pytest.approx(ref, rel=1e-9, abs=1e-9)
