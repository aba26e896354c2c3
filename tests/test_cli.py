"""The ``lemke`` command: exit codes (0 solved, 1 not solved, 2 bad input, 130 interrupted),
one-line errors naming the file, --json, --out, several sources, built-in problems."""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import lemke
from lemke import _cli, problems

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).resolve().parents[1]


def run(capsys, *argv):
    """``(exit code, stdout, stderr)`` of ``lemke argv`` run in this process.  The one-line
    notice that numba is compiling (on a cold cache, e.g. in CI) is taken out of stderr: it
    depends on which tests ran before; ``test_compiling_is_announced_once`` checks it."""
    code = _cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err.replace(_cli.COMPILE_NOTICE + "\n", "")


def one_error_line(err: str, *words):
    assert err.startswith("lemke: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err
    for word in words:
        assert word in err, err


def test_no_source_solves_the_default_example(capsys):
    code, out, err = run(capsys, "solve")
    assert code == 0 and err == ""
    assert "built-in example 'cps-4.4.7'" in out
    for word in ("SOLVED", "pivots     5", "residual   0", "time", "z          [0., 1., 3.]"):
        assert word in out, out


@pytest.mark.parametrize("name", list(problems.NAMED))
def test_every_builtin_problem(capsys, name):
    code, out, err = run(capsys, "solve", name)
    expected = 1 if name == "bimatrix-lcp" else 0  # Lemke with d = 1 ends on a ray on the game
    assert code == expected, out + err
    assert ("RAY_TERMINATION" if expected else "SOLVED") in out


def test_problems_lists_every_builtin_with_its_source(capsys):
    code, out, _ = run(capsys, "problems")
    assert code == 0
    for fn in problems.NAMED.values():
        p = fn()
        assert (p.name if not p.name.startswith("murty") else "murty-N") in out
        assert p.source in out
    for word in ("bimatrix", "contact-box", "hs21", "QP", "Cottle"):
        assert word in out


def test_a_qp_shows_its_objective_with_the_constant(capsys):
    code, out, _ = run(capsys, "solve", "hs21")
    assert code == 0 and "objective  -99.96 (incl. the constant -100)" in out


def test_several_sources_give_a_summary_table(capsys):
    code, out, err = run(capsys, "solve", DATA / "siconos" / "lcp", "murty-4", DATA / "siconos" / "mlcp" / "RCD_mlcp.dat")
    assert code == 1  # two Siconos files end on a ray
    assert err == ""  # no progress bar when stderr is not a terminal
    lines = out.splitlines()
    assert lines[0].split() == ["name", "kind", "size", "status", "pivots", "residual", "time"]
    assert any(line.startswith("lcp_CPS_3.dat") and "RAY_TERMINATION" in line for line in lines)
    assert any(line.startswith("murty-4") and " 16 " in line for line in lines)
    assert any(line.startswith("RCD_mlcp.dat") and "2+1" in line for line in lines)
    assert "22 problems: 20 solved, 2 not solved, 0 bad input" in out


def test_directory_is_read_sorted(capsys):
    code, out, _ = run(capsys, "solve", DATA / "siconos" / "mlcp", "--json")
    docs = json.loads(out)
    names = [d["name"] for d in docs]
    assert code == 0 and names == sorted(names) and len(names) == 16
    assert all(d["kind"] == "mlcp" and d["success"] for d in docs)


def test_json_is_the_only_stdout(capsys):
    code, out, err = run(capsys, "solve", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["status"] == "SOLVED" and doc["z"] == [0.0, 1.0, 3.0]
    assert doc["pivots"] == 5 and doc["name"] == "cps-4.4.7" and "time_s" in doc
    assert "built-in example" in err  # the note goes to stderr under --json


def test_options_reach_the_solver(capsys):
    code, out, _ = run(capsys, "solve", "murty-10", "--max-pivots", "5", "--json")
    doc = json.loads(out)
    assert code == 1 and doc["status"] == "MAX_PIVOTS" and doc["pivots"] == 5
    code, out, _ = run(capsys, "solve", "murty-10", "--method", "unrevised", "--tol", "1e-8",
                       "--pivot-tol", "1e-12", "--tie-tol", "0", "--json")
    assert code == 0 and json.loads(out)["pivots"] == 1024


@pytest.mark.parametrize("argv, words", [
    (["solve", "--max-pivots", "-1"], ["--max-pivots", "must be >= 0"]),
    (["solve", "--max-pivots", "x"], ["--max-pivots", "integer"]),
    (["solve", "--tol", "2"], ["--tol", "[0, 1)"]),
    (["solve", "--tol", "nan"], ["--tol"]),
    (["solve", "--method", "simplex"], ["--method", "simplex"]),
    (["solve", "nope"], ["nope: no such file, and not a built-in problem"]),
    (["solve", "murty-99"], ["murty-99", "1..30"]),
    (["solve", "--bogus"], ["--bogus"]),
    (["frobnicate"], ["frobnicate"]),
    ([], ["no command"]),
])
def test_usage_errors(capsys, argv, words):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    one_error_line(err, *words)


def _bad_files(tmp_path):
    rng = np.random.default_rng(0)
    mmc = (DATA / "siconos" / "lcp" / "lcp_mmc.dat").read_text()
    files = {
        "missing.json": (None, "no such file or directory"),
        "empty.dat": (b"", "empty"),
        "random.npz": (rng.bytes(200), "npz"),
        "random.mat": (rng.bytes(200), "mat"),
        "truncated.dat": (mmc[: len(mmc) // 2].encode(), "ends early"),
        "malformed.json": (b'{"M": [[1]], "q": [1]', "not valid JSON"),
        "nan.json": (b'{"M": [[NaN]], "q": [1]}', "NaN"),
        "inf.dat": (b"1 0 1 1 1 1 inf -1", "inf"),
        "shapes.json": (b'{"M": [[1, 2]], "q": [1]}', "shape"),
        "unknown.xyz": (b"hello", "unknown format"),
        "fields.mat": (None, "needs the Maros-Meszaros variables"),
    }
    for name, (content, _) in files.items():
        if content is not None:
            (tmp_path / name).write_bytes(content)
    import scipy.io

    scipy.io.savemat(tmp_path / "fields.mat", {"x": np.eye(2)})
    return {tmp_path / name: word for name, (_, word) in files.items()}


def test_every_bad_file_gives_one_line_and_exit_2(capsys, tmp_path):
    for path, word in _bad_files(tmp_path).items():
        code, out, err = run(capsys, "solve", path)
        assert code == 2, path
        one_error_line(err, str(path), word)


def test_a_bad_file_among_good_ones(capsys, tmp_path):
    (tmp_path / "bad.json").write_text("{")
    lemke.write_problem(problems.cps_447(), tmp_path / "good.json")
    code, out, err = run(capsys, "solve", tmp_path)
    assert code == 2  # the good one is still solved and reported
    one_error_line(err, "bad.json", "not valid JSON")
    assert "good.json" in out and "SOLVED" in out and "1 bad input" in out


def test_a_directory_without_problems(capsys, tmp_path):
    (tmp_path / "notes.txt").write_text("nothing here")
    code, _, err = run(capsys, "solve", tmp_path)
    assert code == 2
    one_error_line(err, str(tmp_path), "no problem files")


def test_solver_refusal_is_an_input_error(capsys, tmp_path):
    lemke.write_problem(lemke.Problem.qp([[1.0, 0.0], [0.0, -1.0]], [0.0, 0.0]), tmp_path / "nonconvex.json")
    code, _, err = run(capsys, "solve", tmp_path / "nonconvex.json")
    assert code == 2
    one_error_line(err, "nonconvex.json", "positive semidefinite")


def test_out_writes_json_and_npz(capsys, tmp_path):
    code, _, _ = run(capsys, "solve", "degenerate", "--out", tmp_path / "r.json")
    doc = json.loads((tmp_path / "r.json").read_text())
    assert code == 0 and doc["z"] == [0.0, 0.5]
    code, _, _ = run(capsys, "solve", "hs21", "--out", tmp_path / "r.npz")
    with np.load(tmp_path / "r.npz", allow_pickle=False) as z:
        assert code == 0 and z["x"].tolist() == [2.0, 0.0] and float(z["objective"]) == pytest.approx(-99.96)
    code, _, _ = run(capsys, "solve", "degenerate", "murty-3", "--out", tmp_path / "two.json")
    assert code == 0 and [d["name"] for d in json.loads((tmp_path / "two.json").read_text())] == ["degenerate", "murty-3"]
    assert sorted(os.listdir(tmp_path)) == ["r.json", "r.npz", "two.json"]  # nothing else left


def test_out_never_overwrites_an_input(capsys, tmp_path):
    path = tmp_path / "p.json"
    lemke.write_problem(problems.cps_447(), path)
    before = path.read_bytes()
    code, out, err = run(capsys, "solve", path, "--out", path)
    assert code == 2 and out == ""
    one_error_line(err, "refusing to write over the input file")
    assert path.read_bytes() == before


@pytest.mark.parametrize("target, words", [
    ("r.txt", [".json or .npz"]),
    ("missing-dir/r.json", ["cannot write"]),
])
def test_out_errors(capsys, tmp_path, target, words):
    code, _, err = run(capsys, "solve", "--out", tmp_path / target)
    assert code == 2
    one_error_line(err, *words)


def test_several_results_are_not_written_as_npz(capsys, tmp_path):
    code, _, err = run(capsys, "solve", "degenerate", "murty-3", "--out", tmp_path / "r.npz")
    assert code == 2
    one_error_line(err, "as .json")


def test_interrupt_gives_130(capsys, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(lemke.Problem, "solve", interrupted)
    code, _, err = run(capsys, "solve", "degenerate")
    assert code == 130 and err == "lemke: interrupted\n"


def test_an_internal_error_is_one_line(capsys, monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("something\nunexpected")

    monkeypatch.setattr(_cli, "_sources", broken)
    monkeypatch.delenv("LEMKE_TRACEBACK", raising=False)
    code, _, err = run(capsys, "solve", "degenerate")
    assert code == 2
    one_error_line(err, "internal error", "RuntimeError", "something unexpected")


def test_progress_bar_only_on_a_terminal(capsys, monkeypatch):
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    code, out, err = run(capsys, "solve", "degenerate", "murty-3")
    assert code == 0 and "[" in err and "2/2" not in out


def _lemke(*argv, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "lemke", *map(str, argv)], capture_output=True, text=True,
                          cwd=cwd, timeout=300, env=dict(os.environ, PYTHONPATH=str(ROOT)))


@pytest.mark.slow
def test_python_dash_m_in_a_subprocess(tmp_path):
    done = _lemke("solve", "--json")
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["status"] == "SOLVED"
    done = _lemke("solve", DATA / "siconos" / "lcp", "--json")
    assert done.returncode == 1 and len(json.loads(done.stdout)) == 20
    (tmp_path / "bad.dat").write_bytes(b"\x00\xff garbage")
    done = _lemke("solve", tmp_path / "bad.dat")
    assert done.returncode == 2 and done.stdout == ""
    one_error_line(done.stderr, "bad.dat")
    done = _lemke("solve", "--max-pivots", "-3")
    assert done.returncode == 2
    one_error_line(done.stderr, "--max-pivots")


def test_solve_a_gambit_game_file(capsys, tmp_path):
    # von Stengel's 3 x 2 game in Gambit's payoff version (row player's strategy fastest)
    path = tmp_path / "game.nfg"
    path.write_text('NFG 1 R "3x2" { "P1" "P2" } { 3 2 }\n3 3 2 2 0 3 3 2 5 6 6 1\n')
    code, out, err = run(capsys, "solve", str(path))
    assert code == 0, out + err
    assert "BIMATRIX" in out and "x          [1., 0., 0.]" in out and "y          [1., 0.]" in out
    code, out, err = run(capsys, "solve", str(path), "--method", "tracing")
    assert code == 0 and "SOLVED" in out
    bad = tmp_path / "bad.nfg"
    bad.write_text('NFG 1 R "x" { "P1" "P2" } { 2 2 }\n1 2 3\n')
    code, out, err = run(capsys, "solve", str(bad))
    assert code == 2 and err.count("\n") == 1 and str(bad) in err


@pytest.mark.parametrize("name, z", [("relay_2x2.dat", [0.5, -0.5]), ("relay_4x4.dat", [1.0, 0.5, -0.5, -1.0])])
def test_siconos_relay_files_solve_as_box_lcps(capsys, name, z):
    """Siconos' relay files (n, M, q, lb, ub) are box LCPs; their answers are Siconos' own."""
    code, out, err = run(capsys, "solve", DATA / "siconos" / "relay" / name, "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["kind"] == "blcp" and doc["status"] == "SOLVED"
    assert np.allclose(doc["z"], z, atol=1e-12)


def test_compiling_is_announced_once(capsys, monkeypatch):
    # numba raises "numba:compile" only when it compiles (a cache miss); here the event is
    # raised by hand, twice, inside a solve.  The real thing, on an empty cache, is checked
    # in the bounds-checked child process (test_boundscheck.py).
    from numba.core import event

    def solve_that_compiles(args):
        for _ in range(2):
            with event.trigger_event("numba:compile", data={}):
                pass
        return 0

    monkeypatch.setattr(_cli._CompileNotice, "said", False)
    monkeypatch.setattr(_cli, "_solve", solve_that_compiles)
    assert _cli.main(["solve"]) == 0 and _cli.main(["solve"]) == 0
    out, err = capsys.readouterr()
    assert out == "" and err == _cli.COMPILE_NOTICE + "\n"

