#!/usr/bin/env python
"""Box LCPs: ``lemke.solve_blcp`` against the box-LCP solvers of physics engines that can be
reached from Python (DART through dartpy, Bullet through pybullet).

Usage::

    python benchmarks/bench_engines.py [--quick] [--note TEXT] [--out benchmarks/RESULTS-engines.md]

Needs ``pip install pybullet dartpy`` (the ``bench`` extra); a missing engine is reported,
not fatal.  ``--quick`` (fewer islands and steps) runs in under a minute.

Same islands (DART)
    dartpy 6.20 binds ``DantzigBoxedLcpSolver.solve`` and ``PgsBoxedLcpSolver.solve``, but
    its pointer arguments (A, x, b, lo, hi, findex) are bound as single numbers: arrays are
    refused and the answer cannot be read back (the script shows this live).  Both methods,
    and the Dantzig driver, are exported C++ symbols of the dartpy module, so this script calls
    them with ctypes: the ``this`` pointer of the solver objects that
    ``BoxedLcpConstraintSolver()`` makes (checked against the class's vtable), A stored with
    DART's padded row stride (n rounded up to a multiple of 4; a stride of n corrupts the heap),
    ``b = -q`` (DART solves ``A x = b + w``), ``findex`` as int32 (PGS dereferences it, so it
    always gets an array, -1 for ordinary rows).  DART overwrites A, b, lo and hi, so every
    call gets fresh copies made outside the timed region; ctypes adds about a microsecond.
    Islands: every box LCP with a friction index that ``examples/box_pile.py`` builds while
    stepping a pile of 12 and of 40 disks (n up to 48 and about 170), and the ``relay`` and
    ``contact`` families of ``bench_blcp.py`` at n = 12, 48, 200, as they are (M with a skew
    part) and with only their symmetric part ``A A'`` (``-sym``: DART's Dantzig factors A as
    LDL', so it assumes a symmetric A).  Solvers: lemke cold; lemke warm-started from the
    previous step's result (pile islands whose size did not change); DART Dantzig; DART PGS at
    its default options (30 sweeps) from x = 0, and from the previous step's PGS answer
    (``warm``, as an engine would).  Per island the calls are interleaved in a random order
    drawn afresh every repeat; the island's time is the median over repeats; per set the
    median over islands and the median of the per-island ratios to lemke cold.
    Every answer is checked here with numpy: the natural-map residual
    ``max |z - clip(z - w, lo', hi')|`` relative to the data's scale (``bench_blcp``'s
    ``natural_residual``), where with a friction index the bounds are the coupled ones at the
    answer, ``lo'_i = lo_i z_f``, ``hi'_i = hi_i z_f``.  An answer is *right* when that residual
    is at most 1e-8, whatever its solver reported.

Scenes (pybullet)
    pybullet does not expose its LCPs; ``setPhysicsEngineParameter(constraintSolverType=...)``
    selects Bullet's sequential impulse (``CONSTRAINT_SOLVER_LCP_SI`` = 1, the default) or the
    MLCP solver with PGS (2) or Dantzig (3) for multibodies.  The scene: the same disks as
    ``box_pile.pile_world`` (radii, masses, start positions, mu = 0.5, h = 0.01) as spheres
    in a 1 m bin only slightly deeper than the largest sphere (an almost 2-D pile), stepped in
    the same loop as box_pile's own 2-D pile, in a random order every step.  Reported: wall
    time per ``stepSimulation`` (collision detection, building the MLCP, solving, integrating,
    in C++) and per ``box_pile.step`` (contacts and A in Python and numpy, then lemke), with
    lemke's share; then, in a separate pass with pybullet's profiler on, the time inside
    Bullet's ``solveMLCP`` and how often the MLCP solver failed and Bullet fell back to
    sequential impulse.  Not comparable: 3-D spheres (3 rows a contact) against 2-D disks
    (2 rows); Bullet's contact manifolds, ERP/CFM and split impulse against box_pile's
    stabilization and CFM; Bullet's answers cannot be checked (no matrices).
"""
from __future__ import annotations

import os

