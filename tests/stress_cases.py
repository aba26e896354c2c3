"""The problems of the stress suite (test_cycling.py), each named by a key ``family/name``.

Shared by the tests and by their solver process (stress_worker.py), which both build a
problem from its key, so that only keys and results cross the pipe.  Nothing here calls
lemke except the contact simulation, which advances its scene with lemke's answers.
"""
from __future__ import annotations

import functools
import itertools
import json
import zlib
from pathlib import Path
from typing import Callable, NamedTuple

import numpy as np

import contact_sim
from lemke import problems
from siconos_dat import read_lcp
from test_peer_siconos import RAY_FILES as SICONOS_RAY_FILES

DATA = Path(__file__).parent / "data"
MURTY_N = 12


class Case(NamedTuple):
    family: str
    name: str
    load: Callable[[], tuple[np.ndarray, np.ndarray]]
    expect: str  # "solved", "ray" or "either"
    options: tuple = ()  # base options, as sorted (key, value) pairs
    uses_lemke: bool = False  # built with lemke's answers (the contact simulation)

    @property
    def key(self):
        return f"{self.family}/{self.name}"


def _json_cases(path):
    for case in json.loads(path.read_text()):
        n = case["n"]
        yield case, np.array(case["M"], dtype=float).reshape(n, n), np.array(case["q"], dtype=float)


def _const(M, q):
    M.setflags(write=False)
    q.setflags(write=False)
    return lambda: (M, q)


def _dart_cases():
    for case, M, q in _json_cases(DATA / "dart" / "lemke_cases.json"):
        yield Case("dart", case["name"], _const(M, q), "solved")


def _murty_cases():
    p = problems.murty(MURTY_N)
    yield Case("murty", f"murty-{MURTY_N}", _const(np.array(p.M), np.array(p.q)), "solved",
               (("max_pivots", 2**MURTY_N + 100),))


def _siconos_cases():
    # The same expectations as test_peer_siconos.py: two files end on a ray.
    for path in sorted((DATA / "siconos" / "lcp").glob("*.dat")):
        M, q = read_lcp(path)
        yield Case("siconos", path.stem, _const(M, q), "ray" if path.name in SICONOS_RAY_FILES else "solved")


def _drake_expect(case):
    if case["expect"] == "solution":
        return "solved"
    # TestProblem4: a bimatrix game (solvable) on which Lemke with d = 1 rays, so either;
    # TestFailure: infeasible, a ray (see test_peer_drake.py).
    return "either" if "known_solution" in case else "ray"


def _drake_cases():
    for case, M, q in _json_cases(DATA / "drake" / "cases.json"):
        yield Case("drake", case["name"], _const(M, q), _drake_expect(case))


def integer_problem(n, seed, p_matrix):
    """M with entries in {-1, 0, 1, 2} and q in {-1, 0, 1} (at least one -1); with
    ``p_matrix``, M + diag(row abs sum + 1): strictly row diagonally dominant with a
    positive diagonal, hence a P-matrix."""
    rng = np.random.default_rng([n, seed, int(p_matrix)])
    M = rng.integers(-1, 3, (n, n)).astype(float)
    q = rng.integers(-1, 2, n).astype(float)
    q[rng.integers(n)] = -1.0
    if p_matrix:
        M += np.diag(np.abs(M).sum(axis=1) + 1.0)
    return M, q


INT_SIZES = range(4, 13)
INT_SEEDS = range(6)


def _integer_cases():
    for p_matrix in (False, True):
        for n, seed in itertools.product(INT_SIZES, INT_SEEDS):
            load = functools.partial(integer_problem, n, seed, p_matrix)
            yield Case("int-p" if p_matrix else "int", f"n{n}-s{seed}", load, "solved" if p_matrix else "either")


# Scenes of the contact simulation: (label, seed, bodies, with boxes, steps).  A sequence
# depends on lemke's answers (see contact_sim).  In "pile" the pivoting rule before issue 11
# fails from step 25 on, and the bodies, advanced without impulses, fall into each other:
# deep overlaps and large redundant contact sets.
CONTACT_SCENES = [("disks", 1, 30, False, 60), ("mixed", 3, 20, True, 60), ("pile", 0, 20, True, 40)]


@functools.lru_cache(maxsize=None)
def contact_sequence(seed, bodies, boxes, steps):
    out = contact_sim.step_lcps(seed, bodies, steps, boxes)
    for M, q in out:
        M.setflags(write=False)
        q.setflags(write=False)
    return out


