"""Independent checks used by the tests (deliberately not lemke's own certify code)."""
import numpy as np


def assert_lcp_solution(M, q, z, rtol=1e-8):
    """Assert z >= 0, w = Mz + q >= 0 and z'w = 0, each relative to the problem's scale."""
    M = np.asarray(M, dtype=float)
    q = np.asarray(q, dtype=float)
    z = np.asarray(z, dtype=float)
    assert z.shape == q.shape
    if q.size == 0:
        return
    w = M @ z + q
    z_scale = max(np.abs(z).max(), np.finfo(float).tiny)
    w_scale = max(np.abs(q).max(), np.abs(M).max() * np.abs(z).max())
    assert z.min() >= -rtol * z_scale, f"z has a negative entry {z.min()}"
    assert w.min() >= -rtol * w_scale, f"w = Mz + q has a negative entry {w.min()} (scale {w_scale})"
    worst = np.max(np.abs(z * w))
    assert worst <= rtol * z_scale * w_scale, f"z'w is not 0: max |z_i w_i| = {worst}"


def assert_ray(M, q, d, z, z0, ray, rtol=1e-8):
    """Assert that (z, z0) + t * ray stays almost complementary and feasible for all t >= 0."""
    M = np.asarray(M, dtype=float)
    n = len(q)
    ray = np.asarray(ray, dtype=float)
    dz, dz0 = ray[:n], ray[n]
    scale = np.abs(ray).max()
    assert scale > 0, "the ray direction is zero"
    assert dz.min() >= -rtol * scale and dz0 >= -rtol * scale, "the ray leaves z >= 0"
    u = M @ z + q + d * z0
    du = M @ dz + d * dz0
    u_scale = max(np.abs(q).max(), np.abs(M).max() * max(np.abs(z).max(), 1e-300), np.abs(d).max() * z0)
    du_scale = max(np.abs(M).max(), np.abs(d).max()) * scale
    assert u.min() >= -rtol * u_scale, "the ray's start is infeasible"
    assert du.min() >= -rtol * du_scale, "w decreases along the ray"
    for a, b, sa, sb in ((z, u, 1.0, u_scale), (z, du, 1.0, du_scale), (dz, u, scale, u_scale), (dz, du, scale, du_scale)):
        assert np.max(np.abs(a * b)) <= rtol * max(sa, np.abs(z).max()) * sb, "complementarity fails along the ray"