BLAS_THREAD_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
if __name__ == "__main__":  # not when imported (by the tests): their environment stays theirs
    for _var in BLAS_THREAD_VARS:
        # lemke's numpy parts on one BLAS thread, as the engines' solvers are single-threaded (on
        # a shared 2-core machine OpenBLAS's own threads made lemke's warm solves ~30x slower)
        os.environ.setdefault(_var, "1")

import ctypes  # noqa: E402
import gc  # noqa: E402
import glob  # noqa: E402
import importlib.metadata as md  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "examples"))

import bench_blcp as bb  # noqa: E402  (families, natural residual)
import bench_lcp as bl  # noqa: E402  (problems, machine description, report head)
import box_pile as bp  # noqa: E402  (the contact scene)

import lemke  # noqa: E402

RIGHT = 1e-8
H = 0.01


def version(dist):
    try:
        return md.version(dist)
    except md.PackageNotFoundError:
        return "not installed"


# --------------------------------------------------------------------------- checks


def coupled_residual(M, q, lo, hi, findex, z):
    """Natural-map residual of the box LCP, friction bounds coupled to the answer's z_f."""
    if findex is not None:
        lo, hi = lo.copy(), hi.copy()
        m = findex >= 0
        lo[m] = lo[m] * z[findex[m]]
        hi[m] = hi[m] * z[findex[m]]
    return bb.natural_residual(M, q, lo, hi, z)


# --------------------------------------------------------------------------- DART


class Dart:
    """DART's boxed LCP solvers called through the dartpy module's exported symbols."""

    SYMBOLS = {
        "DantzigBoxedLcpSolver": ("_ZN4dart10constraint21DantzigBoxedLcpSolver5solveEiPdS2_S2_iS2_S2_Pib",
                                  "_ZTVN4dart10constraint21DantzigBoxedLcpSolverE"),
        "PgsBoxedLcpSolver": ("_ZN4dart10constraint17PgsBoxedLcpSolver5solveEiPdS2_S2_iS2_S2_Pib",
                              "_ZTVN4dart10constraint17PgsBoxedLcpSolverE"),
    }

    def __init__(self):
        import dartpy

        self.dartpy = dartpy
        self.notes = self.probe_binding()
        lib = ctypes.CDLL(dartpy.__file__)
        P, PI = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_int)
        self.holder = dartpy.constraint.BoxedLcpConstraintSolver()
        self.fns = {}
        for obj in (self.holder.getBoxedLcpSolver(), self.holder.getSecondaryBoxedLcpSolver()):
            name = type(obj).__name__
            method, vtable = self.SYMBOLS[name]
            fn = getattr(lib, method)
            fn.restype = ctypes.c_bool
            fn.argtypes = [ctypes.c_void_p, ctypes.c_int, P, P, P, ctypes.c_int, P, P, PI, ctypes.c_bool]
            # pybind11's instance: PyObject header (2 words), then the C++ object's address.
            this = (ctypes.c_void_p * 3).from_address(id(obj))[2]
            vt = ctypes.cast(getattr(lib, vtable), ctypes.c_void_p).value
            if ctypes.c_void_p.from_address(this).value != vt + 16:
                raise RuntimeError(f"{name}: the object's vtable is not the class's; layout changed")
            self.fns[name] = (fn, this, obj)

    def probe_binding(self):
        """What the Python binding itself does with a box LCP (recorded for the report)."""
        C = self.dartpy.constraint
        notes = []
        try:
            C.DantzigBoxedLcpSolver()
        except TypeError as e:
            notes.append(f"`DantzigBoxedLcpSolver()` raises `TypeError: {e}`; the solver objects "
                         "come from `BoxedLcpConstraintSolver().getBoxedLcpSolver()` / "
                         "`getSecondaryBoxedLcpSolver()`")
        s = C.BoxedLcpConstraintSolver().getBoxedLcpSolver()
        A, x, b = np.array([[2.0, 1.0], [1.0, 2.0]]), np.zeros(2), np.array([5.0, -1.0])
        try:
            s.solve(2, A, x, b, 0, np.array([0.0, -1.0]), np.array([2.0, 1.0]),
                    np.array([-1, -1], dtype=np.int32), False)
            notes.append("`solve(2, A, x, b, ...)` with numpy arrays was accepted")
        except TypeError as e:
            notes.append("`solve(n, A, x, b, nub, lo, hi, findex, earlyTermination)` with numpy "
                         f"arrays raises `TypeError: {str(e).splitlines()[0]}`: the signature "
                         "takes one float for each of A, x, b, lo, hi and one int for findex")
        ok = s.solve(1, 2.0, 0.0, 1.0, 0, 0.0, 10.0, -1, False)
        notes.append(f"with scalars, n = 1 (`solve(1, 2.0, 0.0, 1.0, 0, 0.0, 10.0, -1, False)`) it "
                     f"returns {ok}, but x is a temporary: the answer (0.5) cannot be read back; "
                     "n > 1 would read past one double and was not tried")
        return notes

    @staticmethod
    def pad(n):
        return ((n - 1) | 3) + 1 if n > 1 else n

    def prepare(self, name, M, q, lo, hi, findex, x0=None):
        """A zero-argument call on fresh copies of the data, and the array it answers in."""
        fn, this, _ = self.fns[name]
        n = q.size
        A = np.zeros((n, self.pad(n)))
        A[:, :n] = M
        x = np.zeros(n) if x0 is None else np.array(x0, dtype=float)
        b, lo, hi = -q, lo.copy(), hi.copy()
        fi = np.full(n, -1, dtype=np.int32) if findex is None else findex.astype(np.int32)
        P, PI = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_int)
        args = (this, n, A.ctypes.data_as(P), x.ctypes.data_as(P), b.ctypes.data_as(P), 0,
                lo.ctypes.data_as(P), hi.ctypes.data_as(P), fi.ctypes.data_as(PI), False)
        keep = (A, b, lo, hi, fi)

        def call(keep=keep):
            return fn(*args)

        return call, x


