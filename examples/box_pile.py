#!/usr/bin/env python
"""Disks falling into a bin with friction: one box LCP with a friction index per time step.

A small 2-D rigid-body engine of the kind ODE and Bullet are (velocity-level time
stepping, Stewart-Trinkle/Anitescu-Potra): at every step the contact impulses lambda solve
the box LCP

    w = A lambda + b,   A = J W J',   b = J (u + h W f) + stabilization,

with J the contact Jacobian (a normal row and a tangent row per contact), W the inverse
mass matrix, u the velocities and f gravity.  A normal row has 0 <= lambda_n (w_n is the
separating velocity after the step); its tangent row has the friction index pointing at it,
``-mu lambda_n <= lambda_t <= mu lambda_n`` (``lemke.solve_blcp(..., findex=...)``, mu
folded into lo/hi as ODE and Bullet do).  Each step is warm-started from the previous
step's final basis when the contact set has the same size.

Run ``python examples/box_pile.py [--steps 300] [--out box_pile.png]``: it writes a PNG with
snapshots of the pile, the energy, the contact impulses, and the pivots and solve time of
every step.  :func:`slope` is the textbook check: a box on an inclined plane sticks when
mu > tan(angle) and otherwise slides with acceleration g (sin a - mu cos a).
"""
from __future__ import annotations

import argparse
import time
from dataclasses import dataclass, field

import numpy as np

import lemke

G = 9.81


@dataclass
class World:
    """Bodies (disks of radius r > 0, or boxes of half extents ``half`` when r = 0), a
    floor y = 0 and, when ``width`` is set, walls x = 0 and x = width."""

    pos: np.ndarray  # (N, 2)
    ang: np.ndarray  # (N,)
    vel: np.ndarray  # (N, 2)
    omega: np.ndarray  # (N,)
    mass: np.ndarray
    inertia: np.ndarray  # np.inf: the body does not rotate
    radius: np.ndarray  # 0 for a box
    half: np.ndarray  # (N, 2) half extents of a box
    mu: float
    width: float | None = None
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, -G]))
    margin: float = 0.02  # contacts are kept while closer than this
    # Constraint force mixing: A + cfm diag(A), as ODE's CFM (default 1e-5 there).  A pile
    # with redundant contacts has a singular A; at cfm = 1e-9 some steps' bases have condition
    # numbers near 1e10 and their answers cannot be certified to 1e-9 (the solver then says
    # NUMERICAL_FAILURE rather than return a wrong answer).
    cfm: float = 1e-6


def contacts(world: World):
    """The contacts: a list of (a, b, point, normal, gap) with b = -1 for the static
    world; the normal points from b to a.  Ordered by (a, b, feature) so that the rows of
    consecutive steps line up for warm starts."""
    out = []
    N = world.pos.shape[0]
    planes = [(np.array([0.0, 1.0]), 0.0)]
    if world.width is not None:
        planes += [(np.array([1.0, 0.0]), 0.0), (np.array([-1.0, 0.0]), -world.width)]
    for a in range(N):
        c = world.pos[a]
        if world.radius[a] > 0:
            for n, off in planes:
                gap = n @ c - off - world.radius[a]
                if gap < world.margin:
                    out.append((a, -1, c - n * world.radius[a], n, gap))
        else:
            ca, sa = np.cos(world.ang[a]), np.sin(world.ang[a])
            R = np.array([[ca, -sa], [sa, ca]])
            for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = c + R @ (world.half[a] * (sx, sy))
                for n, off in planes:
                    gap = n @ p - off
                    if gap < world.margin:
                        out.append((a, -1, p, n, gap))
    for a in range(N):
        for b in range(a + 1, N):
            if world.radius[a] > 0 and world.radius[b] > 0:
                d = world.pos[a] - world.pos[b]
                dist = np.hypot(*d)
                gap = dist - world.radius[a] - world.radius[b]
                if gap < world.margin and dist > 0:
                    n = d / dist
                    out.append((a, b, world.pos[b] + n * world.radius[b], n, gap))
    return out


def _jac_row(world, a, b, p, dirn):
    """The Jacobian row of the relative velocity of a against b at p along dirn."""
    N = world.pos.shape[0]
    row = np.zeros(3 * N)
    for body, sign in ((a, 1.0), (b, -1.0)):
        if body < 0:
            continue
        r = p - world.pos[body]
        row[3 * body: 3 * body + 2] += sign * dirn
        row[3 * body + 2] += sign * (r[0] * dirn[1] - r[1] * dirn[0])
    return row


