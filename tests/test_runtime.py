"""How the package runs: on the C++ core (no solve compiles a numba kernel), the numba
kernels (test oracles) as plain Python, threads, the command line."""
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import lemke
from lemke import _cli, problems


def run_python(code, **env):
    """Run ``code`` in a new interpreter, with tests/ on its path (the oracle package)."""
    e = dict(os.environ, **env)
    here = os.path.dirname(os.path.abspath(__file__))
    e["PYTHONPATH"] = os.pathsep.join([here] + [p for p in [e.get("PYTHONPATH")] if p])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=e, timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_import_compiles_nothing():
    out = run_python(
        "import lemke, oracle.tableau as t, oracle.unrevised as u, oracle.pivoting as p, oracle.certify as c, oracle.linalg, oracle.cold as k\n"
        "print(sum(len(f.signatures) for f in (t.solve, t.lemke, t.pivot, t.lex_ties, u.solve, u.ratio_test, p.min_ratio, p.keep_lowest, p.first_row, c.lcp_check, c.lcp_ray_check, oracle.linalg.dot, oracle.linalg.axpy, oracle.linalg.equilibrate, k.checked, k.batch)))"
    )
    assert out.strip() == "0"


# Every solve of the package, on the paths its fronts take: an LCP (both methods), a batch,
# a box LCP, an MLCP, QPs (the fused path, the factored path for m >= 4n, the small box
# kernel, the box path through solve_blcp), a bimatrix game and its paths.
_SOLVES = (
    "import numpy as np, lemke\n"
    "from lemke import problems\n"
    "rng = np.random.default_rng(0)\n"
    "M, q = problems.random_psd(12, rng)\n"
    "for method in lemke.METHODS:\n"
    "    assert lemke.solve_lcp(M, q, method=method).success\n"
    "assert lemke.solve_lcp_batch(np.stack([M, M]), np.stack([q, q + 1.0])).z.shape == (2, 12)\n"
    "assert lemke.solve_blcp(M, q, -np.ones(12), np.ones(12)).success\n"
    "assert lemke.solve_mlcp(M[:3, :3], M[3:, 3:], M[:3, 3:], M[3:, :3], q[:3], q[3:]).success\n"
    "n = 8\n"
    "B = rng.standard_normal((n, n))\n"
    "P, c = B @ B.T + 0.1 * np.eye(n), rng.standard_normal(n)\n"
    "qps = [lemke.solve_qp(P, c, G=rng.standard_normal((5, n)), h=rng.uniform(0.1, 1, 5)),\n"
    "       lemke.solve_qp(P, c, G=rng.standard_normal((40, n)), h=rng.uniform(0.1, 1, 40)),\n"
    "       lemke.solve_qp(P, c, lb=-np.ones(n), ub=np.ones(n)),\n"
    "       lemke.solve_qp(np.eye(20), np.ones(20), lb=np.zeros(20), ub=np.ones(20))]\n"
    "for r in qps:\n"
    "    assert r.success, r\n"
    "    r.warm_start, r.z_box, r.obj\n"
    "A, Bm = [[3.0, 0.0], [0.0, 2.0]], [[2.0, 0.0], [0.0, 3.0]]\n"
    "assert lemke.solve_bimatrix(A, Bm).success\n"
    "assert len(lemke.lemke_paths(A, Bm)) == 3\n"
)


def test_solves_compile_no_numba_kernel():
    """The package runs on the C++ core: no solve compiles a numba kernel (numba's compile
    events, recorded around the solves; and every dispatcher of oracle, imported
    afterwards, has no signature, compiled or loaded from numba's cache).  The numba
    kernels are the core's test oracles (tests/test_core_*.py) only."""
    code = (
        "import importlib, pkgutil, sys\n"
        "import numba\n"
        "from numba.core import event, registry\n"
        "with event.install_recorder('numba:compile') as rec:\n"
        + "".join("    " + line + "\n" for line in _SOLVES.splitlines())
        + "imported = sorted(m for m in sys.modules if m.startswith('oracle.'))\n"
        "import oracle\n"
        "count = dispatchers = 0\n"
        "for info in pkgutil.iter_modules(oracle.__path__):\n"
        "    mod = importlib.import_module('oracle.' + info.name)\n"
        "    for f in vars(mod).values():\n"
        "        if isinstance(f, registry.CPUDispatcher):\n"
        "            dispatchers += 1\n"
        "            count += len(f.signatures)\n"
        "with event.install_recorder('numba:compile') as probe:\n"
        "    numba.njit(lambda x: x + 1)(1)\n"
        "print(len(rec.buffer), count, dispatchers, len(probe.buffer) > 0, imported)\n"
    )
    events, signatures, dispatchers, probe_works, imported = run_python(code).split(" ", 4)
    assert probe_works == "True"  # the recorder sees a compilation
    assert int(dispatchers) > 100
    assert (events, signatures) == ("0", "0"), imported


