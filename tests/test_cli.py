"""The ``lemke`` command: exit codes (0 solved, 1 not solved, 2 bad input, 130 interrupted;
the worst over the sources), one-line errors naming the file and the argument, the other
sources still solved, options anywhere, --json, --out (atomic), several sources, built-in
problems, one short status line, Ctrl-C answered at once (a subprocess, SIGINT)."""
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import lemke
from lemke import _cli, problems

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).resolve().parents[1]


def run(capsys, *argv):
    """``(exit code, stdout, stderr)`` of ``lemke argv`` run in this process (nothing is
    compiled at run time: stderr holds only what the command says)."""
    code = _cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


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


def test_the_cli_loads_only_numpy_for_an_lcp(tmp_path):
    """``lemke solve`` on an LCP (the default problem, and a file) runs in the C++ core:
    the process loads no module outside the standard library, numpy and lemke (bar the
    private import hooks of an editable install), and says nothing about compiling."""
    import subprocess
    import sys
    path = tmp_path / "p.json"
    lemke.write_problem(problems.cps_447(), path)
    code = ("import sys; from lemke._cli import main; rc = main(['solve', sys.argv[1]]); "
            "other = sorted(m for m in {n.split('.')[0] for n in sys.modules} - set(sys.stdlib_module_names) "
            "if not m.startswith('_') and m not in ('lemke', 'numpy')); "
            "assert not other, other; sys.exit(rc)")
    for args in ([], [str(path)]):
        out = subprocess.run([sys.executable, "-c", code.replace("sys.argv[1]", repr(args[0])) if args
                              else code.replace("'solve', sys.argv[1]", "'solve'")],
                             capture_output=True, text=True, timeout=120)
        assert out.returncode == 0, out.stderr
        assert "SOLVED" in out.stdout and out.stderr == ""


# --------------------------------------------------------------------------- keeps going

def test_a_missing_or_unreadable_file_among_good_ones(capsys, tmp_path):
    good = tmp_path / "good.json"
    lemke.write_problem(problems.cps_447(), good)
    missing = tmp_path / "missing.json"
    unreadable = tmp_path / "dangling.json"  # a link to nothing: listed, but cannot be read
    unreadable.symlink_to(tmp_path / "gone.json")
    code, out, err = run(capsys, "solve", good, missing, "murty-3", unreadable, "nope", "murty-99", "--json")
    assert code == 2  # the worst outcome: input errors
    lines = err.splitlines()
    assert len(lines) == 4 and all(line.startswith("lemke: error: ") for line in lines), err
    for line, words in zip(lines, (["missing.json", "no such file"], ["dangling.json"],
                                   ["nope", "not a built-in problem"], ["murty-99", "1..30"])):
        assert all(w in line for w in words), line
    docs = json.loads(out)  # every source has its entry, in order; the good ones solved
    assert [Path(d["name"]).name for d in docs] == ["cps-4.4.7", "missing.json", "murty-3", "dangling.json",
                                                   "nope", "murty-99"]
    assert [d.get("status") for d in docs] == ["SOLVED", None, "SOLVED", None, None, None]
    assert all("error" in d for d in docs if "status" not in d)


def test_a_missing_file_among_good_ones_in_the_table(capsys, tmp_path):
    code, out, err = run(capsys, "solve", "murty-3", tmp_path / "missing.json", "degenerate")
    assert code == 2
    one_error_line(err, "missing.json", "no such file or directory")
    lines = out.splitlines()
    assert any(line.startswith("murty-3") and "SOLVED" in line for line in lines)
    assert any(line.startswith("degenerate") and "SOLVED" in line for line in lines)
    assert any(line.startswith(str(tmp_path / "missing.json")) and "ERROR" in line for line in lines)
    assert "3 problems: 2 solved, 0 not solved, 1 bad input" in out


@pytest.mark.parametrize("argv, expected", [
    (["murty-3", "degenerate"], 0),
    (["murty-3", "bimatrix-lcp", "degenerate"], 1),  # one ends on a ray
    (["murty-3", "bimatrix-lcp", "no-such-problem"], 2),  # and one cannot be read
    (["no-such-problem", "bimatrix-lcp"], 2),
])
def test_the_exit_code_is_the_worst_outcome(capsys, argv, expected):
    code, _, _ = run(capsys, "solve", *argv)
    assert code == expected