# --------------------------------------------------------------------------- islands


def pile_islands(n_disks, steps):
    """The box LCPs (M, q, lo, hi, findex) box_pile builds while stepping its pile."""
    rec = []

    class Recorder:
        def __getattr__(self, name):
            return getattr(lemke, name)

        @staticmethod
        def solve_blcp(M, q, lo, hi, **kw):
            rec.append((M.copy(), q.copy(), lo.copy(), hi.copy(), kw["findex"].copy()))
            return lemke.solve_blcp(M, q, lo, hi, **kw)

    world = bp.pile_world(n_disks)
    saved, bp.lemke = bp.lemke, Recorder()
    try:
        ws = None
        for _ in range(steps):
            lam, cs, res, secs = bp.step(world, H, ws)
            ws = res.warm_start if res is not None else None
    finally:
        bp.lemke = saved
    return rec


def family_islands(kind, n, count, sym):
    out = []
    for k in range(count):
        if sym:
            A, _, q = bl.make_factors(n, k)
            M = np.ascontiguousarray(A @ A.T)
        else:
            M, q = bl.make_problem(n, k)
        lo, hi = bb.boxes(n, kind)
        out.append((M, q, lo, hi, None))
    return out


# --------------------------------------------------------------------------- timing


def time_calls(preps, rng, budget, min_reps=3, max_reps=200):
    """``preps``: name -> function returning (call, answer-getter); the calls interleaved in a
    random order every repeat, set-up outside the timed region.  Returns (median seconds per
    name, last answer per name)."""
    names = list(preps)
    times = {k: [] for k in names}
    last = {}
    gc.collect()
    gc.disable()
    try:
        pc = time.perf_counter
        t0, reps = pc(), 0
        while reps < min_reps or (pc() - t0 < budget and reps < max_reps):
            for j in rng.permutation(len(names)):
                name = names[j]
                call, get = preps[name]()
                s = pc()
                out = call()
                e = pc()
                times[name].append(e - s)
                last[name] = get(out)
            reps += 1
    finally:
        gc.enable()
    return {k: statistics.median(v) for k, v in times.items()}, last


