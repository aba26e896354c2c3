"""The ``test`` extra installs what the tests would otherwise skip without (they import these
packages with ``pytest.importorskip``), so a run of the README's test command runs every test
it claims to; and it includes the ``examples`` extra, since tests/test_examples.py runs them.
A missing package fails here, naming what to install, instead of skipping elsewhere."""
import importlib
from importlib import metadata

from packaging.requirements import Requirement

# The modules the tests import optionally, and the extra's distributions that provide them.
OPTIONAL = {"quadprog": "quadprog", "qpsolvers": "qpsolvers", "matplotlib": "matplotlib",
            "distributed": "dask"}


def _extra(name):
    reqs = [Requirement(r) for r in metadata.requires("lemke") or ()]
    return {r.name.lower(): r for r in reqs if r.marker is not None and r.marker.evaluate({"extra": name})}


def test_test_extra_lists_every_optional_package_and_the_examples_extra():
    test = _extra("test")
    assert set(OPTIONAL.values()) <= set(test), sorted(set(OPTIONAL.values()) - set(test))
    examples = _extra("examples")
    assert examples and set(examples) <= set(test), sorted(set(examples) - set(test))


def test_test_extra_is_installed():
    for module, dist in OPTIONAL.items():
        try:
            importlib.import_module(module)
        except ImportError as exc:  # pragma: no cover - the message is the point
            raise AssertionError(f"{module} ({dist}) is missing: pip install '.[test]'") from exc
    import qpsolvers

    assert "quadprog" in qpsolvers.available_solvers
    for name, req in _extra("test").items():
        assert req.specifier.contains(metadata.version(name), prereleases=True), (name, req)
