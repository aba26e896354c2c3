"""The acceptance rule is one rule: the check fused into the kernels' solve gives the
verdict of the public check (lemke._certify), and the tolerance constants are shared."""
import numpy as np
import pytest

import lemke
from lemke import _certify


def test_constants_are_shared():
    from lemke import _core
    assert _certify.CERTIFIABLE is _core.CERTIFIABLE and _core.CERTIFIABLE == 1000.0  # (the oracle's constant)


@pytest.mark.parametrize("seed", range(20))
def test_fused_check_agrees_with_the_public_check(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 12))
    A = rng.standard_normal((n, n))
    M, q = A @ A.T + 1e-3 * np.eye(n), rng.standard_normal(n)
    res = lemke.solve_lcp(M, q)
    assert res.success == lemke.is_lcp_solution(M, q, res.z)
    # A point nudged just outside the allowance fails both; the fused check rejects it too.
    z = np.array(res.z)
    k = int(np.argmax(z))
    if z[k] > 0:
        z[k] *= 1 + 1e-6
        w = M @ z + q
        _, ok, _ = _certify.check_lcp(M, q, z, 1e-9)
        assert ok == lemke.is_lcp_solution(M, q, z)
        assert not ok or abs(w[k]) <= 1e-6 * (np.abs(M[k]) @ np.abs(z) + abs(q[k]))
