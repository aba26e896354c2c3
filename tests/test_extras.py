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


def _closure(roots):
    """The distributions that the requirements ``roots`` pull in, transitively, as installed
    here (each one's own requirements with the extras asked of it, markers evaluated)."""
    from packaging.utils import canonicalize_name

    seen, todo = {}, list(roots)
    while todo:
        req = todo.pop()
        name = canonicalize_name(req.name)
        extras = set(req.extras) | {""}
        if name in seen and extras <= seen[name]:
            continue
        seen[name] = seen.get(name, set()) | extras
        try:
            sub = metadata.requires(req.name) or ()
        except metadata.PackageNotFoundError:
            continue
        for r in map(Requirement, sub):
            if r.marker is None or any(r.marker.evaluate({"extra": e}) for e in extras):
                todo.append(r)
    return set(seen)


def test_numba_is_in_no_requirement_of_the_package():
    """Issue 31: numba is gone from the package, its tests and its install.  Neither the
    runtime requirements nor the test and examples extras name it, and nothing they pull in
    requires it (as installed here).  Only the bench extra brings it, as quantecon's own
    dependency: quantecon is a peer the benchmarks measure (the README says so)."""
    reqs = [Requirement(r) for r in metadata.requires("lemke") or ()]
    runtime = [r for r in reqs if r.marker is None]
    assert {r.name for r in runtime} == {"numpy", "scipy"}
    for extra in ("", "test", "examples", "dask", "progress"):
        roots = runtime + list(_extra(extra).values()) if extra else runtime
        assert "numba" not in _closure(roots), extra
    assert "numba" not in {r.name.lower() for r in reqs}  # the bench extra too, by name