def _contact_cases():
    for label, seed, bodies, boxes, steps in CONTACT_SCENES:
        for k in range(steps):
            load = (lambda s=seed, b=bodies, x=boxes, t=steps, k=k: contact_sequence(s, b, x, t)[k])
            yield Case("contact", f"{label}-step{k:03d}", load, "solved", uses_lemke=True)


BASE_CASES = [*_dart_cases(), *_murty_cases(), *_siconos_cases(), *_drake_cases(), *_integer_cases(),
              *_contact_cases()]
BY_KEY = {c.key: c for c in BASE_CASES}

# The subset that is scaled and permuted.
SCALED_BASES = (
    [c.key for c in BASE_CASES if c.family in ("dart", "murty")]
    + [f"int/n{n}-s0" for n in INT_SIZES] + [f"int-p/n{n}-s0" for n in INT_SIZES]
    + [f"drake/unrevised_{name}" for name in ("TestCycling", "TestPSD", "TestProblem1", "TestProblem3",
                                              "TestProblem6_l100", "TestProblem4")]
    + [f"siconos/{name}" for name in ("lcp_CPS_1", "lcp_CPS_3", "lcp_deudeu", "lcp_exp_murty", "lcp_mmc",
                                      "lcp_tobenna", "lcp_enum_fails")]
    + [f"contact/{name}" for name in ("disks-step030", "mixed-step045", "pile-step020")]
)
SCALINGS = ["times1e-6", "times1e6", "rowcol-a", "rowcol-b", "perm-a", "perm-b", "perm-rowcol"]


def scaling(n, how, key):
    """The copy ``how`` of a problem of size n as ``(p, d1, d2)``: the copy is
    ``M' = D1 P M P' D2``, ``q' = D1 P q`` (``P M P'`` is ``M[p][:, p]``), whose solutions are
    ``z' = D2^-1 P z``.  ``times<c>``: d1 = c, d2 = 1; ``rowcol``: factors 10^u, u uniform in
    [-6, 6]; ``perm``: a random permutation; ``perm-rowcol``: both.  Seeded by the names,
    so every run and every process sees the same copies."""
    rng = np.random.default_rng(zlib.crc32(f"{key}:{how}".encode()))
    p, d1, d2 = np.arange(n), np.ones(n), np.ones(n)
    if how.startswith("times"):
        d1[:] = float(how[len("times"):])
    if "perm" in how:
        p = rng.permutation(n)
    if "rowcol" in how:
        d1 = 10.0 ** rng.uniform(-6.0, 6.0, n)
        d2 = 10.0 ** rng.uniform(-6.0, 6.0, n)
    return p, d1, d2


def transform(M, q, how, key):
    """``(M', q')`` of the copy ``how`` (see :func:`scaling`)."""
    p, d1, d2 = scaling(q.size, how, key)
    return d1[:, None] * M[np.ix_(p, p)] * d2[None, :], d1 * q[p]


def _scaled_cases():
    for base in SCALED_BASES:
        c = BY_KEY[base]
        for how in SCALINGS:
            load = (lambda c=c, how=how: transform(*c.load(), how, c.key))
            yield Case("scaled", f"{how}:{c.key}", load, c.expect, c.options, c.uses_lemke)


SCALED_CASES = list(_scaled_cases())
CASES = BASE_CASES + SCALED_CASES
ALL = {c.key: c for c in CASES}


@functools.lru_cache(maxsize=None)
def problem(key):
    """``(M, q)`` of case ``key``, float64 and C-contiguous."""
    M, q = ALL[key].load()
    return np.ascontiguousarray(M, dtype=float), np.ascontiguousarray(q, dtype=float)


def p_matrix(kind, n, rng):
    """A P-matrix: positive definite symmetric part plus a skew part (``"pd"``), or strictly
    row diagonally dominant with a positive diagonal (``"dd"``)."""
    if kind == "pd":
        B = rng.standard_normal((n, n))
        C = rng.standard_normal((n, n))
        return B @ B.T / n + 0.1 * np.eye(n) + (C - C.T) / n
    A = rng.standard_normal((n, n))
    np.fill_diagonal(A, 0.0)
    return A + np.diag(np.abs(A).sum(axis=1) + rng.uniform(0.1, 1.0, n))
