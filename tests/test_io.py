"""Problems in files: every format round-trips, every peer file loads, every bad file gives
one ProblemFormatError naming the file and what is wrong."""
import io
import json
import os
import pickle
import zipfile
from pathlib import Path

import numpy as np
import pytest
import scipy.io

import lemke
from lemke import Problem, ProblemFormatError, problems
from lemke._io import FORMATS, matfile, npzfile, qps, siconos
from siconos_mlcp import LARGE_MLCP, unpacked

DATA = Path(__file__).parent / "data"
SICONOS_LCP = sorted((DATA / "siconos" / "lcp").glob("*.dat"))
SICONOS_MLCP = sorted((DATA / "siconos" / "mlcp").glob("*.dat"))
HOLDS = {"json": ("lcp", "mlcp", "qp", "bimatrix", "blcp"), "npz": ("lcp", "mlcp", "qp", "bimatrix", "blcp"),
         "dat": ("lcp", "mlcp", "blcp"), "mat": ("lcp", "mlcp", "qp"), "qps": ("qp",), "nfg": ("bimatrix",)}


def _qp_with_everything():
    """A QP with inequalities, equalities, infinite and negative bounds and a constant."""
    rng = np.random.default_rng(3)
    X = rng.standard_normal((4, 4))
    return Problem.qp(X @ X.T, rng.standard_normal(4), G=rng.standard_normal((3, 4)), h=rng.standard_normal(3),
                      A=rng.standard_normal((1, 4)), b=[0.5], lb=[-np.inf, 0.0, -1.0, 2.0],
                      ub=[np.inf, -0.0 + 3.0, -0.5, 2.0], objective_constant=1.25, name="everything",
                      source="made for the tests")


def _examples():
    out = [problems.NAMED[k]() for k in problems.NAMED]
    out.append(lemke.read_problem(DATA / "siconos" / "mlcp" / "RCD_mlcp.dat"))
    out.append(_qp_with_everything())
    out.append(Problem.qp(np.eye(2), [1.0, -1.0], name="no constraints", source="tests"))
    out.append(Problem.lcp(np.zeros((0, 0)), np.zeros(0), name="empty", source="tests"))
    out.append(Problem.blcp([[2.0, 1.0, 0.0], [1.0, 2.0, 0.5], [0.0, 0.5, 1.0]], [-1.0, 3.0, 0.5],
                            [0.0, -np.inf, -2.0], [1.5, 4.0, np.inf], name="box", source="tests"))
    return out


def same_problem(a: Problem, b: Problem):
    """Equal kinds and arrays; an absent bound counts as an infinite one."""
    assert a.kind == b.kind
    n = a.q.size if a.kind in ("lcp", "qp") else 0
    fill = {"lb": np.full(n, -np.inf), "ub": np.full(n, np.inf)}
    for key in set(a.arrays) | set(b.arrays):
        x, y = a.arrays.get(key, fill.get(key)), b.arrays.get(key, fill.get(key))
        assert x is not None and y is not None, f"{key} is missing on one side"
        np.testing.assert_array_equal(x, y, err_msg=key)
    assert a.objective_constant == b.objective_constant


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("prob", _examples(), ids=lambda p: p.name)
def test_round_trip(prob, fmt, tmp_path):
    path = tmp_path / f"problem.{fmt}"
    if prob.kind not in HOLDS[fmt]:
        with pytest.raises(ValueError, match="cannot hold"):
            lemke.write_problem(prob, path)
        assert not path.exists()
        return
    lemke.write_problem(prob, path)
    back = lemke.read_problem(path)
    same_problem(prob, back)
    if fmt in ("json", "npz"):  # these keep the name and the provenance
        assert (back.name, back.source) == (prob.name, prob.source)
    assert os.listdir(tmp_path) == [path.name]  # no temporary file left


def test_format_is_told_by_content_without_extension(tmp_path):
    for fmt in FORMATS:
        prob = {"qps": problems.hs21, "nfg": problems.bimatrix}.get(fmt, problems.cps_447)()
        path = tmp_path / f"problem-{fmt}"
        lemke.write_problem(prob, path, format=fmt)
        same_problem(prob, lemke.read_problem(path))