def test_options_may_stand_between_sources(capsys, tmp_path):
    code, out, err = run(capsys, "solve", "murty-3", "--json", "murty-4", "--max-pivots", "3", "degenerate",
                         "--out", tmp_path / "r.json")
    assert err == "" and code == 1  # murty-3 and murty-4 stop at the pivot limit
    docs = json.loads(out)
    assert [d["name"] for d in docs] == ["murty-3", "murty-4", "degenerate"]
    assert [d["status"] for d in docs] == ["MAX_PIVOTS", "MAX_PIVOTS", "SOLVED"]
    assert json.loads((tmp_path / "r.json").read_text()) == docs
    done = _lemke("solve", "degenerate", "--json", "murty-3")  # the same through python -m
    assert done.returncode == 0, done.stderr
    assert [d["name"] for d in json.loads(done.stdout)] == ["degenerate", "murty-3"]


@pytest.mark.parametrize("doc, words", [
    # a q of the wrong length is a wrong q, not a wrong M (M is square and fixes n)
    ({"M": [[2, 1], [1, 2]], "q": [1, 2, 3]}, ["q must have shape (2,) to match M", "got shape (3,)"]),
    ({"M": [[2, 1, 0], [1, 2, 0]], "q": [1, 2]}, ["M must have shape (2, 2)", "got shape (2, 3)"]),
    ({"kind": "blcp", "M": [[2, 1], [1, 2]], "q": [1, 2, 3], "lo": [0, 0], "hi": [1, 1]}, ["q must have shape (2,)"]),
    ({"kind": "blcp", "M": [[2, 1], [1, 2]], "q": [1, 2, 3], "lo": [0, 0, 0], "hi": [1, 1, 1]},
     ["M must have shape (3, 3) to match q, lo and hi"]),
    ({"P": [[2, 0], [0, 2]], "q": [1, 2, 3]}, ["q must have shape (2,) to match P"]),
    ({"P": [[2, 0], [0, 2]], "q": [1, 2], "G": [[1, 0, 0]], "h": [1]}, ["G must have 2 columns"]),
    ({"A": [[2]], "B": [[1]], "C": [[1]], "D": [[-1]], "a": [-1, 2], "b": [-1]}, ["a must have shape (1,)"]),
    ({"A": [[2]], "B": [[1]], "C": [[1]], "D": [[-1]], "a": [-1], "b": [-1, 3]}, ["b must have shape (1,)"]),
    ({"A": [[2, 0], [0, 2]], "B": [[1]], "C": [[1]], "D": [[-1]], "a": [-1], "b": [-1]}, ["A must have shape (1, 1)"]),
])
def test_a_wrong_size_names_the_argument_that_differs(capsys, tmp_path, doc, words):
    path = tmp_path / "p.json"
    path.write_text(json.dumps(doc))
    code, out, err = run(capsys, "solve", path)
    assert code == 2 and out == ""
    one_error_line(err, "p.json", *words)


# --------------------------------------------------------------------------- the status line

@pytest.mark.parametrize("name, words", [
    ("cps-4.4.7", ["SOLVED: z >= 0, w = Mz + q >= 0 and z'w = 0"]),
    ("hs21", ["SOLVED: optimal", "KKT"]),
    ("bimatrix", ["SOLVED: a Nash equilibrium"]),
    ("bimatrix-lcp", ["RAY_TERMINATION: ended on a secondary ray"]),
])
def test_the_status_is_one_short_line_for_the_kind(capsys, name, words):
    code, out, _ = run(capsys, "solve", name)
    line = next(line for line in out.splitlines() if line.startswith("  status"))
    assert len(line) <= 120, line
    for word in words:
        assert word in line, line
    for other in ("MLCP", "box LCP", "QP", "game"):  # not every kind's conditions at once
        assert other not in line, line


def test_every_kind_has_a_short_solved_line(tmp_path, capsys):
    from lemke._kinds import KINDS

    lines = {k.solved for k in KINDS.values()}
    assert len(lines) == len(KINDS) and all(len(line) <= 90 for line in lines)
    # a box LCP and an MLCP file, through the command line
    code, out, _ = run(capsys, "solve", DATA / "siconos" / "relay" / "relay_2x2.dat")
    assert code == 0 and f"SOLVED: {KINDS['blcp'].solved}" in out
    code, out, _ = run(capsys, "solve", DATA / "siconos" / "mlcp" / "RCD_mlcp.dat")
    assert code == 0 and f"SOLVED: {KINDS['mlcp'].solved}" in out
    assert lemke.Status.SOLVED.message not in out  # the API's long message stays in --json
    code, out, _ = run(capsys, "solve", "murty-3", "--json")
    assert json.loads(out)["message"] == lemke.Status.SOLVED.message


