"""A reproducible MPC problem sequence (benchmarks/bench_mpc.py, tests/test_qp_warm.py).

Two masses on a line joined by a spring, each pushed by its own force: the state
(p1, p2, v1, v2), the input (u1, u2), semi-implicit Euler with dt = 0.1.  The horizon of
N = 10 stages gives the decision vector [u_0, x_1, u_1, x_2, ..., u_9, x_10]: 60
variables, 40 equalities (the dynamics, x_0 in b), 20 inequalities (the spring's stretch
p1 - p2 <= 0.8 at every stage, and v1 + v2 <= 1.5 at the even stages: h = +inf at the odd
ones, qpsolvers' "no constraint"), and bounds (|u| <= 3, |p| <= 1, v <= 2 with no lower
bound on v).  The positions track a moving reference that leaves the bounds at times, so
bounds and rows come and go from the active set.  P, G, A, h, lb, ub stay; q (the
reference) and b (the measured state) move every step.
"""
from __future__ import annotations

import numpy as np

NX, NU, N = 4, 2, 10
DT = 0.1


def dynamics():
    """(Ad, Bd): semi-implicit Euler, v+ = v + dt (K p + D v + u), p+ = p + dt v+."""
    k, c = 4.0, 0.3  # spring, damping
    K = np.array([[-k, k], [k, -k]])
    D = -c * np.eye(2)
    Av = np.hstack([DT * K, np.eye(2) + DT * D])  # v+ from (p, v)
    Ap = np.hstack([np.eye(2), np.zeros((2, 2))]) + DT * Av
    Ad = np.vstack([Ap, Av])
    Bd = np.vstack([DT * DT * np.eye(2), DT * np.eye(2)])
    return Ad, Bd


def matrices():
    """(P, G, h, A, lb, ub) and the maps (x0 -> b, reference -> q)."""
    Ad, Bd = dynamics()
    nz = N * (NU + NX)
    Qx = np.diag([10.0, 10.0, 0.5, 0.5])
    Ru = 0.1 * np.eye(NU)
    P = np.zeros((nz, nz))
    for k in range(N):
        u = k * (NU + NX)
        x = u + NU
        P[u:u + NU, u:u + NU] = Ru
        P[x:x + NX, x:x + NX] = Qx * (5.0 if k == N - 1 else 1.0)
    A = np.zeros((N * NX, nz))
    for k in range(N):
        u = k * (NU + NX)
        x = u + NU
        A[k * NX:(k + 1) * NX, x:x + NX] = np.eye(NX)
        A[k * NX:(k + 1) * NX, u:u + NU] = -Bd
        if k > 0:
            A[k * NX:(k + 1) * NX, x - NU - NX:x - NU] = -Ad
    G = np.zeros((2 * N, nz))
    h = np.zeros(2 * N)
    for k in range(N):
        x = k * (NU + NX) + NU
        G[k, x] = 1.0
        G[k, x + 1] = -1.0
        h[k] = 0.8
        G[N + k, x + 2] = G[N + k, x + 3] = 1.0
        h[N + k] = 1.5 if k % 2 == 0 else np.inf
    lb = np.empty(nz)
    ub = np.empty(nz)
    for k in range(N):
        u = k * (NU + NX)
        lb[u:u + NU], ub[u:u + NU] = -3.0, 3.0
        lb[u + NU:u + NU + 2], ub[u + NU:u + NU + 2] = -1.0, 1.0
        lb[u + NU + 2:u + NU + 4], ub[u + NU + 2:u + NU + 4] = -np.inf, 2.0
    return P, G, h, A, lb, ub, Ad, Bd, Qx


def sequence(steps=100, seed=0):
    """``(P, G, h, A, lb, ub)`` and a list of ``steps`` pairs ``(q, b)``: the closed loop of
    the MPC controller (each step's first input applied, plus a small seeded disturbance)
    on a reference that moves, computed once here (by lemke, cold) so that every solver
    gets the same problems."""
    import lemke

    P, G, h, A, lb, ub, Ad, Bd, Qx = matrices()
    rng = np.random.default_rng(seed)
    x0 = np.array([0.2, -0.2, 0.0, 0.0])
    out = []
    for t in range(steps):
        q = np.zeros(P.shape[0])
        for k in range(N):
            x = k * (NU + NX) + NU
            s = (t + k + 1) * DT
            ref = np.array([1.3 * np.sin(0.8 * s), 1.3 * np.sin(0.8 * s + 1.0), 0.0, 0.0])
            q[x:x + NX] = -(P[x:x + NX, x:x + NX] @ ref)
        b = np.zeros(A.shape[0])
        b[:NX] = Ad @ x0
        out.append((q, b))
        r = lemke.solve_qp(P, q, G, h, A, b, lb, ub)
        assert r.status == lemke.Status.SOLVED, r
        u0 = r.x[:NU]
        x0 = Ad @ x0 + Bd @ u0 + 0.002 * rng.standard_normal(NX)
    return (P, G, h, A, lb, ub), out
