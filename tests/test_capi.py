"""The C API (include/lemke.h), built by CMake with AddressSanitizer and
UndefinedBehaviorSanitizer and index checks (LEMKE_SANITIZE, a Debug build): the C example,
the C++ test (known answers, random problems checked independently, warm starts, bad
arguments), a seeded fuzz run, and every LCP of the goldens' problem table solved through the
C API under the sanitizers, its answers compared with Python's."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import lemke

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).parent))
import golden  # noqa: E402

# The CMake build of the C API with the sanitizers takes tens of seconds: not in the fast lane
# (`pytest -m "not slow"`); the README's test command runs it.
pytestmark = pytest.mark.slow


def _cmake():
    exe = shutil.which("cmake")
    if exe is None:
        try:
            import cmake  # the PyPI package (the test extra installs it)
            exe = str(Path(cmake.CMAKE_BIN_DIR) / "cmake")
        except ImportError:
            pytest.fail("cmake is needed to build the C API's tests (pip install cmake)")
    return exe


@pytest.fixture(scope="module")
def build(tmp_path_factory):
    out = tmp_path_factory.mktemp("capi-build")
    cmake = _cmake()
    args = [cmake, "-S", str(ROOT), "-B", str(out), "-DLEMKE_PYTHON=OFF", "-DLEMKE_TESTS=ON",
            "-DLEMKE_SANITIZE=ON", "-DCMAKE_BUILD_TYPE=Debug"]
    if shutil.which("ninja"):
        args += ["-G", "Ninja"]
    subprocess.run(args, check=True, capture_output=True, text=True)
    subprocess.run([cmake, "--build", str(out), "-j", "2"], check=True, capture_output=True,
                   text=True)
    return out


def _run(cmd, **kw):
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1:abort_on_error=0",
               UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1")
    return subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600, **kw)


def test_c_example_runs(build):
    r = _run([str(build / "lemke_example_c")])
    assert r.returncode == 0, r.stderr
    assert "SOLVED after 5 pivots: z = (0, 1, 3)" in r.stdout
    assert "warm: SOLVED after 0 pivots (basis reused: 1)" in r.stdout


def test_cpp_test_of_the_c_api(build):
    r = _run([str(build / "lemke_capi_test")])
    assert r.returncode == 0, r.stdout + r.stderr
    assert "all checks passed" in r.stdout


def test_fuzz_under_sanitizers(build):
    r = _run([str(build / "lemke_fuzz"), "20000", "20261128"])
    assert r.returncode == 0, r.stdout + r.stderr[-3000:]
    assert "20000 rounds, 0 bad" in r.stdout
    assert "ERROR: AddressSanitizer" not in r.stderr and "runtime error" not in r.stderr


def test_problem_table_under_sanitizers(build, tmp_path):
    """Every LCP of the goldens' table (Drake, DART, Siconos, built-in, random families)
    through the C API, under the sanitizers: a SOLVED answer passes the test's own
    complementarity check (computed in the C++ test in long double, not by the library),
    and the status, the pivots and z are Python's."""
    cases = list(golden.lcp_cases())
    path = tmp_path / "table.txt"
    with path.open("w") as f:
        for _, M, q in cases:
            n = len(q)
            f.write(f"{n}\n" + " ".join(repr(float(v)) for v in np.ravel(M)) + "\n"
                    + " ".join(repr(float(v)) for v in q) + "\n")
    r = _run([str(build / "lemke_capi_test"), str(path)])
    assert r.returncode == 0, r.stderr[-3000:]
    rows = [line.split() for line in r.stdout.splitlines()]
    assert len(rows) == len(cases)
    solved = 0
    for (name, M, q), row in zip(cases, rows):
        status, pivots, checked = (int(v) for v in row[:3])
        z = np.array([float(v) for v in row[3:]])
        assert checked == 1, name
        py = lemke.solve_lcp(M, q)
        # the same solve as solve_lcp (the same driver): the same status and pivots, and z
        # bit for bit unless the final point was recomputed from the basis (Python by
        # LAPACK, the C API by the core's LU)
        assert (status, pivots) == (int(py.status), py.pivots), name
        solved += status == 0
        if status in (0, 2):
            np.testing.assert_allclose(z, py.z, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(py.z).max(initial=0.0)))
    assert solved > 0.8 * len(cases)


def _box_cases():
    """Box LCPs of tests/test_blcp.py: the seeded family, the small integer fuzz, friction
    contacts and the pile of examples/box_pile.py (with its friction index)."""
    import test_blcp

    for seed in range(120):
        yield (*test_blcp.family(seed), None)
    rng = np.random.default_rng(12)
    for _ in range(200):
        n = int(rng.integers(1, 7))
        M = rng.integers(-2, 3, (n, n)).astype(float)
        if rng.random() < 0.5:
            M = M @ M.T
        q = rng.integers(-2, 3, n).astype(float)
        lo = rng.choice([-np.inf, -2.0, -1.0, 0.0], n)
        hi = np.maximum(rng.choice([0.0, 1.0, 2.0, np.inf], n), lo)
        yield M, q, lo, hi, None
    for seed in range(10):
        for k in (1, 3, 6):
            M, q, lo, hi, findex, _ = test_blcp.contacts(seed, k)
            yield M, q, lo, hi, findex
    for A, b, lo, hi, fi in test_blcp.pile_steps()[::4]:
        yield A, b, lo, hi, fi