def test_kernels_run_as_plain_python():
    """The numba kernels (the core's oracles) run as plain Python with NUMBA_DISABLE_JIT,
    with the bits they have compiled and the core's: kernels.qp.solve_box on a few box-only
    QPs (screen, Cholesky, the box LCP, the KKT check, the basis) against _core.qp_solve_box."""
    code = (
        "import hashlib, numpy as np\n"
        "from lemke import _core\n"
        "from oracle import qp, tableau\n"
        "compiled = hasattr(tableau.lemke, 'signatures')\n"
        "rng = np.random.default_rng(3)\n"
        "for n in (1, 4, 9):\n"
        "    B = rng.standard_normal((n, n))\n"
        "    args = [B @ B.T / n + 0.1 * np.eye(n), 3.0 * rng.standard_normal(n), np.zeros((0, n)),\n"
        "            np.zeros(0), np.zeros((0, n)), np.zeros(0), -rng.uniform(0, 1, n),\n"
        "            np.where(rng.random(n) < 0.7, rng.uniform(0, 1, n), np.inf)]\n"
        "    bits = []\n"
        "    for run in (qp.solve_box, _core.qp_solve_box):\n"
        "        out, final = np.zeros(7 * n + 5), np.zeros(3 * n, np.int64)\n"
        "        ret = tuple(int(v) for v in run(*args, np.zeros(2 * n, bool), 100 * (n + 1),\n"
        "                                        1e-11, 1e-11, 1e-9, out, final))\n"
        "        bits.append((ret, hashlib.sha1(out.tobytes() + final.tobytes()).hexdigest()))\n"
        "    assert bits[0] == bits[1], (n, bits)\n"
        "    print(bits[0][0][0], bits[0][1])\n"
        "print(compiled)\n"
    )
    plain = run_python(code, NUMBA_DISABLE_JIT="1")
    jitted = run_python(code)
    assert plain.splitlines()[-1] == "False" and jitted.splitlines()[-1] == "True"
    assert plain.splitlines()[:-1] == jitted.splitlines()[:-1]
    assert [line.split()[0] for line in plain.splitlines()[:-1]] == ["0", "0", "0"]


def test_threads_give_the_same_answers():
    rng = np.random.default_rng(1)
    probs = [problems.random_psd(60, rng) for _ in range(16)]
    serial = [lemke.solve_lcp(M, q) for M, q in probs]
    with ThreadPoolExecutor(4) as ex:
        threaded = list(ex.map(lambda p: lemke.solve_lcp(*p), probs))
    for a, b in zip(serial, threaded):
        assert a.status == b.status and a.pivots == b.pivots
        assert np.array_equal(a.z, b.z)


def test_cli_default_example(capsys):
    assert _cli.main(["solve"]) == 0
    out = capsys.readouterr().out
    assert "cps-4.4.7" in out and "SOLVED" in out and "[0., 1., 3.]" in out


def test_cli_not_solved_and_errors(capsys):
    assert _cli.main(["solve", "murty-10", "--max-pivots", "5"]) == 1
    assert "MAX_PIVOTS" in capsys.readouterr().out
    for argv in (["solve", "nope"], ["solve", "--max-pivots", "-1"], ["solve", "--max-pivots", "x"], ["frobnicate"], []):
        assert _cli.main(argv) == 2
        err = capsys.readouterr().err
        assert err.startswith("lemke: error:") and err.count("\n") == 1 and "Traceback" not in err


def test_cli_problems_lists_every_named_problem(capsys):
    assert _cli.main(["problems"]) == 0
    out = capsys.readouterr().out
    for name in problems.NAMED:
        assert name in out


def test_console_command_runs():
    out = subprocess.run([sys.executable, "-m", "lemke", "solve", "degenerate"], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0 and "SOLVED" in out.stdout and "[0. , 0.5]" in out.stdout


def test_readme_example_runs():
    """The README's Python example runs as written (its asserts included)."""
    from pathlib import Path

    readme = Path(__file__).resolve().parents[1] / "README.md"
    text = readme.read_text()
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    out = run_python(code)
    assert out.split() == ["SOLVED", "[0.", "1.", "3.]", "5", "0"]
