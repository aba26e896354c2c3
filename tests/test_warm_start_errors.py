"""What bad warm starts get (issue 32, item 4): a warm start of the wrong kind, size or
structure, at every entry that takes one, is refused with a ValueError or TypeError whose
message names the argument (never a silent cold solve), and so are bad arguments of
take / relabel.  The only things accepted are those the README says are: a WarmStart is a
basis and nothing else, so any WarmStart of the right size is tried (and the answer checked),
and take's findex says only which new rows are friction rows."""
import numpy as np
import pytest
from helpers import assert_lcp_solution

import lemke


def _pd(n, seed):
    A = np.random.default_rng(seed).standard_normal((n, n))
    return A @ A.T + n * np.eye(n)


M3, q3, M4, q4 = _pd(3, 1), -np.ones(3), _pd(4, 2), -np.ones(4)
LO3, HI3, LO4, HI4 = np.zeros(3), np.full(3, np.inf), np.zeros(4), np.full(4, np.inf)
FI = np.array([-1, 0, -1, 2])  # rows 1 and 3: friction rows of the normals 0 and 2
LOF, HIF = np.array([0.0, -0.5, 0.0, -0.5]), np.array([np.inf, 0.5, np.inf, 0.5])
P, G, h = _pd(3, 3), np.eye(3), np.ones(3)
MA, MB, MC, MD = M3[:1, :1], M3[1:, 1:], M3[:1, 1:], M3[1:, :1]
GA, GB = np.array([[3.0, 0.0], [0.0, 2.0]]), np.array([[2.0, 0.0], [0.0, 3.0]])


@pytest.fixture(scope="module")
def ws():
    """The warm starts of each kind, from solved problems."""
    out = {
        "lcp3": lemke.solve_lcp(M3, q3).warm_start,
        "lcp4": lemke.solve_lcp(M4, q4).warm_start,
        "box3": lemke.solve_blcp(M3, q3, LO3, HI3).warm_start,
        "box4": lemke.solve_blcp(M4, q4, LO4, HI4).warm_start,
        "fric4": lemke.solve_blcp(M4, q4, LOF, HIF, findex=FI).warm_start,
        "batch": lemke.solve_lcp_many([M3, M4], [q3, q4]).warm_start,
        "boxbatch": lemke.solve_blcp_many([M3, M4], [q3, q4], [LO3, LO4], [HI3, HI4]).warm_start,
        "qp3": lemke.solve_qp(P, -np.ones(3), G, h).warm_start,
        "qp6": lemke.solve_qp(P, -np.ones(3), np.vstack([G, G]), np.ones(6)).warm_start,
        "game3": lemke.solve_bimatrix(np.eye(3), np.eye(3)).basis,
    }
    assert out["fric4"].friction == (1, 3)
    return out


def _lcp_many(w):
    return lemke.solve_lcp_many([M3, M4], [q3, q4], warm_start=w)


def _blcp_many(w):
    return lemke.solve_blcp_many([M3, M4], [q3, q4], [LO3, LO4], [HI3, HI4], warm_start=w)


def _qp(w, **kw):
    return lemke.solve_qp(P, -np.ones(3), G, h, warm_start=w, **kw)


def _mlcp(w):
    return lemke.solve_mlcp(MA, MB, MC, MD, q3[:1], q3[1:], warm_start=w)


