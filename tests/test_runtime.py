"""How the package runs: lazy compilation, plain-Python kernels, threads, the command line."""
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import lemke
from lemke import _cli, problems


def run_python(code, **env):
    e = dict(os.environ, **env)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=e, timeout=300)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_import_compiles_nothing():
    out = run_python(
        "import lemke, lemke.kernels.tableau as t, lemke.kernels.unrevised as u, lemke.kernels.pivoting as p, lemke.kernels.certify as c, lemke.kernels.linalg, lemke.kernels.cold as k\n"
        "print(sum(len(f.signatures) for f in (t.solve, t.lemke, t.pivot, t.lex_ties, u.solve, u.ratio_test, p.min_ratio, p.keep_lowest, p.first_row, c.lcp_check, c.lcp_ray_check, lemke.kernels.linalg.dot, lemke.kernels.linalg.axpy, lemke.kernels.linalg.equilibrate, k.checked, k.batch)))"
    )
    assert out.strip() == "0"


def test_kernels_run_as_plain_python():
    code = (
        "import numpy as np, lemke\n"
        "from lemke import problems\n"
        "from lemke.kernels import tableau\n"
        "assert not hasattr(tableau.lemke, 'signatures')  # really not compiled\n"
        "rng = np.random.default_rng(0)\n"
        "for M, q in [problems.random_psd(12, rng), problems.contact_like(15, rng), (problems.murty(5).M, problems.murty(5).q), ([[-1.0]], [-1.0])]:\n"
        "    r = lemke.solve_lcp(M, q)\n"
        "    print(r.status.name, r.pivots, repr(r.z.tolist()))\n"
    )
    plain = run_python(code, NUMBA_DISABLE_JIT="1")
    jitted = run_python(code.replace("assert not hasattr(tableau.lemke, 'signatures')  # really not compiled\n", ""))
    assert plain == jitted
    assert plain.count("SOLVED") == 3 and "RAY_TERMINATION" in plain


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