def island_solvers(dart, isl, prev_lemke, prev_pgs):
    """name -> prep for one island; prep() gives (call, get), get(out) -> (reported_ok, z)."""
    M, q, lo, hi, fi = isl

    def lem(ws=None):
        return lambda: (lambda: lemke.solve_blcp(M, q, lo, hi, findex=fi, warm_start=ws),
                        lambda r: (r.success, np.asarray(r.z)))

    out = {"lemke cold": lem()}
    if prev_lemke is not None:
        out["lemke warm"] = lem(prev_lemke)
    if dart is not None:
        def eng(name, x0=None):
            def prep():
                call, x = dart.prepare(name, M, q, lo, hi, fi, x0)
                return call, lambda ok: (bool(ok), x.copy())
            return prep

        out["DART Dantzig"] = eng("DantzigBoxedLcpSolver")
        out["DART PGS"] = eng("PgsBoxedLcpSolver")
        if prev_pgs is not None:
            out["DART PGS warm"] = eng("PgsBoxedLcpSolver", prev_pgs)
    return out


def bench_set(label, islands, dart, rng, budget, chain):
    """Time and check every solver on a list of islands; ``chain``: consecutive steps of one
    scene (warm starts from the previous island of the same size)."""
    per = {}
    prev_lemke = prev_pgs = None
    prev_n = None
    for isl in islands:
        M, q, lo, hi, fi = isl
        n = q.size
        same = chain and prev_n == n
        solvers = island_solvers(dart, isl, prev_lemke if same else None, prev_pgs if same else None)
        med, ans = time_calls(solvers, rng, budget)
        for name, t in med.items():
            ok, z = ans[name]
            res = coupled_residual(M, q, lo, hi, fi, z)
            per.setdefault(name, []).append(dict(n=n, t=t, ref=med["lemke cold"], ok=ok, res=res))
        if chain:
            # the warm starts of the next island: lemke's from this step's (warm) solve, PGS's
            # own previous answer
            r = lemke.solve_blcp(M, q, lo, hi, findex=fi, warm_start=prev_lemke if same else None)
            prev_lemke = r.warm_start
            if dart is not None:
                call, x = dart.prepare("PgsBoxedLcpSolver", M, q, lo, hi, fi, prev_pgs if same else None)
                call()
                prev_pgs = x.copy()
            prev_n = n
    rows = []
    for name, recs in per.items():
        ns = [r["n"] for r in recs]
        rows.append(dict(
            set=label, solver=name, islands=len(recs), n=(min(ns), max(ns)),
            t=statistics.median(r["t"] for r in recs),
            ratio=statistics.median(r["t"] / r["ref"] for r in recs),
            right=sum(r["res"] <= RIGHT for r in recs),
            reported_ok=sum(bool(r["ok"]) for r in recs),
            wrong_but_ok=sum(bool(r["ok"]) and r["res"] > RIGHT for r in recs),
            med_res=statistics.median(r["res"] for r in recs),
            max_res=max(r["res"] for r in recs)))
        print(f"{label:14s} {name:14s} {fmt_t(rows[-1]['t']):>10s} x{rows[-1]['ratio']:.2f} "
              f"right {rows[-1]['right']}/{len(recs)} max res {rows[-1]['max_res']:.1e}", file=sys.stderr)
    return rows


# --------------------------------------------------------------------------- pybullet scenes


class BulletPile:
    """box_pile's disks as spheres in a narrow 3-D bin, in one pybullet DIRECT client."""

    def __init__(self, p, solver, n_disks):
        self.p = p
        c = self.c = p.connect(p.DIRECT)
        world = bp.pile_world(n_disks)
        depth = 2 * world.radius.max() + 0.01
        p.setGravity(0, 0, -bp.G, physicsClientId=c)
        p.setTimeStep(H, physicsClientId=c)
        p.setPhysicsEngineParameter(constraintSolverType=solver, reportSolverAnalytics=1, physicsClientId=c)
        w = world.width
        walls = (([w, depth, 0.05], [w / 2, depth / 2, -0.05]),
                 ([0.05, depth, 2], [-0.05, depth / 2, 2]), ([0.05, depth, 2], [w + 0.05, depth / 2, 2]),
                 ([w, 0.05, 2], [w / 2, -0.05, 2]), ([w, 0.05, 2], [w / 2, depth + 0.05, 2]))
        for half, pos in walls:
            self.body(0.0, p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=c), pos, world.mu)
        self.ids = [self.body(m, p.createCollisionShape(p.GEOM_SPHERE, radius=r, physicsClientId=c),
                              [x, depth / 2, y], world.mu)
                    for r, m, (x, y) in zip(world.radius, world.mass, world.pos)]

    def body(self, mass, shape, pos, mu):
        b = self.p.createMultiBody(mass, shape, basePosition=pos, physicsClientId=self.c)
        self.p.changeDynamics(b, -1, lateralFriction=mu, physicsClientId=self.c)
        return b

    def step(self):
        return self.p.stepSimulation(physicsClientId=self.c)

    def contacts(self):
        return len(self.p.getContactPoints(physicsClientId=self.c))

    def state(self):
        return np.array([self.p.getBasePositionAndOrientation(b, physicsClientId=self.c)[0] for b in self.ids])

    def close(self):
        self.p.disconnect(self.c)


