"""Fuzzing the readers: random bytes, random tokens and mutated valid files only ever give a
valid Problem or the documented ProblemFormatError (one line naming the file) -- never another
exception, never a crash, never a huge allocation."""
import io
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lemke
from lemke import ProblemFormatError, problems
from lemke._io import _MODULES

DATA = Path(__file__).parent / "data"
EXTENSIONS = ["json", "npz", "dat", "mat", "qps", "bin"]
FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def _valid_files() -> dict:
    """One valid file's bytes per format (an LCP, an MLCP and QPs)."""
    out = {}
    for name, prob in [("lcp.json", problems.cps_447()), ("qp.json", problems.hs21()), ("lcp.npz", problems.murty(3)),
                       ("qp.mat", problems.hs21()), ("lcp.mat", problems.degenerate()), ("qp.qps", problems.hs21())]:
        buf = io.BytesIO()
        _MODULES[name.split(".")[1]].write(prob, buf)
        out[name] = buf.getvalue()
    out["lcp.dat"] = (DATA / "siconos" / "lcp" / "lcp_ortiz.dat").read_bytes()
    out["block.dat"] = (DATA / "siconos" / "lcp" / "lcp_ortiz_block.dat").read_bytes()
    out["m3n2_mlcp.dat"] = (DATA / "siconos" / "mlcp" / "m3n2_mlcp.dat").read_bytes()
    return out


VALID = _valid_files()


def read_or_documented_error(path: Path):
    """The reader's contract: a Problem, or a ProblemFormatError of one line naming the file."""
    try:
        prob = lemke.read_problem(path)
    except ProblemFormatError as exc:
        message = str(exc)
        assert message.startswith(f"{path}: ") and "\n" not in message and exc.reason
        return None
    assert isinstance(prob, lemke.Problem) and prob.kind in ("lcp", "mlcp", "qp")
    for a in prob.arrays.values():
        assert a.dtype == np.float64 and not np.isnan(a).any()
    return prob


@FUZZ
@given(data=st.binary(max_size=2000), ext=st.sampled_from(EXTENSIONS))
def test_random_bytes(tmp_path, data, ext):
    path = tmp_path / f"fuzz.{ext}"
    path.write_bytes(data)
    read_or_documented_error(path)


_TOKEN = st.one_of(
    st.integers(-3, 12).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["nan", "inf", "-0", "1e400", "0x10", "1_0", "\u0663", "--1", "", "NAME", "ROWS", "ENDATA"]),
)


@FUZZ
@given(tokens=st.lists(_TOKEN, max_size=60), ext=st.sampled_from(["dat", "qps", "json"]),
       sep=st.sampled_from([" ", "\n", "\t"]))
def test_random_tokens(tmp_path, tokens, ext, sep):
    # Small integers reach deep into the .dat parser (sizes, storage types, block counts).
    path = tmp_path / f"fuzz_mlcp.{ext}" if tokens[:1] == ["1"] else tmp_path / f"fuzz.{ext}"
    path.write_text(sep.join(tokens))
    read_or_documented_error(path)


def _mutate(data: bytes, op: str, at: int, size: int, junk: bytes) -> bytes:
    at = at % (len(data) + 1)
    if op == "truncate":
        return data[:at]
    if op == "delete":
        return data[:at] + data[at + size:]
    if op == "insert":
        return data[:at] + junk + data[at:]
    if op == "overwrite":
        return data[:at] + junk + data[at + len(junk):]
    return data[:at] + data[at:at + size] * 3 + data[at + size:]  # "repeat"


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(name=st.sampled_from(sorted(VALID)), ops=st.lists(
    st.tuples(st.sampled_from(["truncate", "delete", "insert", "overwrite", "repeat"]), st.integers(0, 10**6),
              st.integers(1, 40), st.binary(min_size=1, max_size=12)), min_size=1, max_size=3))
def test_mutated_valid_files(tmp_path, name, ops):
    data = VALID[name]
    for op in ops:
        data = _mutate(data, *op)
    path = tmp_path / name
    path.write_bytes(data)
    read_or_documented_error(path)


@pytest.mark.parametrize("name", sorted(VALID))
def test_the_unmutated_files_are_valid(tmp_path, name):
    path = tmp_path / name
    path.write_bytes(VALID[name])
    assert read_or_documented_error(path) is not None


@FUZZ
@given(text=st.text(max_size=300))
def test_random_text_as_json_and_qps(tmp_path, text):
    for ext in ("json", "qps"):
        path = tmp_path / f"fuzz.{ext}"
        path.write_bytes(text.encode("utf-8", errors="replace"))
        read_or_documented_error(path)
