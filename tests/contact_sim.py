"""Step LCPs of a small 2-D rigid-body simulation with Coulomb friction (a test-data generator).

Scene
-----
``n_bodies`` rigid bodies (disks, and with ``boxes=True`` about one in four is a rectangle)
are dropped into a bin: a floor ``y = 0`` and walls ``x = 0`` and ``x = width``.  Every body
has a position ``c = (x, y)``, an angle ``theta`` and a velocity ``(vx, vy, omega)``; the
generalized velocity ``v`` stacks the three numbers of every body, and ``W`` is the diagonal
inverse mass matrix ``diag(1/m, 1/m, 1/I)``.  Everything is drawn from ``seed``.

Contacts
--------
A contact is a point ``p``, a unit normal ``n`` pointing from body B (or the environment)
to body A, the tangent ``t = (-n_y, n_x)``, a gap ``phi`` (negative when the bodies overlap)
and a friction coefficient ``mu``.  Contacts are kept while ``phi < margin``, a margin that
covers a tenth of the bodies' size plus the distance they can travel in one step, so that a
contact is found before it closes (and some of the contacts are open, with a positive
right-hand side).  The relative velocity at ``p`` along a direction ``u`` is
``u . (v_A + omega_A k x r_A) - u . (v_B + omega_B k x r_B)`` with ``r = p - c``; in 2-D
``u . (omega k x r) = omega (r x u)`` with ``r x u = r_x u_y - r_y u_x``.  That gives a row
of the normal Jacobian ``J_n`` (for ``u = n``) and of the tangent Jacobian ``J_t`` (for
``u = t``).

Found contacts: disk-floor and disk-wall, disk-disk, box corners against floor and walls,
box-disk (closest point of the rectangle to the disk's centre), box-box (each corner of one
box near the other one, against the face of least penetration).  Redundant contacts are
there on purpose, as a real collision pipeline produces them:

* a disk on the floor touches it at *two* nearby points, at angles ``+-delta`` from its
  lowest point (both with the floor's normal): two almost equal rows of ``J_n``;
* a box resting on a face gets a third contact at the middle of that face (collinear
  with the two corners);
* on every third step the disk-disk contacts are listed twice (identical rows).

The number of contacts ``m`` changes from step to step, and so does the LCP size ``4 m``.

The LCP of one step (Stewart & Trinkle 1996, Anitescu & Potra 1997)
--------------------------------------------------------------------
The friction cone is polyhedral: in 2-D it is spanned by the two tangent directions
``+t`` and ``-t``.  With ``D`` the ``2m x 3N`` matrix whose rows for contact k are
``+J_t[k]`` and ``-J_t[k]``, ``E`` the ``2m x m`` matrix with ``E[2k, k] = E[2k+1, k] = 1``,
and ``U = diag(mu)``, the unknowns are the normal impulses ``c_n`` (m), the friction
impulses ``beta`` (2m) and the sliding-speed slacks ``lam`` (m), and the step is

    v+ = v* + W (J_n' c_n + D' beta),        v* = v + h W f_ext  (gravity),

    0 <= c_n  _|_  J_n v+ + b                  >= 0   (no approach; b below)
    0 <= beta _|_  D v+ + E lam                >= 0   (friction opposes sliding)
    0 <= lam  _|_  U c_n - E' beta             >= 0   (Coulomb cone: |f_t| <= mu c_n)

that is LCP(M, q) with z = (c_n, beta, lam) and

        [ J_n W J_n'   J_n W D'   0 ]          [ J_n v* + b ]
    M = [ D W J_n'     D W D'     E ] ,    q = [ D v*       ] .
        [ U            -E'        0 ]          [ 0          ]

M is neither symmetric nor positive semidefinite (the ``U`` / ``-E'`` / ``E`` blocks), but it
is copositive: for z = (c_n, beta, lam) >= 0,

    z'M z = |W^(1/2) (J_n' c_n + D' beta)|^2 + lam' U c_n >= 0

(the E and -E' blocks cancel).  ``b = max(phi, 0) / h``: an open contact may close during
the step but not overlap; an existing overlap is not pushed out, only kept from growing.

With ``b >= 0`` every step LCP has a solution, and Lemke's method with any covering vector
d > 0 and a rule that cannot cycle finds one (the argument of Anitescu & Potra; see
Cottle, Pang & Stone 1992, section 4.4).  Suppose it ended on a secondary ray
(z, z0) + t (dz, dz0), z0 > 0, dz != 0.  Along the ray dz >= 0, M dz + d dz0 >= 0 and
dz'(M dz + d dz0) = 0, so copositivity gives dz0 = 0, M dz >= 0 and dz'M dz = 0.  By the
identity above, J_n' dc_n + D' dbeta = 0, hence dz'q = dc_n' b >= 0.  But complementarity
along the ray gives dz'q = -dz'M z - z0 dz'd and z'M dz = 0, and dz'M z = z'M'dz >=
-z'M dz = 0 (for copositive M, dz >= 0 and dz'M dz = 0 imply (M + M') dz >= 0), so
dz'q <= -z0 dz'd < 0: a contradiction.  A Baumgarte term (b < 0 on overlaps) would break
this: a body squeezed from two opposite sides gives c_n >= 0 with J_n' c_n = 0 and
c_n' b < 0, and an infeasible LCP.

Advancing
---------
Each step's LCP is solved by ``lemke.solve_lcp`` (default method and options).  When the
result is SOLVED its impulses are applied; otherwise the step is advanced with zero contact
impulse, so that the sequence does not depend on whether a solve succeeded (it does depend
on which solution lemke returns: the impulses of a redundant contact set are not unique).
Positions are then updated by semi-implicit Euler, ``c += h v+``, ``theta += h omega+``.
Overlaps (from the linearization: a disk rolling over a box's corner, or a step advanced
without impulse) are not corrected in the LCP (that would need ``b < 0``) but by a position
correction after it: the two bodies of a contact with ``phi < 0`` at the start of the step
are moved apart along its normal by ``0.2 |phi|``, shared in proportion to their inverse
masses (the environment does not move).
Everything is plain numpy, deterministic for a given seed and lemke version.
"""
from __future__ import annotations