def test_a_binary_signature_beats_the_extension(tmp_path):
    path = tmp_path / "really-npz.json"
    lemke.write_problem(problems.cps_447(), path, format="npz")
    same_problem(problems.cps_447(), lemke.read_problem(path))


def test_reading_changes_nothing(tmp_path):
    path = tmp_path / "p.dat"
    lemke.write_problem(problems.murty(4), path)
    before, stat = path.read_bytes(), path.stat()
    lemke.read_problem(path)
    assert path.read_bytes() == before and path.stat().st_mtime_ns == stat.st_mtime_ns


def test_writing_is_atomic(tmp_path, monkeypatch):
    path = tmp_path / "p.json"
    lemke.write_problem(problems.cps_447(), path)
    before = path.read_bytes()

    def broken(problem, fh):
        fh.write(b"{half a file")
        raise RuntimeError("disk full")

    from lemke._io import jsonfile

    monkeypatch.setattr(jsonfile, "write", broken)
    with pytest.raises(RuntimeError):
        lemke.write_problem(problems.degenerate(), path)
    assert path.read_bytes() == before  # the old file is intact
    assert os.listdir(tmp_path) == ["p.json"]  # and the temporary file is gone


def test_write_problem_refuses_what_it_cannot_do(tmp_path):
    with pytest.raises(ValueError, match="format"):
        lemke.write_problem(problems.cps_447(), tmp_path / "p.txt")
    with pytest.raises(TypeError):
        lemke.write_problem({"M": [[1.0]], "q": [1.0]}, tmp_path / "p.json")
    lemke.write_problem(problems.cps_447(), tmp_path / "p.json")
    with pytest.raises(FileExistsError):
        lemke.write_problem(problems.cps_447(), tmp_path / "p.json", overwrite=False)


# --------------------------------------------------------------------------- peer files

@pytest.mark.parametrize("path", SICONOS_LCP, ids=lambda p: p.stem)
def test_siconos_lcp_files_load(path):
    p = lemke.read_problem(path)
    assert p.kind == "lcp" and p.name == path.stem and p.M.shape == (p.q.size, p.q.size)


def test_block_and_dense_storage_agree():
    for block in (p for p in SICONOS_LCP if p.stem.endswith("_block")):
        same_problem(lemke.read_problem(block), lemke.read_problem(block.with_name(block.name.replace("_block", ""))))


def _storage_1_only(text: str) -> str:
    """The same MLCP file with its storage-2 flag cleared (the reader must split M)."""
    words = text.split()
    return " ".join(words[:1] + ["0"] + words[2:])


@pytest.mark.parametrize("path", SICONOS_MLCP, ids=lambda p: p.stem)
def test_siconos_mlcp_files_load_and_both_storages_agree(path, tmp_path):
    p = lemke.read_problem(path)
    n, m = p.shape
    assert p.kind == "mlcp" and p.A.shape == (n, n) and p.B.shape == (m, m)
    other = tmp_path / path.name
    other.write_text(_storage_1_only(path.read_text()))
    if path.stem == "Rectangular_mlcp":  # its 3 x 2 M does not tile into A, B, C, D
        with pytest.raises(ProblemFormatError, match="expected 2 x 2"):
            lemke.read_problem(other)
    else:
        same_problem(p, lemke.read_problem(other))


@pytest.mark.parametrize("kind, count", [("lcp", 20), ("mlcp", 18)])
def test_siconos_files_load(kind, count, tmp_path):
    """Every Siconos file of the kind, with the two large MLCP files (compressed in tests/data)."""
    files = sorted((DATA / "siconos" / kind).glob("*.dat"))
    if kind == "mlcp":
        files += [unpacked(path, tmp_path) for path in LARGE_MLCP]
    assert len(files) == count
    for path in files:
        assert lemke.read_problem(path).kind == kind, path


