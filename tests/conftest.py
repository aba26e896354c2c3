import os
import platform
import shutil
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import pytest

import lemke

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SANITIZED_TEST = "test_solves_under_sanitizers"
_sanitized = {}  # "job": the SanitizedJob of this session


_frozen_store: dict = {}  # the references recorded in this session (LEMKE_FREEZE=update)


@pytest.fixture(autouse=True)
def _frozen_reference(request):
    """The running test's frozen reference (tests/frozen.py): what it hands to
    ``frozen.check`` is compared with the recorded digests when it ends."""
    import frozen

    frozen._current = ref = frozen.Reference(Path(request.node.fspath).stem, request.node.name)
    yield ref
    frozen._current = None
    ref.finish(_frozen_store)


def pytest_sessionfinish(session, exitstatus):
    if _frozen_store and exitstatus == 0:
        import frozen

        frozen.write(_frozen_store)


@pytest.fixture(params=lemke.METHODS)
def method(request):
    """Every test that takes ``method`` runs once per Lemke method."""
    return request.param


@pytest.hookimpl(trylast=True)  # after -m and -k have deselected: `-m "not slow"` starts nothing
def pytest_collection_modifyitems(config, items):
    """Start the sanitized build and its child (test_sanitized.py) as soon as its test is
    selected, so that they run beside the rest of the suite instead of before the tests after
    it."""
    if any(item.name == SANITIZED_TEST for item in items):
        start_sanitized_job()


def _tool(name):
    """cmake or ninja: on PATH, beside this Python (a venv's bin, not activated), or from the
    PyPI package of that name (the test extra installs both)."""
    exe = shutil.which(name) or shutil.which(name, path=str(Path(sys.executable).parent))
    if exe is None:
        try:
            mod = __import__(name)
            exe = shutil.which(name, path=str(getattr(mod, "BIN_DIR", None) or getattr(mod, "CMAKE_BIN_DIR", "")))
        except ImportError:
            pass
    return exe


