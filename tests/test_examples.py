"""Every script in examples/ runs as a user runs it, ``python examples/<name>.py`` with its
default arguments, or with its quick mode where the default is a long run (``ARGS``; the
``examples`` extra installed; the ``test`` extra includes it), with
matplotlib's non-interactive Agg backend, in an empty folder: it writes its output there, and
the committed pictures beside the scripts are never written over."""
import hashlib
import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SCRIPTS = sorted(EXAMPLES.glob("*.py"))
# What each example writes into its working folder when run without arguments.
WRITES = {"box_pile.py": ["box_pile.png"], "contact_3d.py": ["contact_3d.png"]}
# The arguments each example gets (contact_3d's default is 1000 steps, about 30 s).
ARGS = {"contact_3d.py": ["--quick"]}
PNG = b"\x89PNG\r\n\x1a\n"


def _files(folder):
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in folder.iterdir() if p.is_file()}


def test_every_example_is_run():
    assert [p.name for p in SCRIPTS] == sorted(WRITES)


@pytest.mark.slow
@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_example_runs_and_writes_into_its_working_folder(script, tmp_path):
    committed = _files(EXAMPLES)
    env = dict(os.environ, MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, str(script), *ARGS.get(script.name, [])], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-4000:]
    assert sorted(p.name for p in tmp_path.iterdir()) == WRITES[script.name]
    for name in WRITES[script.name]:
        data = (tmp_path / name).read_bytes()
        if name.endswith(".png"):
            assert data[:8] == PNG and len(data) > 10_000, name
        assert f"wrote {name}" in done.stdout
    assert _files(EXAMPLES) == committed
