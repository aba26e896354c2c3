"""benchmarks/bench_vs_numba.py's report: the table it writes from the processes' numbers (no
timing here; the measurements themselves run only in the benchmark)."""
import sys
from pathlib import Path
from types import SimpleNamespace

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import bench_vs_numba as bvn  # noqa: E402


def _process(cold3, warm3, box12, cpu3=None):
    return dict(lemke="0", path="p", commit="c", numba=None, load=[1.0, 2.0], seconds=1.0, rows={
        "cold n=3": dict(t=cold3, peer=4e-6, pivots=3, cpu=cpu3 or cold3),
        "warm n=3": dict(t=warm3, ratio=warm3 / cold3, pivots=0),
        "box relay n=12": dict(t=box12, ratio=1.5, pivots=9),
    })


def test_report_pairs_the_processes_and_names_the_rows_today_is_slower_on():
    old = [_process(2e-6, 2e-6, 4e-6, cpu3=1.6e-6), _process(2.2e-6, 2e-6, 4e-6)]
    new = [_process(3e-6, 1e-6, 2e-6), _process(2.0e-6, 1e-6, 2e-6)]  # cold: 1.5 and 0.91 per pair
    first = {"solve_lcp": {"old": 3.0, "new": 0.3, "old call": 1.0, "new call": 1e-5, "old empty": 30.0}}
    data = dict(date="d", cpu="c", usable=2, load=[1.0, 1.0], seconds=1.0, old=old, new=new, first=first)
    args = SimpleNamespace(compare=["OLD", "NEW"], pairs=2, budget=0.1, runs=3)
    text = bvn.report(data, args)
    rows = {line.split(" | ")[0][2:]: line.split(" | ") for line in text.splitlines() if line.startswith("| ")}
    assert rows["cold n=3"][4] == "1.20 (0.909-1.5)"  # today/old: the median of the pairs' ratios
    assert rows["cold n=3"][2] == "2.10 (2.00-2.20)"  # old: median (range) in microseconds
    assert rows["cold n=3"][5] == "1.00"  # today's fastest process over the old package's
    assert rows["cold n=3"][6] == "1.25"  # the least CPU times: 2.0 over 1.6
    assert rows["warm n=3"][6] == ""  # (no CPU time)
    assert rows["cold n=3"][9] == "4.00"  # the peer over all four processes
    assert rows["cold n=3"][8] == "0.62 (0.5-0.75)"  # today over the peer, per process
    assert rows["warm n=3"][4] == "0.50 (0.5)"
    assert "(median per-pair ratio above 1): cold n=3." in text
    assert rows["solve_lcp"][1:5] == ["3.000", "30.00", "0.300", "0.10"]


def test_every_row_has_a_target():
    keys = [f"cold n={n}" for n in bvn.COLD_SIZES] + [f"warm n={n}" for n in bvn.WARM_SIZES]
    keys += ["unrevised n=100", "fixed n=1 q>=0", "batch of one", "islands packed", "qp cached n=10",
             "games n=20", "box contact n=200", "mpc cold", "mpc warm"]
    for key in keys:
        assert sum(key.startswith(prefix) for prefix, _, _ in bvn.TARGETS) == 1, key


def test_summary_gives_each_runs_ratios():
    old = [_process(2e-6, 2e-6, 4e-6, cpu3=1e-6)]
    new = [_process(1e-6, 1e-6, 2e-6, cpu3=0.5e-6)]
    runs = [dict(old=old, new=new), dict(old=old, new=[_process(3e-6, 1e-6, 2e-6, cpu3=2e-6)])]
    rows = {line.split(" | ")[0][2:]: line.split(" | ") for line in bvn.summary(runs).splitlines()[2:]}
    assert rows["cold n=3"][1:5] == ["0.50 / 1.50", "0.50-1.50", "0.50 / 1.50", "0.50 / 2.00"]
