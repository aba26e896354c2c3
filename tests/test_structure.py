"""The package's structure, as ARCHITECTURE.md states it: imports only go down the layers
(no cycle, no import back up, not even inside a function), the kind strings live in the
registry and the file formats' declarations only, the core's buffer layout is the one
_layout.py states, and results behave like values; and the package imports nothing beyond
the standard library, numpy, scipy and its optional extras."""
import ast
import pickle
from pathlib import Path

import numpy as np
import pytest

import lemke
from lemke._kinds import KINDS

PACKAGE = Path(lemke.__file__).parent

#: Layer of each module (dotted, relative to lemke); a module may import only lower layers
#: (or, inside the _io and _reductions packages, its siblings, acyclically).
LAYERS = [
    {"_layout", "_core"},  # (the compiled core imports nothing of the package)
    {"_status", "_options", "_validate", "_version", "_progress"},
    {"_result"},
    {"_certify"},
    {"_reductions", "_games_exact"},
    {"_lcp", "_pivot_column", "_games", "_blcp"},
    {"_batch", "_mlcp"},
    {"_blcp_many"},
    {"_qp", "_dask"},
    {"_kinds"},
    {"_problem"},
    {"problems", "_io"},
    {"_cli"},
    {"__init__", "__main__"},
]


def _layer(module: str) -> int:
    top = module.split(".")[0]
    for k, names in enumerate(LAYERS):
        if top in names:
            return k
    raise AssertionError(f"module {module} is in no layer of tests/test_structure.py")


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).with_suffix("")
        parts = rel.parts[:-1] if rel.name == "__init__" and len(rel.parts) > 1 else rel.parts
        yield ".".join(parts), path


def _imports(module: str, path: Path):
    """The lemke modules that ``module`` imports, anywhere in the file."""
    package = module.split(".")[:-1] if path.name != "__init__.py" else module.split(".")
    if module == "__init__":
        package = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level == 0:
                if node.module and node.module.split(".")[0] == "lemke":
                    yield node.module.split(".", 1)[1] if "." in node.module else "__init__"
                continue
            base = package[: len(package) - (node.level - 1)]
            target = ".".join(base + ([node.module] if node.module else []))
            if node.module:
                yield target
            else:
                for alias in node.names:
                    yield ".".join(base + [alias.name])
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "lemke":
                    yield alias.name.split(".", 1)[1] if "." in alias.name else "__init__"


def test_imports_go_down_the_layers():
    graph = {}
    for module, path in _modules():
        graph[module] = set()
        for target in _imports(module, path):
            if target in ("", "__init__") and module != "__init__":
                raise AssertionError(f"{module} imports lemke itself (back up the layers)")
            lo, hi = _layer(target), _layer(module)
            same_package = target.split(".")[0] == module.split(".")[0]
            assert lo < hi or (lo == hi and same_package), f"{module} imports {target}: up the layers"
            graph[module].add(target)
    # no cycle among siblings (kernels, _io, _reductions)
    state = {}

    def visit(m, stack):
        state[m] = 1
        for t in graph.get(m, ()):
            t = t if t in graph else t.rsplit(".", 1)[0]
            assert state.get(t) != 1, f"import cycle: {' -> '.join(stack + [t])}"
            if t in graph and t not in state:
                visit(t, stack + [t])
        state[m] = 2

    for m in graph:
        if m not in state:
            visit(m, [m])


def test_kind_strings_only_in_the_registry_and_the_formats_declarations():
    names = set(KINDS)
    for module, path in _modules():
        if module == "_kinds":
            continue
        tree = ast.parse(path.read_text())
        docstrings = {id(n.value) for n in ast.walk(tree)
                      if isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant)}
        declared = set()
        # A format's KINDS = ... declaration; and __all__ and the built-in problems' names
        # (problems.NAMED), where a name may be a kind's by coincidence ("bimatrix").
        for n in ast.walk(tree):
            if isinstance(n, ast.Assign) and any(isinstance(t, ast.Name) and t.id in ("KINDS", "__all__", "NAMED")
                                                 for t in n.targets):
                declared |= {id(c) for c in ast.walk(n.value)}
            if isinstance(n, ast.keyword) and n.arg == "name":  # a problem's name
                declared.add(id(n.value))
        for n in ast.walk(tree):
            if (isinstance(n, ast.Constant) and n.value in names and id(n) not in docstrings
                    and id(n) not in declared):
                raise AssertionError(f"{module}:{n.lineno} spells the kind {n.value!r}")


