"""A batch over a Dask cluster gives the one-machine answer bit for bit (LocalCluster with
worker processes, so the problems really cross a process boundary).  Skipped only where
dask's distributed scheduler is not installed (the test extra installs it)."""
import numpy as np
import pytest

import lemke
from lemke import problems

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=50)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def _family(B, n, seed):
    """Contact-like LCPs (rank-deficient, ties; some without solution) and a shared PD M."""
    rng = np.random.default_rng(seed)
    pairs = [problems.contact_like(n, rng) for _ in range(B)]
    return np.stack([M for M, _ in pairs]), np.stack([q for _, q in pairs])


def _independent_check(M, q, z, status):
    """The LCP conditions, recomputed here in numpy for every solved problem."""
    for b in np.flatnonzero(status == lemke.Status.SOLVED):
        Mb = M if M.ndim == 2 else M[b]
        w = Mb @ z[b] + q[b]
        scale = np.abs(Mb) @ np.abs(z[b]) + np.abs(q[b]) + 1.0
        assert (z[b] >= 0).all() and (w >= -1e-9 * scale).all()
        assert (np.abs(np.minimum(z[b], w)) <= 1e-9 * scale).all()


@pytest.mark.parametrize("chunk_size", [None, 1, 7, 100])
def test_dask_matches_one_machine_bit_for_bit(client, method, chunk_size):
    M, Q = _family(40, 9, 1)
    here = lemke.solve_lcp_batch(M, Q, method=method, workers=1)
    there = lemke.solve_lcp_batch_dask(M, Q, method=method, chunk_size=chunk_size, client=client)
    assert there == here  # every array, bit for bit
    assert (there.status == lemke.Status.SOLVED).sum() >= 20
    _independent_check(M, Q, there.z, there.status)
    one = lemke.solve_lcp(M[3], Q[3], method=method)
    assert one.pivots == there.pivots[3] and np.array_equal(one.z, there.z[3])


def test_dask_shared_matrix_and_warm_starts(client):
    rng = np.random.default_rng(2)
    A = rng.normal(size=(12, 12))
    M = A @ A.T + 0.1 * np.eye(12)
    Q = rng.normal(size=(30, 12))
    first = [lemke.solve_lcp(M, qb) for qb in Q]
    ws = [r.warm_start if b % 3 else None for b, r in enumerate(first)]
    Q2 = Q + 1e-3 * rng.normal(size=Q.shape)
    here = lemke.solve_lcp_batch(M, Q2, warm_start=ws, workers=2)
    there = lemke.solve_lcp_batch_dask(M, Q2, warm_start=ws, chunk_size=4, client=client)
    assert there == here
    _independent_check(M, Q2, there.z, there.status)
    assert there.pivots[1] < first[1].pivots  # a warm start really ran on the worker


def test_dask_bad_input_names_the_problem(client):
    M, Q = _family(5, 4, 3)
    Q[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"q has a NaN or infinite entry at index \(3, 1\)"):
        lemke.solve_lcp_batch_dask(M, Q, client=client)
    with pytest.raises(ValueError, match="chunk_size"):
        lemke.solve_lcp_batch_dask(M[:2], Q[:2] * 0, chunk_size=0, client=client)
    with pytest.raises(ValueError, match="warm_start"):
        lemke.solve_lcp_batch_dask(M[:2], Q[:2] * 0, warm_start=[None], client=client)


def test_dask_empty_batch(client):
    r = lemke.solve_lcp_batch_dask(np.eye(3), np.zeros((0, 3)), client=client)
    assert r.z.shape == (0, 3) and r.status.shape == (0,)


def test_dask_without_a_client_says_so(monkeypatch):
    def no_client():
        raise ValueError("No clients found")

    monkeypatch.setattr(distributed, "get_client", no_client)
    with pytest.raises(ValueError, match="no Dask client: pass client="):
        lemke.solve_lcp_batch_dask(np.eye(2), np.ones((1, 2)))