import numpy as np

import lemke

H = 0.01  # time step (s)
GRAVITY = 9.81
DELTA = 0.08  # angle (rad) between each of the two floor contacts of a disk and its lowest point
PUSH_OUT = 0.2  # fraction of an overlap removed by the position correction of a step


class Scene:
    """The bodies' state and constant properties (arrays of length n_bodies)."""

    def __init__(self, seed: int, n_bodies: int, boxes: bool = True):
        rng = np.random.default_rng(seed)
        self.n = n_bodies
        self.is_box = np.zeros(n_bodies, dtype=bool)
        if boxes:
            self.is_box[rng.permutation(n_bodies)[: n_bodies // 4]] = True
        self.radius = rng.uniform(0.05, 0.09, n_bodies)  # of a disk
        self.half = np.stack([rng.uniform(0.05, 0.1, n_bodies), rng.uniform(0.03, 0.06, n_bodies)], axis=1)  # of a box
        self.size = np.where(self.is_box, np.hypot(self.half[:, 0], self.half[:, 1]), self.radius)  # bounding radius
        area = np.where(self.is_box, 4.0 * self.half[:, 0] * self.half[:, 1], np.pi * self.radius**2)
        self.mass = rng.uniform(500.0, 1500.0, n_bodies) * area
        self.inertia = np.where(
            self.is_box,
            self.mass * ((2 * self.half[:, 0]) ** 2 + (2 * self.half[:, 1]) ** 2) / 12.0,
            0.5 * self.mass * self.radius**2,
        )
        self.mu = rng.uniform(0.2, 0.8, n_bodies)
        # A bin seven bodies wide; the bodies start on a grid of rows, with jitter, the
        # lowest row just above the floor so that the first contacts come within a few steps.
        per_row = 7
        spacing = 2.3 * self.size.max()
        self.width = per_row * spacing
        rows, cols = np.divmod(np.arange(n_bodies), per_row)
        x = (cols + 0.5 + rng.uniform(-0.15, 0.15, n_bodies)) * spacing
        y = self.size.max() * 1.05 + (rows + rng.uniform(0.0, 0.2, n_bodies)) * spacing
        self.pos = np.stack([x, y], axis=1)
        self.theta = rng.uniform(-0.3, 0.3, n_bodies)
        self.vel = np.stack([rng.uniform(-0.3, 0.3, n_bodies), rng.uniform(-0.5, 0.0, n_bodies)], axis=1)
        self.omega = rng.uniform(-1.0, 1.0, n_bodies)

    def frame(self, i):
        """The rotation matrix of body i."""
        c, s = np.cos(self.theta[i]), np.sin(self.theta[i])
        return np.array([[c, -s], [s, c]])

    def corners(self, i):
        """The four corners of box i in world coordinates, in cyclic order."""
        a, b = self.half[i]
        local = np.array([[a, b], [-a, b], [-a, -b], [a, -b]])
        return self.pos[i] + local @ self.frame(i).T

    def reach(self):
        """How far each body's surface may get in one step, plus a tenth of its size."""
        speed = np.hypot(self.vel[:, 0], self.vel[:, 1]) + np.abs(self.omega) * self.size + H * GRAVITY
        return 0.1 * self.size + 1.5 * H * speed


def _find_contacts(sc: Scene, step: int):
    """The contacts ``(a, b, p, n, phi, mu)`` of the current state; ``b = -1`` is the
    environment, ``n`` points from b to a."""
    contacts = []
    width = sc.width
    reach = sc.reach()

    def env(i, p, n, phi):
        contacts.append((i, -1, np.asarray(p, float), np.asarray(n, float), float(phi), sc.mu[i]))

    for i in range(sc.n):
        margin = reach[i]
        if sc.is_box[i]:
            P = sc.corners(i)
            for plane_n, dist in (((0.0, 1.0), P[:, 1]), ((1.0, 0.0), P[:, 0]), ((-1.0, 0.0), width - P[:, 0])):
                near = np.flatnonzero(dist < margin)
                for k in near:
                    env(i, P[k], plane_n, dist[k])
                if len(near) == 2 and (near[1] - near[0]) % 2 == 1:
                    # Two corners of one face near the plane: the face's middle too (redundant).
                    env(i, 0.5 * (P[near[0]] + P[near[1]]), plane_n, 0.5 * (dist[near[0]] + dist[near[1]]))
        else:
            r = sc.radius[i]
            x, y = sc.pos[i]
            if y - r < margin:
                for a in (-DELTA, DELTA):  # two nearby points on the floor (redundant)
                    env(i, (x + r * np.sin(a), y - r * np.cos(a)), (0.0, 1.0), y - r)
            if x - r < margin:
                env(i, (x - r, y), (1.0, 0.0), x - r)
            if width - x - r < margin:
                env(i, (x + r, y), (-1.0, 0.0), width - x - r)

    # Pairs whose bounding circles come within the margins (a vectorized broad phase).
    d = sc.pos[:, None, :] - sc.pos[None, :, :]
    gap = np.hypot(d[..., 0], d[..., 1]) - sc.size[:, None] - sc.size[None, :]
    close = np.argwhere(np.triu(gap < reach[:, None] + reach[None, :], 1))
    copies = 2 if step % 3 == 2 else 1  # disk-disk contacts listed twice every third step
    for i, j in close:
        margin = reach[i] + reach[j]
        mu = np.sqrt(sc.mu[i] * sc.mu[j])
        if not sc.is_box[i] and not sc.is_box[j]:
            dij = sc.pos[i] - sc.pos[j]
            dist = np.hypot(dij[0], dij[1])
            n = dij / dist
            phi = dist - sc.radius[i] - sc.radius[j]
            p = sc.pos[j] + n * (sc.radius[j] + 0.5 * phi)
            contacts.extend([(i, j, p, n, phi, mu)] * copies)
        elif sc.is_box[i] != sc.is_box[j]:
            box, disk = (i, j) if sc.is_box[i] else (j, i)
            R = sc.frame(box)
            local = R.T @ (sc.pos[disk] - sc.pos[box])
            hb = sc.half[box]
            nearest = np.clip(local, -hb, hb)
            if np.array_equal(nearest, local):  # centre inside the box: out by the nearest face
                k = int(np.argmin(hb - np.abs(local)))
                nl = np.zeros(2)
                nl[k] = 1.0 if local[k] >= 0.0 else -1.0
                phi = -(hb[k] - abs(local[k])) - sc.radius[disk]
                nearest = local.copy()
                nearest[k] = nl[k] * hb[k]
            else:
                g = local - nearest
                nl = g / np.hypot(g[0], g[1])
                phi = np.hypot(g[0], g[1]) - sc.radius[disk]
            p = sc.pos[box] + R @ nearest
            contacts.append((disk, box, p, R @ nl, phi, mu))
        else:
            for a, b in ((i, j), (j, i)):  # corners of box a against the faces of box b
                R = sc.frame(b)
                for P in sc.corners(a):
                    local = R.T @ (P - sc.pos[b])
                    sep = np.abs(local) - sc.half[b]
                    k = int(np.argmax(sep))
                    if sep[k] < margin:
                        nl = np.zeros(2)
                        nl[k] = 1.0 if local[k] >= 0.0 else -1.0
                        contacts.append((a, b, P, R @ nl, sep[k], mu))
    if contacts:
        return [c for c in contacts if c[4] < (reach[c[0]] + (reach[c[1]] if c[1] >= 0 else 0.0))]
    return contacts


def step_lcp(sc: Scene, step: int):
    """The LCP of the scene's next step: ``(M, q, apply)``, where ``apply(z)`` advances the
    scene with the impulses z (with none when z is None)."""
    contacts = _find_contacts(sc, step)
    m = len(contacts)
    w = np.empty(3 * sc.n)  # the diagonal of W
    w[0::3] = w[1::3] = 1.0 / sc.mass
    w[2::3] = 1.0 / sc.inertia
    v = np.empty(3 * sc.n)
    v[0::3], v[1::3], v[2::3] = sc.vel[:, 0], sc.vel[:, 1], sc.omega
    v_star = v.copy()
    v_star[1::3] -= H * GRAVITY

    # A = [J_n; D] (3m x 3N), row k the normal of contact k, rows m + 2k and m + 2k + 1 the
    # tangent +t and -t; each row touches one or two bodies.
    A = np.zeros((3 * m, 3 * sc.n))
    rows_of = [[] for _ in range(sc.n)]
    for k, (a, b, p, n, _phi, _mu) in enumerate(contacts):
        t = np.array([-n[1], n[0]])
        for body, sign in ((a, 1.0), (b, -1.0)):
            if body < 0:
                continue
            r = p - sc.pos[body]
            cols = slice(3 * body, 3 * body + 3)
            A[k, cols] += sign * np.array([n[0], n[1], r[0] * n[1] - r[1] * n[0]])
            jt = sign * np.array([t[0], t[1], r[0] * t[1] - r[1] * t[0]])
            A[m + 2 * k, cols] += jt
            A[m + 2 * k + 1, cols] -= jt
            rows_of[body] += [k, m + 2 * k, m + 2 * k + 1]
    # A W A', body by body (each body couples only the rows of its own contacts).
    AWA = np.zeros((3 * m, 3 * m))
    for body, rows in enumerate(rows_of):
        if rows:
            rows = np.array(rows)
            Ab = A[rows, 3 * body : 3 * body + 3]
            AWA[np.ix_(rows, rows)] += (Ab * w[3 * body : 3 * body + 3]) @ Ab.T
    phi = np.array([c[4] for c in contacts])
    mu = np.array([c[5] for c in contacts])

    M = np.zeros((4 * m, 4 * m))
    M[: 3 * m, : 3 * m] = AWA
    cones = np.arange(m)
    M[m + 2 * cones, 3 * m + cones] = 1.0  # E
    M[m + 2 * cones + 1, 3 * m + cones] = 1.0
    M[3 * m + cones, cones] = mu  # U
    M[3 * m + cones, m + 2 * cones] = -1.0  # -E'
    M[3 * m + cones, m + 2 * cones + 1] = -1.0
    q = np.zeros(4 * m)
    q[: 3 * m] = A @ v_star
    q[:m] += np.maximum(phi, 0.0) / H  # b >= 0: see the module docstring

    def apply(z):
        v_new = v_star.copy()
        if z is not None and m:
            v_new += w * (z[: 3 * m] @ A)
        sc.vel[:, 0], sc.vel[:, 1], sc.omega[:] = v_new[0::3], v_new[1::3], v_new[2::3]
        sc.pos += H * sc.vel
        sc.theta += H * sc.omega
        # Position correction outside the LCP: each overlap at the start of the step moves
        # the bodies apart by a fifth of it along the normal, shared by inverse mass.
        for a, b, _p, n, ph, _mu in contacts:
            if ph < 0.0:
                wa, wb = 1.0 / sc.mass[a], (1.0 / sc.mass[b] if b >= 0 else 0.0)
                push = -PUSH_OUT * ph / (wa + wb) * n
                sc.pos[a] += wa * push
                if b >= 0:
                    sc.pos[b] -= wb * push

    # A label per LCP row, stable from step to step while a contact persists: the bodies,
    # which of the pair's contacts (in the order found) and the row's role.
    seen = {}
    keys = []
    for a, b, *_ in contacts:
        seen[(a, b)] = seen.get((a, b), -1) + 1
        keys.append((a, b, seen[(a, b)]))
    apply.labels = ([("n", key) for key in keys]
                    + [(role, key) for key in keys for role in ("t+", "t-")]
                    + [("cone", key) for key in keys])
    # The same labels as ints (one per (role, a, b, k), the same identity from step to
    # step): what a simulation that wants the relabel fast passes (an int hashes in a few
    # tens of nanoseconds, a nested tuple item by item).
    ids = [((a * (sc.n + 1) + b + 1) * 64 + k) * 4 for a, b, k in keys]
    assert all(k < 64 for _a, _b, k in keys)
    apply.ids = ids + [i + role for i in ids for role in (1, 2)] + [i + 3 for i in ids]
    apply.id_array = np.array(apply.ids, dtype=np.int64)  # the same, for relabel's kernel path
    return M, q, apply


def step_lcps(seed: int, n_bodies: int = 20, steps: int = 100, boxes: bool = True):
    """The ``steps`` step LCPs ``(M, q)`` of the scene drawn from ``seed`` (see the module
    docstring), in order; a step without any contact gives an LCP of size 0."""
    sc = Scene(seed, n_bodies, boxes)
    out = []
    for step in range(steps):
        M, q, apply = step_lcp(sc, step)
        res = lemke.solve_lcp(M, q)
        apply(res.z if res.status == lemke.Status.SOLVED else None)
        out.append((M, q))
    return out