def test_the_not_solved_lines_speak_of_the_options(capsys):
    code, out, _ = run(capsys, "solve", "murty-10", "--max-pivots", "5")
    assert code == 1 and "MAX_PIVOTS: stopped at the pivot limit; raise --max-pivots" in out


# --------------------------------------------------------------------------- --out, interrupts

def test_several_results_replace_the_out_file_atomically(capsys, tmp_path):
    out = tmp_path / "r.json"
    out.write_text("old")
    inode = out.stat().st_ino
    code, _, _ = run(capsys, "solve", "degenerate", "murty-3", "--out", out)
    assert code == 0 and [d["name"] for d in json.loads(out.read_text())] == ["degenerate", "murty-3"]
    assert out.stat().st_ino != inode  # a new file moved over the old one, not the old one rewritten
    assert os.listdir(tmp_path) == ["r.json"]  # no temporary file left


def test_an_interrupt_reports_and_writes_the_finished_sources(capsys, monkeypatch, tmp_path):
    solve = lemke.Problem.solve

    def interrupted_at_murty(self, *args, **kwargs):
        if self.name.startswith("murty"):
            raise KeyboardInterrupt
        return solve(self, *args, **kwargs)

    monkeypatch.setattr(lemke.Problem, "solve", interrupted_at_murty)
    out = tmp_path / "r.json"
    code, stdout, err = run(capsys, "solve", "degenerate", "cps-4.4.7", "murty-3", "hs21", "--json", "--out", out)
    assert code == 130 and err == "lemke: interrupted\n"
    names = ["degenerate", "cps-4.4.7"]
    assert [d["name"] for d in json.loads(stdout)] == names
    assert [d["name"] for d in json.loads(out.read_text())] == names
    assert os.listdir(tmp_path) == ["r.json"]
    code, stdout, err = run(capsys, "solve", "degenerate", "murty-3", "hs21")
    assert code == 130 and "1 problems: 1 solved" in stdout and "interrupted, 2 not run" in stdout


def _start_time():
    """Seconds a small `python -m lemke solve` takes here (its kernels then cached on disk)."""
    t0 = time.perf_counter()
    done = _lemke("solve", "murty-3")
    assert done.returncode == 0, done.stderr
    return time.perf_counter() - t0


@pytest.mark.parametrize("sources, finished", [
    (["murty-28"], None),  # nothing finished: no --out written
    (["murty-3", "degenerate", "murty-28", "murty-4"], ["murty-3", "degenerate"]),
])
def test_ctrl_c_stops_a_running_kernel_at_once(tmp_path, record_property, sources, finished):
    """SIGINT while Lemke's method runs on Murty's problem at n = 28 (2^28 pivots, a minute or
    more; the kernel does not look at signals): exit 130 at once (the target is 0.1 s; the
    bound asserted is loose, for a loaded CI machine), one line on stderr, and the results
    finished before it in --out, whole (or no --out at all), no temporary file left."""
    wait = _start_time() + 1.0  # by then the kernel has been running for about a second
    out = tmp_path / "r.json"
    child = subprocess.Popen([sys.executable, "-m", "lemke", "solve", *sources, "--max-pivots", "1000000000",
                              "--json", "--out", str(out)], cwd=ROOT, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=dict(os.environ, PYTHONPATH=str(ROOT)))
    try:
        time.sleep(wait)
        assert child.poll() is None, "murty-28 ended before the interrupt"
        t0 = time.perf_counter()
        child.send_signal(signal.SIGINT)
        code = child.wait(timeout=60)
        latency = time.perf_counter() - t0
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    stdout, stderr = child.stdout.read(), child.stderr.read()
    child.stdout.close()
    child.stderr.close()
    print(f"SIGINT to exit: {latency * 1e3:.1f} ms")
    record_property("sigint_latency_s", latency)
    assert code == 130, stderr
    assert latency < 2.0
    assert stderr == "lemke: interrupted\n"
    if finished is None:
        assert stdout == "" and not out.exists()
    else:
        assert [d["name"] for d in json.loads(stdout)] == finished
        assert [d["name"] for d in json.loads(out.read_text())] == finished
    assert os.listdir(tmp_path) == (["r.json"] if finished else [])


def test_quiet_silences_the_progress_line(monkeypatch):
    """Several sources on a terminal get a progress line on stderr; --quiet none."""
    from lemke._cli import _parser, _Progress
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    assert _Progress(3).on and not _Progress(1).on
    args = _parser().parse_args(["solve", "a.json", "--quiet", "b.json"])
    assert args.quiet and args.source == ["a.json", "b.json"]
    assert not _Progress(3, args.quiet).on
