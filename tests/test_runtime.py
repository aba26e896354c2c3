"""How the package runs: on the C++ core (a solve loads nothing but numpy, scipy and the
core), threads, the command line."""
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import lemke
from lemke import _cli, problems


def run_python(code, **env):
    """Run ``code`` in a new interpreter, with tests/ on its path."""
    e = dict(os.environ, **env)
    here = os.path.dirname(os.path.abspath(__file__))
    e["PYTHONPATH"] = os.pathsep.join([here] + [p for p in [e.get("PYTHONPATH")] if p])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=e, timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout


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


def test_solves_load_nothing_but_numpy_scipy_and_the_core():
    """The package runs on the C++ core: every solve above, in a fresh interpreter, loads no
    module outside the standard library, numpy, scipy and lemke (bar the private import
    hooks of an editable install, and scipy's Cython runtime): no compiler, nothing from
    tests/."""
    code = _SOLVES + (
        "import sys\n"
        "print(sorted({m.split('.')[0] for m in sys.modules} - set(sys.stdlib_module_names)))\n")
    loaded = eval(run_python(code).strip())
    assert [m for m in loaded if not m.startswith("_") and m not in ("lemke", "numpy", "scipy", "cython_runtime")] == []
    assert "lemke" in loaded and "numpy" in loaded


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
