"""The Python package's solves over the problem tables, run against a build of ``lemke._core``
with AddressSanitizer, UndefinedBehaviorSanitizer and the core's index checks
(``LEMKE_SANITIZE``: ``LEMKE_CHECKED``, ``-fsanitize=address,undefined``,
``-fno-sanitize-recover=all``; a Debug build).

conftest.py starts the work in a thread as soon as this test is selected, so that it runs
beside the rest of the suite: CMake configures and builds the extension into a temporary
directory (``-DLEMKE_PYTHON=ON -DLEMKE_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug``, this Python as
``Python_EXECUTABLE``, nanobind's CMake files from ``python -m nanobind --cmake_dir``; about
30 s on two cores), copies python/lemke there with the sanitized ``_core*.so`` in it (nothing
is written into the repository), and runs tests/sanitized_run.py in a child Python whose
PYTHONPATH finds that copy first (a few seconds).  The test is marked ``slow``: ``pytest -m
"not slow"`` leaves it out, and then nothing is built or started.

**Loading the sanitizer into Python.**  The extension is linked against GCC's shared
``libasan`` and ``libubsan``; AddressSanitizer must be the first library in the process (it
replaces malloc and free, and checks at start-up that it comes first: otherwise "ASan
runtime does not come first in initial library list").  The Python executable is not built
with it, so the child gets ``LD_PRELOAD`` of the compiler's runtimes (``<compiler>
-print-file-name=libasan.so`` and ``libubsan.so``, the compiler read from the build's
CMakeCache.txt).  That works here (GCC 12, Linux x86-64) with no other setting: no
``verify_asan_link_order=0`` and no ``-static-libasan``.  The child checks that it is in
force (``sanitized_run.sanitizer_probe``: ASan's allocator serves malloc, a freed block is
poisoned; UBSan's handlers are loaded), and the test checks the build's compile commands.

``ASAN_OPTIONS=detect_leaks=0``: CPython and numpy keep many allocations to the end by
design, and LeakSanitizer would report them at exit (the C API's own tests, tests/test_capi.py,
run with the leak check on).  ``UBSAN_OPTIONS=halt_on_error=1``: a UBSan finding stops the
child (the build also has ``-fno-sanitize-recover=all``).

The child's solves (see sanitized_run.py) cover the goldens' problems, the stress families
and a contact scene, every size from 1 to 9 and some larger, box LCPs with and without a
friction index, games, warm starts and relabels, and sanitized_fuzz.py's adversarial inputs
(malformed lists and arrays, the private batch helpers with inconsistent offsets, the kept
matrices' large slot, box islands of varying sizes, blcp_pack's islands in every form).  The test asserts exit code 0, no
sanitizer report on stderr, no exception, and that the answers are the normal build's bit
for bit: the goldens' against this process's ``golden.solve_all()`` (and against
tests/data/golden.json's record when it is of this platform), every other solve by its
fingerprint (status, pivots and the bits of its arrays) against the same solves run here.
"""
import json
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
import golden  # noqa: E402
import sanitized_run  # noqa: E402


def _report(out, n=4000):
    """What a stage printed: the end of stdout, and stderr from its first sanitizer report
    (the start of a report names the access and the frames in lemke's sources) or its end."""
    stderr = out.get("stderr") or ""
    first = min((i for i in (stderr.find("ERROR: AddressSanitizer"), stderr.find("runtime error:")) if i >= 0),
                default=-1)
    shown = stderr[max(0, first - 300):first + 3 * n] if first >= 0 else stderr[-n:]
    return (f"stage {out.get('stage')}, exit code {out.get('returncode')}"
            f"{' (timed out)' if out.get('timed_out') else ''}\nstdout:\n{(out.get('stdout') or '')[-n:]}"
            f"\nstderr:\n{shown}")


@pytest.mark.slow
def test_solves_under_sanitizers():
    from conftest import start_sanitized_job

    job = start_sanitized_job()  # started at collection time by conftest.py
    out = job.wait(timeout=900)
    assert out.get("stage") == "child", "the sanitized build failed:\n" + _report(out)
    stderr = out["stderr"]
    assert "ERROR: AddressSanitizer" not in stderr and "runtime error:" not in stderr, _report(out)
    assert "ERROR: LeakSanitizer" not in stderr
    summary_path = Path(out["summary_path"])
    assert out["returncode"] == 0 or summary_path.exists(), "the child died:\n" + _report(out, 12000)
    summary = json.loads(summary_path.read_text())
    errors = summary["errors"]
    assert out["returncode"] == 0 and not errors and summary["golden_error"] is None, (
        f"{len(errors)} exception(s) in {summary['solves']} solves (exit code {out['returncode']}):\n"
        + "\n".join(f"{e['case']}: {e['error']}" for e in errors)
        + ("\n\nfirst traceback:\n" + errors[0]["traceback"] if errors else "")
        + ("\n\ngolden.solve_all():\n" + summary["golden_error"] if summary["golden_error"] else ""))

    # The child ran the copy with the sanitized core, under the sanitizers' runtimes.
    pkg = Path(out["env"]["PYTHONPATH"]).resolve()
    assert Path(summary["core"]).resolve().parent == pkg / "lemke", summary["core"]
    assert Path(summary["lemke"]).resolve().parent == pkg / "lemke", summary["lemke"]
    probe = summary["probe"]
    assert probe["asan"] and probe["ubsan"], probe
    assert probe["freed_block_poisoned"] and not probe["live_block_poisoned"], probe
    commands = json.loads((Path(out["dir"]) / "build" / "compile_commands.json").read_text())
    for entry in commands:
        if "/nanobind/" in entry["file"]:
            continue
        cmd = entry.get("command") or " ".join(entry.get("arguments", ()))
        assert "-fsanitize=address,undefined" in cmd and "-DLEMKE_CHECKED" in cmd, (entry["file"], cmd)
    assert any(e["file"].endswith("python.cpp") for e in commands)

    # The answers are the normal build's, bit for bit (the core gives the same bits in every
    # build: no fast-math, no contraction; see CMakeLists.txt).
    assert summary["golden_solves"] > 200 and summary["solves"] > 2000, summary["solves"]
    normal = golden.solve_all()
    assert sorted(summary["golden"]) == sorted(normal)
    differ = [k for k in normal if summary["golden"][k] != normal[k]]
    assert not differ, f"{len(differ)} goldens' answers differ from the normal build's: {differ[:20]}"
    own = [r for r in golden.records() if r["versions"] == summary["golden_versions"]]
    if own:  # a record of this platform: the sanitized build answers as recorded, bit for bit
        assert summary["golden"] == own[0]["results"]
    run = sanitized_run.run_all()
    assert not run.errors, [e["case"] for e in run.errors]
    theirs = summary["fingerprints"]
    assert sorted(theirs) == sorted(run.fingerprints)
    differ = [k for k, v in run.fingerprints.items() if theirs[k] != v]
    assert not differ, f"{len(differ)} of {len(theirs)} answers differ from the normal build's: {differ[:20]}"