def test_maros_meszaros_files_load_and_round_trip_through_qps(tmp_path):
    files = sorted((DATA / "maros-meszaros").glob("*.mat"))
    assert len(files) == 62
    for path in files:
        p = lemke.read_problem(path)
        assert p.kind == "qp" and p.name == path.stem
        if p.q.size <= 150:
            out = tmp_path / f"{path.stem}.qps"
            lemke.write_problem(p, out)
            same_problem(p, lemke.read_problem(out))


def test_maros_meszaros_conventions():
    # HS21 (tests/data/maros-meszaros/README.md): P = diag(0.02, 2), r = -100, 10 x1 - x2 >= 10,
    # 2 <= x1 <= 50, -50 <= x2 <= 50; the optimum -99.96 at (2, 0) counts r.
    p = lemke.read_problem(DATA / "maros-meszaros" / "HS21.mat")
    same_problem(p, problems.hs21())
    assert p.objective([2.0, 0.0]) == pytest.approx(-99.96)


def test_mat_equalities_ranges_and_infinities(tmp_path):
    # rows: an equality (u - l < 1e-10), a range, a <= row with -1e20, a >= row with 9.99e19.
    A = np.array([[1.0, 1.0], [1.0, -1.0], [2.0, 0.0], [0.0, 3.0], [1.0, 0.0], [0.0, 1.0]])
    l = np.array([1.0, -2.0, -1e20, 4.0, 0.0, -1e20])
    u = np.array([1.0 + 1e-12, 5.0, 7.0, 9.99999999999999e19, 1e20, 6.0])
    scipy.io.savemat(tmp_path / "t.mat", dict(P=np.eye(2), q=np.array([[1.0], [2.0]]), r=3.0, A=A, l=l[:, None],
                                             u=u[:, None], n=2.0, m=6.0))
    p = lemke.read_problem(tmp_path / "t.mat")
    np.testing.assert_array_equal(p.A, [[1.0, 1.0]])
    np.testing.assert_array_equal(p.b, [1.0 + 1e-12])
    # qpbenchmark's order: every finite upper side, then every finite lower side
    np.testing.assert_array_equal(p.G, [[1.0, -1.0], [2.0, 0.0], [-1.0, 1.0], [-0.0, -3.0]])
    np.testing.assert_array_equal(p.h, [5.0, 7.0, 2.0, -4.0])
    np.testing.assert_array_equal(p.lb, [0.0, -np.inf])
    np.testing.assert_array_equal(p.ub, [np.inf, 6.0])
    assert p.objective_constant == 3.0


def test_qps_reader_semantics(tmp_path):
    text = """* a comment
NAME          TESTQP
ROWS
 N  cost
 L  lim1
 G  lim2
 E  eq1
 E  eq2
COLUMNS
    x1   cost  1.0   lim1  1.0
    x1   lim2  1.0   eq1   1.0
    x2   cost  -2.0  lim1  1.0
    x2   eq2   1.0
    x3   cost  0.5   eq2   2.0
RHS
    rhs  cost  -4.5  lim1  4.0
    rhs  lim2  1.0   eq1   2.0
    rhs  eq2   3.0
RANGES
    rng  lim1  2.5   eq2  -1.0
BOUNDS
 UP bnd  x1  4.0
 MI bnd  x2
 UP bnd  x3  -1.0
QUADOBJ
    x1   x1   2.0
    x1   x2   -1.0
    x2   x2   4.0
ENDATA
"""
    path = tmp_path / "t.qps"
    path.write_text(text)
    p = lemke.read_problem(path)
    assert p.name == "TESTQP" and p.objective_constant == 4.5
    np.testing.assert_array_equal(p.P, [[2.0, -1.0, 0.0], [-1.0, 4.0, 0.0], [0.0, 0.0, 0.0]])
    np.testing.assert_array_equal(p.q, [1.0, -2.0, 0.5])
    # lim1 with range 2.5 -> 1.5 <= x1 + x2 <= 4; lim2 -> -x1 <= -1; eq2 with range -1 -> 2 <= x2 + 2 x3 <= 3
    np.testing.assert_array_equal(p.G, [[1.0, 1.0, 0.0], [-1.0, -1.0, 0.0], [-1.0, 0.0, 0.0],
                                        [0.0, 1.0, 2.0], [0.0, -1.0, -2.0]])
    np.testing.assert_array_equal(p.h, [4.0, -1.5, -1.0, 3.0, -2.0])
    np.testing.assert_array_equal(p.A, [[1.0, 0.0, 0.0]])
    np.testing.assert_array_equal(p.b, [2.0])
    # x2 free (MI), x3's negative UP with no lower bound set makes its lower bound -inf
    np.testing.assert_array_equal(p.lb, [0.0, -np.inf, -np.inf])
    np.testing.assert_array_equal(p.ub, [4.0, np.inf, -1.0])