# (name, call on the fixture's warm starts, exception, what the message must name)
BAD = [
    # solve_lcp: wrong size, wrong kind, not a warm start at all
    ("lcp size", lambda w: lemke.solve_lcp(M3, q3, warm_start=w["lcp4"]), ValueError, "warm_start"),
    ("lcp size unrevised", lambda w: lemke.solve_lcp(M3, q3, method="unrevised", warm_start=w["lcp4"]),
     ValueError, "warm_start"),
    ("lcp size from lists", lambda w: lemke.solve_lcp(M3.tolist(), q3.tolist(), warm_start=w["lcp4"]),
     ValueError, "warm_start"),
    ("lcp box kind", lambda w: lemke.solve_lcp(M3, q3, warm_start=w["box3"]), ValueError, "warm_start"),
    ("lcp batch kind", lambda w: lemke.solve_lcp(M3, q3, warm_start=w["batch"]), ValueError, "warm_start"),
    ("lcp list", lambda w: lemke.solve_lcp(M3, q3, warm_start=[0, 1, 2]), TypeError, "warm_start"),
    ("lcp array", lambda w: lemke.solve_lcp(M3, q3, warm_start=np.ones(3, bool)), TypeError, "warm_start"),
    # batches: one basis per problem, each of its problem's size and kind
    ("batch count", lambda w: lemke.solve_lcp_batch(np.stack([M3, M3]), np.stack([q3, q3]),
                                                    warm_start=[w["lcp3"]]), ValueError, "warm_start"),
    ("batch item size", lambda w: lemke.solve_lcp_batch(np.stack([M3, M3]), np.stack([q3, q3]),
                                                        warm_start=[w["lcp3"], w["lcp4"]]),
     ValueError, "warm_start[1]"),
    ("batch item kind", lambda w: lemke.solve_lcp_batch(np.stack([M3, M3]), np.stack([q3, q3]),
                                                        warm_start=[w["lcp3"], w["box3"]]),
     ValueError, "warm_start"),
    ("many sizes", lambda w: lemke.solve_lcp_many([M4, M3], [q4, q3], warm_start=w["batch"]),
     ValueError, "warm_start[0]"),
    ("many packed sizes", lambda w: lemke.solve_lcp_many(
        np.concatenate([M4.ravel(), M3.ravel()]), np.concatenate([q4, q3]), sizes=[4, 3],
        warm_start=w["batch"]), ValueError, "warm_start[0]"),
    ("many count", lambda w: lemke.solve_lcp_many([M3, M4, M3], [q3, q4, q3], warm_start=w["batch"]),
     ValueError, "warm_start"),
    ("many box batch", lambda w: _lcp_many(w["boxbatch"]), ValueError, "warm_start"),
    ("many one basis", lambda w: _lcp_many(w["lcp3"]), ValueError, "warm_start"),
    ("many list sizes", lambda w: _lcp_many([w["lcp4"], w["lcp3"]]), ValueError, "warm_start[0]"),
    # box LCPs: size, kind, friction rows (a changed number of rows needs take / relabel)
    ("blcp lcp kind", lambda w: lemke.solve_blcp(M4, q4, LO4, HI4, warm_start=w["lcp4"]),
     ValueError, "warm_start"),
    ("blcp size", lambda w: lemke.solve_blcp(M4, q4, LO4, HI4, warm_start=w["box3"]),
     ValueError, "relabel"),
    ("blcp size from lists", lambda w: lemke.solve_blcp(M4.tolist(), q4.tolist(), 0.0, np.inf,
                                                        warm_start=w["box3"]), ValueError, "warm_start"),
    ("blcp friction basis, no findex", lambda w: lemke.solve_blcp(M4, q4, LO4, HI4, warm_start=w["fric4"]),
     ValueError, "warm_start"),
    ("blcp plain basis, findex", lambda w: lemke.solve_blcp(M4, q4, LOF, HIF, findex=FI, warm_start=w["box4"]),
     ValueError, "warm_start"),
    ("blcp other friction rows", lambda w: lemke.solve_blcp(M4, q4, LOF, HIF, findex=np.array([-1, -1, -1, 2]),
                                                            warm_start=w["fric4"]), ValueError, "warm_start"),
    ("blcp batch kind", lambda w: lemke.solve_blcp(M4, q4, LO4, HI4, warm_start=w["boxbatch"]),
     ValueError, "warm_start"),
    ("blcp list", lambda w: lemke.solve_blcp(M4, q4, LO4, HI4, warm_start=[0, 1, 2, 3]), TypeError, "warm_start"),
    ("blcp_many sizes", lambda w: lemke.solve_blcp_many([M4, M3], [q4, q3], [LO4, LO3], [HI4, HI3],
                                                        warm_start=w["boxbatch"]), ValueError, "warm_start[0]"),
    ("blcp_many lcp batch", lambda w: _blcp_many(w["batch"]), ValueError, "warm_start"),
    ("blcp_many list sizes", lambda w: _blcp_many([w["box4"], w["box3"]]), ValueError, "warm_start[0]"),
    ("blcp_many list kind", lambda w: _blcp_many([w["lcp3"], w["box4"]]), ValueError, "warm_start[0]"),
    ("blcp_many one basis", lambda w: _blcp_many(w["box3"]), ValueError, "warm_start"),
    # QPs: kind, number of pairs, initvals
    ("qp box kind", lambda w: _qp(w["box3"]), ValueError, "warm_start"),
    ("qp batch kind", lambda w: _qp(w["batch"]), ValueError, "warm_start"),
    ("qp pairs", lambda w: _qp(w["qp6"]), ValueError, "warm_start"),
    ("qp pairs unrevised", lambda w: _qp(w["qp6"], method="unrevised"), ValueError, "warm_start"),
    ("qp lcp basis of 4", lambda w: _qp(w["lcp4"]), ValueError, "warm_start"),
    ("qp list", lambda w: _qp([0, 1]), TypeError, "warm_start"),
    ("qp box kind from lists", lambda w: lemke.solve_qp(P.tolist(), [-1.0] * 3, G.tolist(), [1.0] * 3,
                                                        warm_start=w["box3"]), ValueError, "warm_start"),
    ("qp initvals shape", lambda w: _qp(None, initvals=np.zeros(4)), ValueError, "initvals"),
    ("qp initvals nan", lambda w: _qp(None, initvals=np.array([0.0, np.nan, 0.0])), ValueError, "initvals"),
    ("qp both", lambda w: _qp(w["qp3"], initvals=np.zeros(3)), ValueError, "initvals"),
    # MLCPs and games
    ("mlcp pairs", lambda w: _mlcp(w["lcp3"]), ValueError, "warm_start"),
    ("mlcp box kind", lambda w: _mlcp(w["box3"]), ValueError, "warm_start"),
    ("game lcp kind", lambda w: lemke.solve_bimatrix(GA, GB, warm_start=w["lcp3"]), ValueError, "warm_start"),
    ("game size", lambda w: lemke.solve_bimatrix(GA, GB, warm_start=w["game3"]), ValueError, "warm_start"),
    ("game list", lambda w: lemke.solve_bimatrix(GA, GB, warm_start=[0, 1]), ValueError, "warm_start"),
    # take / relabel
    ("take range", lambda w: w["lcp3"].take([0, 5]), ValueError, "indices"),
    ("take 2-D", lambda w: w["lcp3"].take([[0, 1]]), TypeError, "indices"),
    ("relabel int arrays length", lambda w: w["lcp3"].relabel(np.array([1, 2]), np.array([1, 2])),
     ValueError, "old_labels"),
    ("relabel int arrays twice", lambda w: w["lcp3"].relabel(np.array([1, 2, 3]), np.array([1, 1])),
     ValueError, "new_labels"),
    ("box take range", lambda w: w["fric4"].take([0, 9], findex=np.array([-1, 0])), ValueError, "indices"),
    ("box take findex length", lambda w: w["fric4"].take([0, 1], findex=np.array([-1])), ValueError, "findex"),
    ("box take kind", lambda w: w["fric4"].take([0, 1, 2, 3], findex=np.array([-1, -1, -1, 2])),
     ValueError, "findex"),
    ("box take findex omitted", lambda w: w["fric4"].take([0, 1, 2, 3]), ValueError, "findex"),
    ("box relabel length", lambda w: w["fric4"].relabel([1, 2], [1, 2], findex=FI[:2]), ValueError, "old_labels"),
    ("box relabel twice", lambda w: w["fric4"].relabel(np.arange(4), np.array([1, 1]), findex=np.array([-1, -1])),
     ValueError, "new_labels"),
    ("box relabel kind", lambda w: w["fric4"].relabel(np.arange(4), np.arange(4), findex=np.array([-1, -1, -1, 2])),
     ValueError, "findex"),
    ("box batch take sizes", lambda w: w["boxbatch"].take([0, 1, 2], sizes=[2, 2]), ValueError, "sizes"),
    ("box batch take range", lambda w: w["boxbatch"].take([0, 99], sizes=[2]), ValueError, "indices"),
    ("box batch relabel length", lambda w: w["boxbatch"].relabel(np.arange(3), np.arange(3), sizes=[3]),
     ValueError, "old_labels"),
    ("box batch relabel twice", lambda w: w["boxbatch"].relabel(np.arange(7), np.array([1, 1]), sizes=[2]),
     ValueError, "new_labels"),
    ("row states code", lambda w: lemke.BoxWarmStart.from_row_states(np.array([0, 30, 0])), ValueError, "states"),
    ("row states float", lambda w: lemke.BoxWarmStart.from_row_states([0.5, 0, 0]), TypeError, "states"),
]


@pytest.mark.parametrize("call, exc, names", [c[1:] for c in BAD], ids=[c[0] for c in BAD])
def test_a_bad_warm_start_is_refused_by_name(ws, call, exc, names):
    with pytest.raises(exc) as info:
        call(ws)
    assert type(info.value) is exc, info.value  # not a subclass standing in for another
    assert names in str(info.value), str(info.value)


def test_what_is_accepted_is_what_the_readme_says(ws):
    """A WarmStart is only a basis: one of the right size from another kind of problem (a QP's
    3 pairs for an LCP of 3 rows) is tried like any other and the answer is checked; take's
    findex names only which new rows are friction rows (its normals' indices are not read)."""
    r = lemke.solve_lcp(M3, q3, warm_start=ws["qp3"])
    assert r.success
    assert_lcp_solution(M3, q3, r.z)
    a = ws["fric4"].take([0, 1], findex=np.array([-1, 0]))
    b = ws["fric4"].take([0, 1], findex=np.array([-1, 5]))
    assert a == b and a.friction == (1,)