def step(world: World, h: float, warm=None, cold=None):
    """Advance one step of length h; returns (impulses, contacts, result, seconds).  With
    ``cold`` (a list), the step's LCP is also solved cold, for comparison, and
    ``(pivots, seconds)`` of that solve appended to it."""
    N = world.pos.shape[0]
    cs = contacts(world)
    u = np.column_stack([world.vel, world.omega]).reshape(-1)
    winv = np.column_stack([1 / world.mass, 1 / world.mass, 1 / world.inertia]).reshape(-1)
    f = np.column_stack([world.mass[:, None] * world.gravity[None, :], np.zeros(N)]).reshape(-1)
    u_free = u + h * winv * f
    k = len(cs)
    if k == 0:
        lam, res, secs = np.zeros(0), None, 0.0
        u_new = u_free
        if cold is not None:
            cold.append((0, 0.0))
    else:
        J = np.zeros((2 * k, 3 * N))
        stab = np.zeros(2 * k)
        lo = np.zeros(2 * k)
        hi = np.full(2 * k, np.inf)
        findex = -np.ones(2 * k, dtype=np.int64)
        for c, (a, b, p, n, gap) in enumerate(cs):
            t = np.array([-n[1], n[0]])
            J[2 * c] = _jac_row(world, a, b, p, n)
            J[2 * c + 1] = _jac_row(world, a, b, p, t)
            # An open contact may close during the step but not overlap; an overlap (from
            # linearizing curved contacts) is kept from growing, not pushed out: a
            # Baumgarte term (negative b) can make a squeezed body's LCP infeasible.
            stab[2 * c] = max(gap, 0.0) / h
            lo[2 * c + 1], hi[2 * c + 1] = -world.mu, world.mu
            findex[2 * c + 1] = 2 * c
        A = (J * winv) @ J.T
        A += world.cfm * np.diag(np.diag(A).clip(min=1e-12))
        bvec = J @ u_free + stab
        if warm is not None and warm.n != 2 * k + 2 * k:
            warm = None
        t0 = time.perf_counter()
        res = lemke.solve_blcp(A, bvec, lo, hi, findex=findex, warm_start=warm)
        secs = time.perf_counter() - t0
        if cold is not None:
            t1 = time.perf_counter()
            rc = lemke.solve_blcp(A, bvec, lo, hi, findex=findex)
            cold.append((rc.pivots, time.perf_counter() - t1))
        if not res.success:
            raise RuntimeError(f"contact LCP not solved: {res}")
        lam = np.asarray(res.z)
        u_new = u_free + winv * (J.T @ lam)
    uv = u_new.reshape(N, 3)
    world.vel = uv[:, :2].copy()
    world.omega = np.where(np.isfinite(world.inertia), uv[:, 2], 0.0)
    world.pos = world.pos + h * world.vel
    world.ang = world.ang + h * world.omega
    return lam, cs, res, secs


def energy(world: World) -> float:
    rot = np.where(np.isfinite(world.inertia), world.inertia, 0.0) * world.omega ** 2
    kin = 0.5 * (world.mass * (world.vel ** 2).sum(axis=1) + rot)
    return float(kin.sum() - (world.mass * (world.pos @ world.gravity)).sum())