def test_json_schema(tmp_path):
    doc = {"kind": "qp", "name": "tiny", "P": {"shape": [2, 2], "rows": [0, 1, 1], "cols": [0, 1, 1],
                                               "values": [2.0, 1.0, 1.0]},
           "q": [1, -1], "lb": [0, None], "ub": [None, 5], "objective_constant": -1}
    path = tmp_path / "t.json"
    path.write_text(json.dumps(doc))
    p = lemke.read_problem(path)
    np.testing.assert_array_equal(p.P, [[2.0, 0.0], [0.0, 2.0]])  # repeated positions add up
    np.testing.assert_array_equal(p.lb, [0.0, -np.inf])
    np.testing.assert_array_equal(p.ub, [np.inf, 5.0])
    assert p.G is None and p.objective_constant == -1.0 and p.name == "tiny"
    path.write_text(json.dumps({"M": [[1, 0], [0, 1]], "q": [-1, -1]}))  # kind inferred, name = stem
    p = lemke.read_problem(path)
    assert p.kind == "lcp" and p.name == "t"


def test_huge_sparse_json_matrix_is_written_in_coordinates(tmp_path):
    M = np.eye(30)
    lemke.write_problem(Problem.lcp(M, np.ones(30)), tmp_path / "big.json")
    doc = json.loads((tmp_path / "big.json").read_text())
    assert set(doc["M"]) == {"shape", "rows", "cols", "values"}
    np.testing.assert_array_equal(lemke.read_problem(tmp_path / "big.json").M, M)


# --------------------------------------------------------------------------- bad files