class SanitizedJob:
    """In a thread: configure and build ``lemke._core`` with LEMKE_SANITIZE (AddressSanitizer,
    UBSan, index checks) in a temporary directory, copy python/lemke there with the sanitized
    ``_core`` in it, and run tests/sanitized_run.py on that copy (see test_sanitized.py for
    how the sanitizer runtime is loaded).  ``wait()`` returns a dict: ``stage`` (the step
    that ended it: ``"tools"``, ``"configure"``, ``"build"`` or ``"child"``), ``returncode``,
    ``stdout``, ``stderr``, ``dir``, ``env`` and ``seconds`` per stage."""

    def __init__(self):
        self.dir = Path(tempfile.mkdtemp(prefix="lemke-sanitized-"))
        self.process = None
        self.killed = False
        self.out = {"dir": str(self.dir), "seconds": {}}
        self.thread = threading.Thread(target=self._work, name="lemke-sanitized", daemon=True)
        self.thread.start()

    def _run(self, stage, cmd, **kw):
        import time

        t0 = time.perf_counter()
        if self.killed:
            raise RuntimeError("stopped")
        self.process = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
        stdout, stderr = self.process.communicate()
        self.out.update(stage=stage, returncode=self.process.returncode, stdout=stdout, stderr=stderr)
        self.out["seconds"][stage] = time.perf_counter() - t0
        return self.process.returncode == 0

    def _work(self):
        try:
            self._steps()
        except Exception as e:  # reported by the test
            self.out.setdefault("stage", "tools")
            self.out.update(returncode=-1, stderr=self.out.get("stderr", "") + f"\n{e!r}")

    def _steps(self):
        cmake, ninja = _tool("cmake"), _tool("ninja")
        if cmake is None:
            self.out.update(stage="tools", returncode=-1, stdout="",
                            stderr="cmake is needed to build the sanitized extension (pip install cmake)")
            return
        build = self.dir / "build"
        args = [cmake, "-S", str(ROOT), "-B", str(build), "-DLEMKE_PYTHON=ON", "-DLEMKE_SANITIZE=ON",
                "-DCMAKE_BUILD_TYPE=Debug", f"-DPython_EXECUTABLE={sys.executable}",
                "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON"]
        if ninja:
            args += ["-G", "Ninja", f"-DCMAKE_MAKE_PROGRAM={ninja}"]
        if not self._run("configure", args) or not self._run("build", [cmake, "--build", str(build), "-j", "2"]):
            return
        cores = sorted(build.glob("_core*.so"))
        if len(cores) != 1:
            self.out.update(stage="build", returncode=-1, stderr=f"no single _core*.so in {build}: {cores}")
            return
        # the package, copied (never a write into the repository), with the sanitized _core
        pkg = self.dir / "pkg"
        shutil.copytree(ROOT / "python" / "lemke", pkg / "lemke",
                        ignore=shutil.ignore_patterns("__pycache__", "_core*.so", "_core*.pyd"))
        shutil.copy2(cores[0], pkg / "lemke" / cores[0].name)
        compiler = _cmake_cache(build).get("CMAKE_CXX_COMPILER")
        preload = sanitizer_runtimes(compiler)
        if not preload:
            self.out.update(stage="tools", returncode=-1,
                            stderr=f"no AddressSanitizer runtime found for the compiler {compiler}")
            return
        env = dict(os.environ, LD_PRELOAD=" ".join(preload), PYTHONPATH=str(pkg), PYTHONFAULTHANDLER="1",
                   # no leak check: CPython and numpy keep allocations to the end by
                   # design, and LeakSanitizer would report thousands of them at exit
                   ASAN_OPTIONS="detect_leaks=0:abort_on_error=0",
                   UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1")
        self.out["env"] = {k: env[k] for k in ("LD_PRELOAD", "PYTHONPATH", "ASAN_OPTIONS", "UBSAN_OPTIONS")}
        self.out["summary_path"] = str(self.dir / "summary.json")
        self._run("child", [sys.executable, str(HERE / "sanitized_run.py"), self.out["summary_path"]],
                  env=env, cwd=str(self.dir))

    def wait(self, timeout):
        self.thread.join(timeout)
        if self.thread.is_alive():
            self.stop()
            self.thread.join(30)
            self.out.setdefault("timed_out", True)
        return self.out

    def stop(self):
        self.killed = True
        if self.process is not None and self.process.poll() is None:
            self.process.kill()


def _cmake_cache(build):
    out = {}
    path = Path(build) / "CMakeCache.txt"
    for line in path.read_text().splitlines() if path.exists() else ():
        if ":" in line and "=" in line and not line.startswith(("#", "//")):
            key, value = line.split("=", 1)
            out[key.split(":", 1)[0]] = value
    return out


def sanitizer_runtimes(compiler):
    """The shared runtimes to preload: the compiler's libasan and, when it is a separate
    library (GCC), libubsan (``<compiler> -print-file-name=...``); for clang its own
    AddressSanitizer runtime, which holds UBSan's handlers too (clang's -print-file-name
    also finds GCC's libasan.so, which is not the runtime its code was built for)."""
    clang_rt = f"libclang_rt.asan-{platform.machine()}.so"
    found = []
    for name in (clang_rt, "libasan.so", "libubsan.so"):
        try:
            path = subprocess.run([compiler or "c++", f"-print-file-name={name}"], capture_output=True,
                                  text=True, timeout=30).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            continue
        if os.path.isabs(path) and os.path.exists(path):
            found.append(os.path.realpath(path))
            if name == clang_rt:
                return found
        elif name == "libasan.so":
            return []
    return found


def start_sanitized_job():
    """The sanitized build and child, started once per session."""
    if "job" not in _sanitized:
        _sanitized["job"] = SanitizedJob()
    return _sanitized["job"]


def pytest_unconfigure(config):
    job = _sanitized.pop("job", None)
    if job is not None:
        job.stop()
        job.thread.join(30)
        shutil.rmtree(job.dir, ignore_errors=True)