def pile_world(n_disks=12, width=1.0, mu=0.5, seed=0) -> World:
    """Disks of radius 0.06-0.1 dropped from a grid above a bin of the given width."""
    rng = np.random.default_rng(seed)
    r = rng.uniform(0.06, 0.1, n_disks)
    cols = max(1, int(width / 0.22))
    pos = np.array([[0.15 + 0.2 * (i % cols) + 0.03 * rng.standard_normal(),
                     0.2 + 0.22 * (i // cols)] for i in range(n_disks)])
    pos[:, 0] = pos[:, 0].clip(r + 0.01, width - r - 0.01)
    m = np.pi * r ** 2 * 100.0
    return World(pos=pos, ang=np.zeros(n_disks), vel=np.zeros((n_disks, 2)),
                 omega=np.zeros(n_disks), mass=m, inertia=0.5 * m * r ** 2, radius=r,
                 half=np.zeros((n_disks, 2)), mu=mu, width=width)


def simulate(n_disks=12, steps=300, h=0.01, mu=0.5, seed=0, warm=True, snapshots=4):
    """Run the pile; returns the history: time, energy, sums of normal and friction
    impulses, rows, pivots and solve time per step, snapshots of the positions, and the
    world at the end."""
    world = pile_world(n_disks, mu=mu, seed=seed)
    # Compile the kernels before the clock matters (the first call of a fresh process).
    lemke.solve_blcp(np.eye(2), -np.ones(2), [0.0, -1.0], [np.inf, 1.0], findex=[-1, 0])
    hist = {k: [] for k in ("t", "energy", "normal", "friction", "rows", "pivots", "secs",
                            "env_vertical", "cold")}
    hist["snap"] = []
    snap_at = set(np.linspace(0, steps, snapshots).astype(int).tolist())
    ws = None
    for s in range(steps + 1):
        if s in snap_at:
            hist["snap"].append((s * h, world.pos.copy()))
        if s == steps:
            break
        lam, cs, res, secs = step(world, h, ws if warm else None, hist["cold"])
        ws = res.warm_start if res is not None else None
        hist["t"].append((s + 1) * h)
        hist["energy"].append(energy(world))
        hist["normal"].append(float(lam[0::2].sum()) if lam.size else 0.0)
        hist["friction"].append(float(np.abs(lam[1::2]).sum()) if lam.size else 0.0)
        hist["rows"].append(lam.size)
        hist["pivots"].append(res.pivots if res is not None else 0)
        hist["secs"].append(secs)
        # vertical impulse from the floor and the walls on the pile
        vert = 0.0
        for c, (a, b, p, n, gap) in enumerate(cs):
            if b < 0:
                t = np.array([-n[1], n[0]])
                vert += lam[2 * c] * n[1] + lam[2 * c + 1] * t[1]
        hist["env_vertical"].append(vert)
    hist["world"] = world
    hist["h"] = h
    return hist


def slope(angle, mu, steps=50, h=0.01):
    """A box (no rotation) resting on a plane inclined by ``angle``: returns its velocity
    along the slope (positive downhill) after each step."""
    g = G * np.array([-np.sin(angle), -np.cos(angle)])  # the plane is y = 0, downhill -x
    half = np.array([[0.1, 0.05]])
    world = World(pos=np.array([[0.0, 0.05]]), ang=np.zeros(1), vel=np.zeros((1, 2)),
                  omega=np.zeros(1), mass=np.array([1.0]), inertia=np.array([np.inf]),
                  radius=np.zeros(1), half=half, mu=mu, gravity=g,
                  cfm=1e-12)  # one body: no pile to regularize; CFM would let it creep
    v = []
    ws = None
    for _ in range(steps):
        lam, cs, res, secs = step(world, h, ws)
        ws = res.warm_start if res is not None else None
        v.append(-world.vel[0, 0])
    return np.array(v)


def plot(hist, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    world = hist["world"]
    fig, axes = plt.subplots(2, 3, figsize=(13, 7.5))
    ax = axes[0, 0]
    colors = plt.cm.viridis(np.linspace(0, 1, len(hist["snap"])))
    for (t, pos), col in zip(hist["snap"], colors):
        for p, r in zip(pos, world.radius):
            ax.add_patch(plt.Circle(p, r, fill=False, color=col, lw=1))
        ax.plot([], [], color=col, label=f"t = {t:.2f} s")
    ax.plot([0, 0, world.width, world.width], [1.2, 0, 0, 1.2], "k-", lw=2)
    ax.set_aspect("equal")
    ax.set_xlim(-0.05, world.width + 0.05)
    ax.set_ylim(-0.05, max(p[:, 1].max() for _, p in hist["snap"]) + 0.15)
    ax.set_title("snapshots")
    ax.legend(fontsize=7, loc="upper right")
    t = np.array(hist["t"])
    axes[0, 1].plot(t, hist["energy"])
    axes[0, 1].set_title("energy (kinetic + potential) [J]")
    axes[0, 2].plot(t, hist["normal"], label="sum of normal impulses (all contacts)")
    axes[0, 2].plot(t, hist["friction"], label="sum of |friction impulses|")
    axes[0, 2].plot(t, hist["env_vertical"], label="vertical impulse of floor and walls")
    axes[0, 2].axhline(world.mass.sum() * G * hist["h"], color="k", ls=":", label="weight x h")
    axes[0, 2].set_title("contact impulses per step [N s]")
    axes[0, 2].legend(fontsize=7)
    axes[1, 0].plot(t, hist["rows"])
    axes[1, 0].set_title("LCP rows per step (2 per contact)")
    cold = np.array(hist["cold"])
    axes[1, 1].plot(t, cold[:, 0], color="0.6", lw=1, label="cold")
    axes[1, 1].plot(t, hist["pivots"], label="warm-started")
    axes[1, 1].set_title("pivots per step")
    axes[1, 1].legend(fontsize=7)
    axes[1, 2].plot(t, cold[:, 1] * 1e3, color="0.6", lw=1, label="cold")
    axes[1, 2].plot(t, np.array(hist["secs"]) * 1e3, label="warm-started")
    axes[1, 2].set_title("solve_blcp time per step [ms]")
    axes[1, 2].legend(fontsize=7)
    for a in axes.flat[1:]:
        a.set_xlabel("t [s]")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description="Disks falling into a bin, one box LCP per step.")
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--disks", type=int, default=12)
    ap.add_argument("--mu", type=float, default=0.5)
    ap.add_argument("--out", default="box_pile.png")
    args = ap.parse_args(argv)
    hist = simulate(args.disks, args.steps, mu=args.mu)
    plot(hist, args.out)
    cold = np.array(hist["cold"]).sum(axis=0)
    print(f"{args.steps} steps: warm-started {sum(hist['pivots'])} pivots, "
          f"{1e3 * sum(hist['secs']):.1f} ms in the LCPs (cold: {int(cold[0])} pivots, "
          f"{1e3 * cold[1]:.1f} ms); wrote {args.out}")


if __name__ == "__main__":
    main()