BULLET = {"SI (default)": 1, "MLCP PGS": 2, "MLCP Dantzig": 3}


def bench_scene(p, n_disks, steps, rng):
    """Interleaved stepping: the pybullet solvers and box_pile's pile, one step each in a random
    order per step."""
    sims = {name: BulletPile(p, s, n_disks) for name, s in BULLET.items()}
    world = bp.pile_world(n_disks)
    state = {"ws": None}
    times = {k: [] for k in [*sims, "box_pile step"]}
    lemke_t, rows_bp, contacts = [], [], []

    def bp_step():
        lam, cs, res, secs = bp.step(world, H, state["ws"])
        state["ws"] = res.warm_start if res is not None else None
        return lam.size, secs

    calls = {**{k: s.step for k, s in sims.items()}, "box_pile step": bp_step}
    names = list(calls)
    gc.collect()
    gc.disable()
    try:
        for _ in range(steps):
            for j in rng.permutation(len(names)):
                t0 = time.perf_counter()
                out = calls[names[j]]()
                times[names[j]].append(time.perf_counter() - t0)
                if names[j] == "box_pile step":
                    rows_bp.append(out[0])
                    lemke_t.append(out[1])
            contacts.append(sims["MLCP Dantzig"].contacts())
    finally:
        gc.enable()
    for s in sims.values():
        s.close()
    half = steps // 2  # the settled half: the pile has formed
    out = []
    for name, ts in times.items():
        out.append(dict(scene=f"{n_disks} bodies", solver=name, t=statistics.median(ts),
                        t_late=statistics.median(ts[half:])))
    out.append(dict(scene=f"{n_disks} bodies", solver="box_pile: lemke inside the step",
                    t=statistics.median(lemke_t), t_late=statistics.median(lemke_t[half:])))
    extra = dict(rows_bp=statistics.median(rows_bp[half:]), contacts=statistics.median(contacts[half:]))
    return out, extra


