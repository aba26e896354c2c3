"""The core's one status vocabulary (src/lemke/status.hpp) and its mappings to the public
statuses: every kernel code declared in the header is in its table KERNEL_CODES, maps through
the C API's one mapping (src/capi_status.hpp, ``c_status``) to a value of lemke.h's enum
lemke_status, whose numbers (an ABI) do not change; the LCP driver's codes map to the same
public status in C++ (``lcp_status``) and in Python (``_layout.public_status``)."""
import re
from pathlib import Path

import numpy as np

from lemke import Status, _core, _layout

ROOT = Path(__file__).resolve().parents[1]

#: lemke.h's enum lemke_status: an ABI, these numbers for good.
ABI = {"LEMKE_SOLVED": 0, "LEMKE_MAX_PIVOTS": 1, "LEMKE_RAY_TERMINATION": 2,
       "LEMKE_NUMERICAL_FAILURE": 3, "LEMKE_CYCLING": 6, "LEMKE_TIME_LIMIT": 7,
       "LEMKE_INTERRUPTED": 8, "LEMKE_NOT_FINITE": -1, "LEMKE_INVALID_ARGUMENT": -3,
       "LEMKE_OUT_OF_MEMORY": -4}


def _header_codes():
    """Every ``constexpr int NAME = ...;`` of status.hpp, named as KERNEL_CODES names it
    (``boxed::BAD_BOUNDS``), read from the source."""
    names, scope = [], []
    for line in (ROOT / "src/lemke/status.hpp").read_text().splitlines():
        m = re.match(r"\s*namespace (\w+) \{", line)
        if m:
            scope.append(m.group(1))
            continue
        if re.match(r"\s*\}\s*//\s*namespace", line):
            scope.pop()
            continue
        m = re.match(r"\s*constexpr int (\w+) =", line)
        if m:
            inner = [s for s in scope if s != "lemke"]
            names.append("::".join(inner + [m.group(1)]))
    return names


def _c_enum():
    text = (ROOT / "include/lemke.h").read_text()
    body = re.search(r"enum lemke_status \{(.*?)\};", text, re.S).group(1)
    body = re.sub(r"/\*.*?\*/", "", body, flags=re.S)
    return {name: int(value) for name, value in re.findall(r"(LEMKE_\w+)\s*=\s*(-?\d+)", body)}


def test_every_header_code_in_the_table():
    table = dict(_core._kernel_codes())
    declared = _header_codes()
    assert declared and len(declared) == len(set(declared))
    assert set(declared) == set(table), "a kernel code of status.hpp missing from KERNEL_CODES"


def test_kernel_codes_negative_and_distinct():
    own = {}
    for name, code in _core._kernel_codes():
        if code == 0:  # a kernel's success: SOLVED's 0
            assert name in ("MLCP_OK", "qp::OK")
            continue
        assert code < 0, name
        own.setdefault(code, set()).add(name.split("::")[-1])
    for code, names in own.items():  # one meaning, one number (NOT_FINITE in three kernels)
        assert len(names) == 1, (code, names)


def test_c_abi_unchanged():
    assert _c_enum() == ABI
    for s in Status:  # the public statuses the C API has are lemke.Status's numbers
        if "LEMKE_" + s.name in ABI:
            assert ABI["LEMKE_" + s.name] == int(s)


def test_every_kernel_code_maps_to_a_documented_c_status():
    documented = set(ABI.values())
    for name, code in _core._kernel_codes():
        assert _core._c_status(code) in documented, name
    # the numbers shared with the C API's bad-input codes map by meaning, not by number
    assert _core._c_status(_core.boxed.BAD_BOUNDS) == ABI["LEMKE_INVALID_ARGUMENT"]
    assert _core._c_status(_core.boxed.SINGULAR) == ABI["LEMKE_NUMERICAL_FAILURE"]
    assert _core._c_status(_core.TRIVIAL) == ABI["LEMKE_SOLVED"]
    assert _core._c_status(_core.NOT_FINITE) == ABI["LEMKE_NOT_FINITE"]
    # a code c_status does not know is not mapped to a documented value (the check can fail)
    assert _core._c_status(-1000) not in documented


def test_lcp_driver_codes_one_mapping():
    """The LCP driver's codes (a Status, NOT_FINITE, TRIVIAL): Python's public_status, the
    core's lcp_status and the C API's c_status agree, on ints and on int64 arrays (the batch)."""
    codes = [int(s) for s in Status if s not in (Status.PRIMAL_INFEASIBLE, Status.DUAL_INFEASIBLE)]
    codes += [_core.NOT_FINITE, _core.TRIVIAL]
    for c in codes:
        assert _layout.public_status(c) == _core._lcp_status(c) == _core._c_status(c)
        assert type(_layout.public_status(c)) is int
    arr = np.array(codes, dtype=np.int64)
    out = _layout.public_status(arr)
    assert out.dtype == np.int64 and out.tolist() == [_core._lcp_status(c) for c in codes]
    assert _layout.public_status(_core.TRIVIAL) == Status.SOLVED
    settled = {c for c in codes if _core._lcp_status(c) in (Status.SOLVED, Status.RAY_TERMINATION)}
    assert _layout.SETTLED == settled
