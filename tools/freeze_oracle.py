"""Record the frozen references (tests/frozen.py) from the numba oracle, tests/oracle/.

Runs only where tests/oracle/ and numba exist (the commit that added this script; the next
commit deleted both): ``python tools/freeze_oracle.py`` from the repository's root runs the
tests that compared the C++ core with the oracle, with LEMKE_FREEZE=record: every call they
check runs on both, the same bits are asserted, and the core's digests are written to
tests/data/frozen/<module>.json (only when every test passed).
"""
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MODULES = ["test_core_lcp", "test_core_unrevised", "test_core_boxed", "test_core_support",
           "test_core_games", "test_core_qp", "test_qp_kkt_check"]

if __name__ == "__main__":
    assert (ROOT / "tests" / "oracle").is_dir(), "the oracle (tests/oracle/) is gone: nothing to record from"
    files = [f"tests/{m}.py" for m in MODULES] + sys.argv[1:]
    env = dict(os.environ, LEMKE_FREEZE="record")
    sys.exit(subprocess.call([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *files],
                             cwd=ROOT, env=env))