def test_box_lcps_under_sanitizers(build, tmp_path):
    """lemke_blcp_solve on box LCPs (bounds of every kind, friction indices), under the
    sanitizers: a SOLVED answer passes the C++ test's own check, every status is Python's,
    and where Python's solve_blcp took the same number of pivots (its one-call path, which
    the C API repeats) z is the same, bit for bit."""
    cases = list(_box_cases())
    path = tmp_path / "boxes.txt"
    with path.open("w") as f:
        for M, q, lo, hi, fi in cases:
            n = len(q)
            f.write(f"{n} {0 if fi is None else 1}\n")
            for a in (M, q, lo, hi):
                f.write(" ".join(repr(float(v)) for v in np.ravel(a)) + "\n")
            if fi is not None:
                f.write(" ".join(str(int(v)) for v in fi) + "\n")
    r = _run([str(build / "lemke_capi_test"), "--blcp", str(path)])
    assert r.returncode == 0, r.stderr[-3000:]
    rows = [line.split() for line in r.stdout.splitlines()]
    assert len(rows) == len(cases)
    same = solved = 0
    for (M, q, lo, hi, fi), row in zip(cases, rows):
        status, pivots, checked = (int(v) for v in row[:3])
        z = np.array([float.fromhex(v) for v in row[3:]])
        assert checked == 1
        py = lemke.solve_blcp(M, q, lo, hi, findex=fi)
        assert status == int(py.status), (status, py)
        solved += status == 0
        if pivots == py.pivots:
            assert z.tobytes() == py.z.tobytes()
            same += 1
    print(f"\n  box LCPs through the C API: {len(cases)}, {solved} solved, {same} bit for bit with Python")
    assert solved > 0.8 * len(cases) and same > 0.95 * len(cases), (solved, same, len(cases))


def test_warm_box_lcps_under_sanitizers(build, tmp_path):
    """lemke_blcp_solve_warm: each box LCP's next step (q moved by 1e-9 of its size, and a
    step with another q) from the row states of Python's answer to this one: a SOLVED answer
    passes the C++ test's own check, every success is Python's (solve_blcp with
    BoxWarmStart.from_row_states), and where both took the same pivots z is the same, bit
    for bit."""
    rng = np.random.default_rng(3)
    cases = []
    for M, q, lo, hi, fi in _box_cases():
        r = lemke.solve_blcp(M, q, lo, hi, findex=fi)
        if r.warm_start is None:
            continue
        states = r.warm_start.row_states()
        scale = max(1.0, float(np.abs(q).max(initial=0.0)))
        for q2 in (q + 1e-9 * scale, rng.standard_normal(len(q)) * scale):
            cases.append((M, q2, lo, hi, fi, states))
    path = tmp_path / "warm.txt"
    with path.open("w") as f:
        for M, q, lo, hi, fi, states in cases:
            f.write(f"{len(q)} {0 if fi is None else 1}\n")
            for a in (M, q, lo, hi):
                f.write(" ".join(repr(float(v)) for v in np.ravel(a)) + "\n")
            if fi is not None:
                f.write(" ".join(str(int(v)) for v in fi) + "\n")
            f.write(" ".join(str(int(v)) for v in states) + "\n")
    r = _run([str(build / "lemke_capi_test"), "--blcp-warm", str(path)])
    assert r.returncode == 0, r.stderr[-3000:]
    rows = [line.split() for line in r.stdout.splitlines()]
    assert len(rows) == len(cases)
    same = solved = zero = alike = 0
    for (M, q, lo, hi, fi, states), row in zip(cases, rows):
        status, pivots, checked = (int(v) for v in row[:3])
        z = np.array([float.fromhex(v) for v in row[3:]])
        assert checked == 1
        py = lemke.solve_blcp(M, q, lo, hi, findex=fi,
                              warm_start=lemke.BoxWarmStart.from_row_states(states))
        assert (status == 0) == py.success, (status, py)
        solved += status == 0
        zero += status == 0 and pivots == 0
        if pivots == py.pivots and status == int(py.status):
            alike += 1  # (the same pivots: mostly the same runs; the C API's cold fallback
            same += z.tobytes() == py.z.tobytes()  # can meet Python's warm recovery's count)
    print(f"\n  warm box LCPs through the C API: {len(cases)}, {solved} solved ({zero} with 0 "
          f"pivots), {alike} with Python's pivots, {same} of them bit for bit")
    assert solved > 0.8 * len(cases) and zero > 0.3 * len(cases)
    assert alike > 0.9 * len(cases) and same > 0.98 * alike