@pytest.mark.parametrize("n", [0, 1, 5, 100])
def test_the_layout_is_the_cores(n):
    """lemke/_layout.py states the C++ core's buffer layout and codes for the fronts."""
    from lemke import _core, _layout
    f = _layout.fields(n)
    starts = tuple(f[name] if name == "z0" else f[name].start for name, _ in _layout.BUFFER)
    assert _core.buffer_layout(n) == starts + (_layout.buffer_length(n),)
    assert (_layout.NOT_FINITE, _layout.TRIVIAL, _layout.RESTART_FROM) == (
        _core.NOT_FINITE, _core.TRIVIAL, _core.RESTART_FROM)
    assert _layout.METHODS == {"tableau": _core.TABLEAU, "unrevised": _core.UNREVISED}
    from lemke._kinds import KINDS
    assert KINDS["lcp"].methods == tuple(_layout.METHODS) == lemke.METHODS


def test_results_are_values():
    M, q = [[2.0, 1.0], [1.0, 2.0]], [-5.0, -6.0]
    a, b = lemke.solve_lcp(M, q), lemke.solve_lcp(M, q)
    assert a == b and hash(a) == hash(b) and len({a, b}) == 1
    assert a == pickle.loads(pickle.dumps(a))
    c = lemke.solve_lcp(M, [-5.0, -6.5])
    assert a != c
    assert a != "not a result"
    qp = lemke.solve_qp([[1.0]], [1.0], G=[[1.0]], h=[2.0], lb=[5.0])  # infeasible: x <= 2, x >= 5
    assert qp.certificate is not None and qp == pickle.loads(pickle.dumps(qp))
    hash(qp)
    batch = lemke.solve_lcp_batch(M, [q, q], workers=1)
    assert batch == lemke.solve_lcp_batch(M, [q, q], workers=1)
    mlcp = lemke.solve_mlcp([[1.0]], [[2.0]], [[-1.0]], [[1.0]], [-1.0], [-3.0])
    assert mlcp == lemke.solve_mlcp([[1.0]], [[2.0]], [[-1.0]], [[1.0]], [-1.0], [-3.0])


def test_status_prints_its_name():
    assert str(lemke.Status.SOLVED) == "SOLVED"
    assert f"{lemke.Status.RAY_TERMINATION}" == "RAY_TERMINATION"
    assert lemke.Status.SOLVED == 0 and int(lemke.Status.CYCLING) == 6
    r = lemke.solve_lcp([[1.0]], [-1.0])
    assert len(repr(r)) < 120


def test_the_package_imports_only_numpy_scipy_and_its_extras():
    """The package's dependencies are numpy and scipy, and its optional extras (tqdm for
    progress bars, dask's distributed, qpsolvers' interface): no module of the package
    imports anything else outside the standard library."""
    import sys

    allowed = {"numpy", "scipy", "tqdm", "distributed", "qpsolvers", "lemke"}
    bad = {}
    for p in PACKAGE.rglob("*.py"):
        for n in ast.walk(ast.parse(p.read_text())):
            names = ([n.module] if isinstance(n, ast.ImportFrom) and n.level == 0 else
                     [a.name for a in n.names] if isinstance(n, ast.Import) else [])
            for name in names:
                top = name.split(".")[0]
                if top not in allowed and top not in sys.stdlib_module_names:
                    bad.setdefault(str(p.relative_to(PACKAGE)), set()).add(top)
    assert not bad, bad