def profile_scene(p, solver, n_disks, steps):
    """Bullet's own profile of the MLCP solver on the scene: solveMLCP calls, their median
    duration, and how many failed (Bullet then runs sequential impulse instead)."""
    sim = BulletPile(p, solver, n_disks)
    with tempfile.TemporaryDirectory(prefix="bench-engines-") as d:
        log = p.startStateLogging(p.STATE_LOGGING_PROFILE_TIMINGS, os.path.join(d, "prof"),
                                  physicsClientId=sim.c)
        for _ in range(steps):
            sim.step()
        p.stopStateLogging(log, physicsClientId=sim.c)
        sim.close()
        events = []
        for f in glob.glob(os.path.join(d, "prof*")):
            with open(f) as fh:
                data = json.load(fh)
            events += data["traceEvents"] if isinstance(data, dict) else data
    stack, spans = [], {}
    for e in events:
        if e.get("ph") == "B":
            stack.append(e)
        elif e.get("ph") == "E" and stack:
            b = stack.pop()
            spans.setdefault(b["name"].rstrip("0123456789"), []).append((b["ts"], e["ts"]))
    steps_ = sorted(spans.get("internalSingleStepSimulation", []))
    calls = sorted(spans.get("solveMLCP", []))
    solved = sorted(spans.get("process MLCP results", []))

    def within(items, b, e):
        return [x for x in items if b <= x[0] <= e]

    per_step = [(sum(e - b for b, e in within(calls, b0, e0)), len(within(calls, b0, e0)),
                 len(within(solved, b0, e0)), e0 - b0) for b0, e0 in steps_]
    late = per_step[len(per_step) // 2:] or [(float("nan"),) * 4]
    return dict(calls=len(calls), solved=len(solved), fallback=len(calls) - len(solved),
                fallback_steps=sum(c > s for _, c, s, _ in per_step), steps=len(per_step),
                mlcp_us=statistics.median(x[0] for x in late),
                step_us=statistics.median(x[3] for x in late))


def ignored_solver_types(p, steps=60):
    """Bullet's enum also has LEMKE (4), NNCG (5), BLOCK_PGS (6); pybullet exports no
    constants for them.  Which of them change the trajectory from sequential impulse's?"""
    def run(s):
        sim = BulletPile(p, s, 12)
        for _ in range(steps):
            sim.step()
        st = sim.state()
        sim.close()
        return st

    ref = run(1)
    return {s: bool(np.array_equal(run(s), ref)) for s in (2, 3, 4, 5, 6)}


# --------------------------------------------------------------------------- report


def fmt_t(s):
    return bl._t(s)


def method_section(doc):
    """The report's "Method" lines: the module docstring from its fourth paragraph on, a
    paragraph whose first line heads an indented block set as a bold heading."""
    L = ["## Method", ""]
    for para in doc.split("\n\n")[3:]:
        lines = [ln.strip() for ln in para.strip().splitlines()]
        if len(lines) > 1 and not para.startswith(" ") and para.splitlines()[1].startswith("    "):
            lines[0] = f"**{lines[0]}.**"
        L += [" ".join(lines).replace("``", "`"), ""]
    return L


def render(info, args, total_s, rows, scene_rows, scene_extra, profiles, ignored, dart_notes, missing):
    L = bl.report_head("Box LCPs: lemke.solve_blcp vs the engines' own solvers (DART, Bullet)",
                       "bench_engines.py", args, total_s, info,
                       extra_versions=f", pybullet {version('pybullet')}, dartpy {version('dartpy')}",
                       extra_lines=["- BLAS threads: " + ", ".join(f"`{v}={os.environ.get(v)}`"
                                                                   for v in BLAS_THREAD_VARS)])
    L += method_section(__doc__)
    L += ["## What each engine exposes to Python", ""]
    L += [f"- dartpy: {n}." for n in dart_notes]
    L += ["- dartpy: no symbol of DART's Lemke solver is in the module's dynamic symbol table "
          "(`nm -D --defined-only dartpy*.so | c++filt | grep -i lemke` is empty), so there is "
          "no dart Lemke to time.",
          "- pybullet: no LCP matrices; `constraintSolverType` chooses the solver for the whole "
          "world; `reportSolverAnalytics=1` makes `stepSimulation` return per-island iteration "
          "counts of sequential impulse; `STATE_LOGGING_PROFILE_TIMINGS` writes Bullet's "
          "internal profile (used below for the time inside `solveMLCP`)."]
    if ignored:
        same = [str(s) for s, eq in ignored.items() if eq]
        diff = [str(s) for s, eq in ignored.items() if not eq]
        L.append(f"- pybullet solver types whose 60-step trajectory is bit-identical to sequential "
                 f"impulse's (type 1): {', '.join(same) or 'none'}; different: {', '.join(diff) or 'none'}. "
                 "Types 4 (LEMKE), 5 (NNCG), 6 (BLOCK_PGS) are accepted without an error and "
                 "without the \"switched solver\" message types 2 and 3 print.")
    L += [f"- Not timed: {m}." for m in missing]
    L += ["", "## Same islands: lemke vs DART's boxed LCP solvers", "",
          "Times: median over islands of each island's median; *vs lemke cold*: median of the "
          "per-island ratios (above 1: slower than lemke cold).  *right*: residual <= 1e-8 by "
          "this script's check; *said ok, wrong*: the solver reported success but the check "
          "failed.", "",
          "| islands | count | n | solver | time | vs lemke cold | right | said ok, wrong "
          "| median residual | max residual |",
          "|---|---:|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        L.append(f"| {r['set']} | {r['islands']} | {bl.fmt_range(r['n'])} | {r['solver']} | "
                 f"{fmt_t(r['t'])} | {r['ratio']:.2f} | {r['right']}/{r['islands']} | "
                 f"{r['wrong_but_ok']} | {r['med_res']:.1e} | {r['max_res']:.1e} |")
    if scene_rows:
        L += ["", "## Scenes: pybullet's stepSimulation vs box_pile's step", "",
              "Wall time per step, median over all steps and over the second half (the pile "
              "has settled).  The rows are not the same problem: see Method.", "",
              "| scene | stepper | per step | per step, settled half |", "|---|---|---:|---:|"]
        for r in scene_rows:
            L.append(f"| {r['scene']} | {r['solver']} | {fmt_t(r['t'])} | {fmt_t(r['t_late'])} |")
        L.append("")
        for scene, ex in scene_extra.items():
            L.append(f"- {scene}, settled half: box_pile's LCP has {ex['rows_bp']:g} rows "
                     f"(2 per contact); Bullet reports {ex['contacts']:g} contact points "
                     "(its MLCP has 3 rows per point).")
        L += ["", "Bullet's own profile (a separate pass with the profiler on, µs resolution; "
              "per step: the sum over that step's `solveMLCP` calls, median over the settled "
              "half):", "",
              "| scene | solver | steps | solveMLCP calls | solved | fell back to SI | steps with a "
              "fallback | solveMLCP per step | whole step (profiler) |",
              "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
        for (scene, name), pr in profiles.items():
            L.append(f"| {scene} | {name} | {pr['steps']} | {pr['calls']} | {pr['solved']} | "
                     f"{pr['fallback']} | {pr['fallback_steps']} | {pr['mlcp_us']:.0f} µs | "
                     f"{pr['step_us']:.0f} µs |")
    L.append("")
    return "\n".join(L)


def main(argv=None):
    parser, argv = bl.report_parser(__doc__, "RESULTS-engines.md", argv)
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    args.argv = argv
    info = bl.machine_info()
    t_start = time.perf_counter()
    rng = np.random.default_rng(11)
    missing = []
    try:
        dart = Dart()
    except Exception as e:  # noqa: BLE001  (reported, not fatal)
        dart, dart_notes = None, []
        missing.append(f"DART ({type(e).__name__}: {e})")
    else:
        dart_notes = dart.notes
    try:
        import pybullet as p
    except ImportError as e:
        p = None
        missing.append(f"pybullet ({e})")
    # compile lemke before anything is timed
    lemke.solve_blcp(np.eye(2), -np.ones(2), np.array([0.0, -1.0]), np.array([np.inf, 1.0]),
                     findex=np.array([-1, 0]))
    lemke.solve_blcp(np.eye(2), -np.ones(2), -np.ones(2), np.ones(2))
    quick = args.quick
    budget = 0.01 if quick else 0.05
    rows = []
    for nd, steps in ((12, 60 if quick else 200), (40, 40 if quick else 200)):
        isl = [i for i in pile_islands(nd, steps) if i[1].size]
        rows += bench_set(f"pile {nd} disks", isl, dart, rng, budget, chain=True)
    counts = {12: 2, 48: 1, 200: 1} if quick else {12: 8, 48: 4, 200: 2}
    for kind in ("contact", "relay"):
        for sym in (False, True):
            for n, count in counts.items():
                label = f"{kind}{'-sym' if sym else ''} n={n}"
                rows += bench_set(label, family_islands(kind, n, count, sym), dart, rng, budget, chain=False)
    scene_rows, scene_extra, profiles, ignored = [], {}, {}, {}
    if p is not None:
        steps = 80 if quick else 300
        for nd in ((12,) if quick else (12, 40)):
            r, ex = bench_scene(p, nd, steps, rng)
            scene_rows += r
            scene_extra[f"{nd} bodies"] = ex
            for name in ("MLCP PGS", "MLCP Dantzig"):
                profiles[(f"{nd} bodies", name)] = profile_scene(p, BULLET[name], nd, steps)
        ignored = ignored_solver_types(p)
    bl.mark_end(info)
    text = render(info, args, time.perf_counter() - t_start, rows, scene_rows, scene_extra,
                  profiles, ignored, dart_notes, missing)
    bl.publish(text, args.out, lambda m: print(m, file=sys.stderr))


if __name__ == "__main__":
    main()
