"""solve_blcp per call, before and after the native front (src/python_front_box.cpp).

    python benchmarks/bench_blcp_front.py BEFORE_PYTHON AFTER_PYTHON [--rounds R]

runs this file as a worker under two interpreters (one with lemke before the change, one
after) in alternating rounds, each round timing every case in one process, and prints a
Markdown table of the medians over rounds (per case, the median over its problems).
Cases: cold calls at n = 1, 3, 6, 12, 24 (box LCPs: a monotone M, every other row a
normal row [0, inf), the others [-0.5, 0.5]); 0-pivot warm re-solves (the last answer's
warm start, q moved by 1e-9) at n = 6, 12, 24, without and with a friction index (n/2 2-D
contacts, ``bench_blcp.contact_islands``). A problem whose warm re-solve needs a pivot
is skipped. Both interpreters must give the same answers (checked: z bit for bit)."""
import json
import subprocess
import sys
import time

import numpy as np

from bench_blcp import contact_islands  # (n/2 2-D contacts with findex)

PROBLEMS = 5


def box(seed, n):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    B = rng.standard_normal((n, n))
    M = A @ A.T / n + 0.1 * (B - B.T) + 0.05 * np.eye(n)
    q = rng.standard_normal(n)
    lo = np.where(np.arange(n) % 2 == 0, 0.0, -0.5)
    hi = np.where(np.arange(n) % 2 == 0, np.inf, 0.5)
    return M, q, lo, hi, None


def friction(seed, n):
    return contact_islands(seed, n // 2)


def cases():
    out = []
    for n in (1, 3, 6, 12, 24):
        out.append(("cold", "box", n))
    for n in (6, 12, 24):
        out.append(("warm", "box", n))
        out.append(("warm", "friction", n))
    return out


def per_call(f, budget=2e-3):
    reps = 1
    while True:
        t = time.perf_counter()
        for _ in range(reps):
            f()
        dt = time.perf_counter() - t
        if dt > budget:
            break
        reps *= 4
    best = []
    for _ in range(5):
        t = time.perf_counter()
        for _ in range(reps):
            f()
        best.append((time.perf_counter() - t) / reps)
    return float(np.median(best))


def worker():
    import lemke
    solve = lemke.solve_blcp
    res = {}
    for kind, fam, n in cases():
        times, check = [], []
        seed = 0
        while len(times) < PROBLEMS and seed < 200:
            seed += 1
            M, q, lo, hi, fi = (box if fam == "box" else friction)(seed, n)
            r = solve(M, q, lo, hi, findex=fi)
            if not r.success:
                continue
            if kind == "cold":
                f = lambda: solve(M, q, lo, hi, findex=fi)
            else:
                q2 = q + 1e-9
                ws = r.warm_start
                r2 = solve(M, q2, lo, hi, findex=fi, warm_start=ws)
                if not r2.success or r2.pivots != 0:
                    continue
                r = r2
                f = lambda: solve(M, q2, lo, hi, findex=fi, warm_start=ws)
            times.append(per_call(f))
            check.append(r.z.tobytes().hex()[:64] + str(r.pivots))
        res[f"{kind} {fam} {n}"] = (float(np.median(times)), len(times), check)
    print(json.dumps(res))


def main():
    before, after = sys.argv[1], sys.argv[2]
    rounds = int(sys.argv[sys.argv.index("--rounds") + 1]) if "--rounds" in sys.argv else 7
    up0 = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    runs = {"before": [], "after": []}
    for r in range(rounds):
        order = (("before", before), ("after", after)) if r % 2 == 0 else (("after", after), ("before", before))
        for name, py in order:
            out = subprocess.run([py, __file__, "--worker"], capture_output=True, text=True, check=True)
            runs[name].append(json.loads(out.stdout))
    up1 = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    print(f"uptime at the start: {up0}; at the end: {up1}; {rounds} rounds each, alternating\n")
    print("| case | family | n | problems | before | after | after/before |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for key in runs["after"][0]:
        b = np.median([run[key][0] for run in runs["before"]]) * 1e6
        a = np.median([run[key][0] for run in runs["after"]]) * 1e6
        same = runs["before"][0][key][2] == runs["after"][0][key][2]
        kind, fam, n = key.split()
        print(f"| {kind} | {fam} | {n} | {runs['after'][0][key][1]} | {b:.2f} us | {a:.2f} us | "
              f"{a / b:.2f} |" + ("" if same else " (answers differ!)"))


if __name__ == "__main__":
    worker() if "--worker" in sys.argv else main()