def _bad(path, *words):
    """read_problem fails with one line that names the file and says each of ``words``."""
    with pytest.raises(ProblemFormatError) as info:
        lemke.read_problem(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{path}: "), message
    for word in words:
        assert word in message, message
    assert isinstance(info.value, ValueError) and info.value.path == str(path)
    return message


def _bad_texts(path, cases: dict):
    """Each text of ``cases`` in ``path`` fails with a message that says its word."""
    for text, word in cases.items():
        path.write_text(text)
        _bad(path, word)


def test_missing_directory_and_unreadable(tmp_path):
    _bad(tmp_path / "nope.json", "cannot read", "No such file")
    _bad(tmp_path, "is a directory")
    link = tmp_path / "dangling.dat"
    link.symlink_to(tmp_path / "gone.dat")
    _bad(link, "cannot read")
    if os.geteuid() != 0:  # root reads anything
        locked = tmp_path / "locked.json"
        locked.write_text("{}")
        locked.chmod(0)
        _bad(locked, "cannot read", "ermission")


@pytest.mark.parametrize("ext", ["json", "npz", "dat", "mat", "qps", "txt"])
def test_empty_file(tmp_path, ext):
    (tmp_path / f"e.{ext}").write_bytes(b"")
    _bad(tmp_path / f"e.{ext}", "empty")
    (tmp_path / f"w.{ext}").write_bytes(b" \n\t\n")
    _bad(tmp_path / f"w.{ext}", "empty")


@pytest.mark.parametrize("ext", ["json", "npz", "dat", "mat", "qps"])
def test_random_bytes(tmp_path, ext):
    path = tmp_path / f"r.{ext}"
    path.write_bytes(np.random.default_rng(7).bytes(300))
    _bad(path)


def test_truncated_dat(tmp_path):
    text = (DATA / "siconos" / "lcp" / "lcp_mmc.dat").read_text()
    for cut in (1, 40, len(text) // 2):
        (tmp_path / "t.dat").write_text(text[:cut])
        _bad(tmp_path / "t.dat", "ends early")
    block = (DATA / "siconos" / "lcp" / "lcp_ortiz_block.dat").read_text()
    (tmp_path / "b.dat").write_text(block[: len(block) // 2])
    _bad(tmp_path / "b.dat", "ends early")
    mlcp = (DATA / "siconos" / "mlcp" / "PD_mlcp.dat").read_text()
    (tmp_path / "PD_mlcp.dat").write_text(mlcp[: len(mlcp) - 400])
    _bad(tmp_path / "PD_mlcp.dat", "ends early")


def test_dat_errors(tmp_path):
    path = tmp_path / "x.dat"
    cases = {
        "2\n0\n2\n2\n2 2\n1 0 0 1\n1 nope\n": "'nope' is not a number",
        "2\n0\n2\n2\n3 3\n1 0 0 1\n1 1\n": "sizes disagree",
        "2\n0\n2\n3\n2 3\n1 0 0 1 0 0\n1 1\n": "expected 2 x 2",
        "2\n2\n2\n2\n": "storage type 2",
        "-2\n0\n-2\n-2\n": "negative",
        "100000\n0\n100000\n100000\n100000 100000\n1 2 3\n": "too large",
        "2\n0\n2\n2\n2 2\n1 0 0 nan\n1 1\n": "NaN",
        "2\n0\n2\n2\n2 2\n1 0 0 inf\n1 1\n": "inf",
        "2.5\n": "integer",
    }
    _bad_texts(path, cases)


def test_malformed_json(tmp_path):
    path = tmp_path / "x.json"
    cases = {
        '{"M": [[1, 2], [3, 4]], "q": [1, 2]': "not valid JSON",
        '{"M": [[1, 2], [3, 4]], "q": [1, NaN]}': "NaN is not allowed",
        '{"M": [[1, 2], [3, Infinity]], "q": [1, 2]}': "Infinity is not allowed",
        '{"M": [[1, 2], [3]], "q": [1, 2]}': "rows of different lengths",
        '{"M": [[1, 2], [3, 4]], "q": [1, 2, 3]}': "q must have shape (2,) to match M",  # q is the odd one out
        '{"M": [[1, 2], [3, 4]], "q": [1, "2"]}': "must hold numbers",
        '{"M": [[1, 2], [3, 4]], "q": [1, true]}': "must hold numbers",
        '{"M": [[1, 2], [3, 4]], "q": [1, 2], "Q": 1}': "unknown key",
        '{"kind": "socp", "M": [[1]], "q": [1]}': "'kind' must be one of",
        '{"x": 1}': "cannot tell the kind",
        '[1, 2]': "must be an object",
        '{"kind": "qp", "P": [[1]], "q": [1], "G": [[1]]}': "G was given without h",
        '{"kind": "qp", "P": [[1]], "q": [1], "lb": [2], "ub": [1]}': "exceeds",
        '{"M": {"shape": [2, 2], "rows": [5], "cols": [0], "values": [1]}, "q": [1, 2]}': "outside its shape",
        '{"M": [[1e999]], "q": [1]}': "infinite entry",
        "[" * 100000: "nested too deeply",
    }
    _bad_texts(path, cases)


def test_npz_errors(tmp_path):
    path = tmp_path / "x.npz"
    np.savez(path, M=np.ones((2, 3)), q=np.ones(2))
    _bad(path, "M must have shape (2, 2)")
    np.savez(path, M=np.array([[np.nan]]), q=np.ones(1))
    _bad(path, "NaN")
    np.savez(path, M=np.array([[object()]], dtype=object), q=np.ones(1))
    _bad(path, "not a readable .npz")  # an object array would need pickle: refused
    np.savez(path, kind=np.array(3), M=np.eye(1), q=np.ones(1))
    _bad(path, "'kind' must be a 0-d string")
    np.savez(path, M=np.array([["a"]]), q=np.ones(1))
    _bad(path, "real numbers")
    np.savez(path, M=np.eye(1), q=np.ones(1))
    data = bytearray(path.read_bytes())
    central = data.index(b"PK\x01\x02")
    data[central + 6] = 0xFF  # "version needed to extract" beyond what zipfile knows
    path.write_bytes(bytes(data))
    _bad(path, "zip file version")
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("M.npy", b"not an array")
    _bad(path, "'M' is not a .npy array")


def test_mat_errors(tmp_path):
    path = tmp_path / "x.mat"
    scipy.io.savemat(path, {"P": np.eye(2), "q": np.ones(2)})
    _bad(path, "needs the variable 'A'")
    scipy.io.savemat(path, {"x": np.eye(2)})
    _bad(path, "Maros-Meszaros variables P, q, A, l, u", "found: x")
    scipy.io.savemat(path, {"P": np.eye(2), "q": np.ones(2), "A": np.eye(2), "l": np.zeros(2), "u": np.ones(3)})
    _bad(path, "u 3 entries")
    scipy.io.savemat(path, {"P": np.eye(2), "q": np.ones(2), "A": np.eye(2), "l": np.zeros(2), "u": np.ones(2), "n": 3})
    _bad(path, "'n' says 3")
    scipy.io.savemat(path, {"P": "text", "q": np.ones(2), "A": np.eye(2), "l": np.zeros(2), "u": np.ones(2)})
    _bad(path, "'P' must be a numeric array")
    scipy.io.savemat(path, {"P": np.array([[np.inf]]), "q": np.ones(1), "A": np.eye(1), "l": np.zeros(1), "u": np.ones(1)})
    _bad(path, "P has a NaN or infinite")


def test_qps_errors(tmp_path):
    path = tmp_path / "x.qps"
    head = "NAME t\nROWS\n N obj\n L c1\nCOLUMNS\n x1 obj 1 c1 1\n"
    cases = {
        head + "RHS\n rhs c1 1\n": "without ENDATA",
        head + " MARKER 'MARKER' 'INTORG'\nENDATA\n": "integer",
        head + "BOUNDS\n BV bnd x1\nENDATA\n": "integer",
        head + "BOUNDS\n UP bnd x9 1\nENDATA\n": "unknown column 'x9'",
        head + " x2 c9 1\nENDATA\n": "unknown row 'c9'",
        head + "QUADOBJ\n x1 x1 nan\nENDATA\n": "not a finite number",
        head + "QUADOBJ\n x1 x1 1\n x1 x1 2\nENDATA\n": "given twice",
        head + "OBJSENSE\n MAX\nENDATA\n": "only MIN",
        "NAME t\nROWS\n X c1\nENDATA\n": "row type 'X'",
        "NAME t\n x y\nENDATA\n": "outside any section",
    }
    _bad_texts(path, cases)


def test_unknown_format(tmp_path):
    path = tmp_path / "notes.txt"
    path.write_text("hello, this is not a problem\n")
    _bad(path, "unknown format", ".txt")
    with pytest.raises(ProblemFormatError, match="unknown format 'xls'"):
        lemke.read_problem(path, format="xls")


def test_hdf5_mat_is_named(tmp_path):
    path = tmp_path / "v73.mat"
    path.write_bytes(b"MATLAB 7.3 MAT-file".ljust(512, b" ") + b"\x89HDF\r\n\x1a\n" + bytes(100))
    _bad(path, "v7.3")


def test_formats_are_documented():
    # the modules say their layout; read_problem says how the format is chosen
    for module in (npzfile, siconos, matfile, qps):
        assert len(module.__doc__) > 200
    assert "ProblemFormatError" in lemke.read_problem.__doc__


# --------------------------------------------------------------------------- the container

def test_problem_copies_and_is_immutable():
    M, q = np.eye(2), np.array([-1.0, 1.0])
    p = Problem.lcp(M, q, name="x")
    M[0, 0] = 5.0
    assert p.M[0, 0] == 1.0  # a copy, not the caller's array
    with pytest.raises(ValueError):
        p.M[0, 0] = 2.0
    with pytest.raises(AttributeError):
        p.name = "y"
    with pytest.raises(AttributeError):
        p.P
    back = pickle.loads(pickle.dumps(p))
    same_problem(p, back)
    assert back.name == "x"


def test_problem_checks_its_input():
    with pytest.raises(ValueError, match="kind must be"):
        Problem("nlp", {})
    with pytest.raises(ValueError, match="needs M"):
        Problem("lcp", {"q": [1.0]})
    with pytest.raises(ValueError, match="unknown array"):
        Problem("lcp", {"M": [[1.0]], "q": [1.0], "P": [[1.0]]})
    with pytest.raises(ValueError, match=r"C must have shape \(1, 2\)"):
        Problem.mlcp([[1.0]], np.eye(2), [[1.0]], [[1.0], [1.0]], [1.0], [1.0, 1.0])
    with pytest.raises(ValueError, match="objective_constant"):
        Problem.qp([[1.0]], [1.0], objective_constant=float("nan"))
    with pytest.raises(TypeError):
        Problem.lcp([["a"]], [1.0])
    assert Problem.qp([[1.0, 0], [0, 1]], [0, 0], G=[1.0, 1.0], h=1.0).G.shape == (1, 2)  # one row


def test_problem_solves_each_kind():
    for prob in (problems.cps_447(), problems.hs21(), lemke.read_problem(DATA / "siconos" / "mlcp" / "RCD_mlcp.dat")):
        res = prob.solve(method="unrevised", options={"tol": 1e-9})
        assert res.success, (prob.name, res.message)
    assert problems.hs21().objective(problems.hs21().solve().x) == pytest.approx(-99.96)


def test_result_writer(tmp_path):
    prob = problems.hs21()
    res = prob.solve()
    lemke.write_result(res, tmp_path / "r.json", problem=prob, time_s=0.5)
    doc = json.loads((tmp_path / "r.json").read_text())
    assert doc["status"] == "SOLVED" and doc["objective"] == pytest.approx(-99.96) and doc["time_s"] == 0.5
    lemke.write_result(res, tmp_path / "r.npz", problem=prob)
    with np.load(tmp_path / "r.npz", allow_pickle=False) as z:
        np.testing.assert_array_equal(z["x"], res.x)
        assert str(z["status"]) == "SOLVED" and str(z["kind"]) == "qp"
    with pytest.raises(ValueError, match="over the input"):
        lemke.write_result(res, tmp_path / "r.json", protect=[tmp_path / "r.json"])
    with pytest.raises(ValueError, match=".json or .npz"):
        lemke.write_result(res, tmp_path / "r.txt")
    lemke.write_result([res, res], tmp_path / "two.json")
    assert len(json.loads((tmp_path / "two.json").read_text())) == 2


def test_result_dict_is_plain_json():
    res = problems.bimatrix_lcp().solve()
    doc = lemke.result_to_dict(res, problems.bimatrix_lcp())
    assert doc["status"] == "RAY_TERMINATION" and isinstance(doc["ray"], list)
    json.dumps(doc, allow_nan=False)
    assert io.StringIO(json.dumps(doc)).read()


def test_readme_json_examples_read(tmp_path):
    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    block = readme.split("```json\n", 1)[1].split("```", 1)[0]
    docs = [json.loads(line) for line in block.replace(",\n ", ", ").splitlines()]
    assert [d["kind"] for d in docs] == ["lcp", "mlcp", "qp"]
    for doc in docs:
        (tmp_path / "x.json").write_text(json.dumps(doc))
        assert lemke.read_problem(tmp_path / "x.json").solve().success
