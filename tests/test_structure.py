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
    {"_layout", "_core", "_frozen", "_npc"},  # (the compiled core imports nothing of the package)
    {"_status", "_options", "_validate", "_version", "_progress", "_ladder"},
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


@pytest.mark.parametrize("n, p, m", [(1, 0, 0), (5, 2, 3), (10, 0, 7), (4, 3, 0)])
def test_the_qp_layouts_are_the_cores(n, p, m):
    """The QP kernels' buffers as the core states them (qp.hpp OutLayout, BoxOutLayout,
    exported as _core.qp_layout / qp_box_layout, from which _qp sizes and reads its
    buffers) are the ones the former kernels used (x, y, z, z_box, 4 residuals laid end to
    end, then the basis: m + 2n; the box path's after boxed's 6n + 1), and a solve's
    fields read through them are the kernel's writes: x, y, z, z_box and the residuals of
    an independent KKT check."""
    from lemke import _core, _qp
    x, y, z, zb, stats, basis, length = _core.qp_layout(n, p, m)
    assert (x, y, z, zb, stats, basis) == (0, n, n + p, n + p + m, 2 * n + p + m, 2 * n + p + m + 4)
    assert length == basis + m + 2 * n
    assert _qp._layout(n, p, m) == (x, y, z, zb, stats, basis, length)
    bx, bzb, bstats, bfinal, blength = _core.qp_box_layout(n)
    assert (bx, bzb, bstats, bfinal) == (0, 6 * n + 1, 7 * n + 1, 7 * n + 5)
    assert blength == bfinal + 3 * n and _qp._box_layout(n) == (bx, bzb, bstats, bfinal, blength)
    rng = np.random.default_rng(n + 10 * p + 100 * m)
    B = rng.standard_normal((n, n))
    P, q = B @ B.T + np.eye(n), rng.standard_normal(n)
    G, A = rng.standard_normal((m, n)), rng.standard_normal((p, n))
    x0 = rng.standard_normal(n)
    h, b = G @ x0 + 0.1, A @ x0
    lb, ub = x0 - 1.0, x0 + 1.0
    out = np.empty(length)
    code, _, k, _ = _core.qp_solve(P, q, G, h, A, b, lb, ub, 0, -1, 1e-9, 1e-12, 1e-9, out)
    assert code == _core.QP_OK
    stats4 = np.empty(4)
    assert _core.qp_kkt_check(P, q, G, h, A, b, lb, ub, out[x:y], out[y:z], out[z:zb],
                              out[zb:stats], 1e-9, stats4)
    assert stats4.tolist() == out[stats:basis].tolist()
    basic = out[basis:basis + k].view(np.int64)
    assert k == 0 or (basic.min() >= 0 and np.all(np.diff(basic) > 0))


@pytest.mark.parametrize("n, nf, friction", [(0, 0, False), (1, 0, False), (5, 0, False),
                                             (0, 0, True), (3, 0, True), (4, 1, True),
                                             (6, 3, True), (9, 6, True)])
def test_the_box_layout_is_stated_once(n, nf, friction):
    """The box engine's buffers are laid out in one place (src/lemke/boxed.hpp FrontLayout,
    exported as _core.boxed.layout): its fields tile each buffer in the stated order, and
    the Python fronts' slices are its own (_blcp._spans, _Run; _blcp_many's blocks)."""
    import numpy as np
    from lemke import _blcp
    from lemke._core import boxed
    L = boxed.layout(n, nf, friction)
    N = n + 2 * nf
    assert L["N"] == N
    fr = friction and n > 0

    def tiles(names, lengths, total):
        at = 0
        for name, k in zip(names, lengths):
            assert L[name] == (at, at + k), name
            at += k
        assert at == total

    run = ("z", "w", "covering", "row_scale", "col_scale", "ray")
    caller = tuple("caller_" + f for f in ("z", "w", "lo", "hi", "row_scale", "col_scale"))
    tiles(run, (N,) * 5 + (N + 1,), L["run_length"])
    if fr:
        tiles(run + caller, (N,) * 5 + (N + 1,) + (n,) * 6, L["length"])
        assert L["answer"] == L["caller_z"][0]
    else:
        assert L["length"] == L["run_length"] and not any(c in L for c in caller)
        assert L["answer"] == L["z"][0]
    # _blcp_many gathers z, w (and lo, hi with friction) as n-blocks after the answer's z
    for shift, name in enumerate(("z", "w", "lo", "hi") if fr else ("z", "w")):
        assert L[("caller_" if fr else "") + name][0] == L["answer"] + shift * n
    tiles(("final", "friction_rows", "normal_rows"), (N, nf, nf), L["ints_length"])
    if nf:
        tiles(("work_M", "work_q", "work_lo", "work_hi"), (N * N, N, N, N), L["work_length"])
    else:
        assert L["work_length"] == 0
    spans = _blcp._spans(n, N, fr)
    for name, span in spans.items():
        want = L["covering"] if name == "covering" else L[("caller_" if fr else "") + name]
        assert span == want, name
    if not friction:
        run_ = _blcp._Run(n)
        assert run_.buf.size == L["length"]
        for attr, name in (("z", "z"), ("w", "w"), ("d", "covering"), ("R", "row_scale"),
                           ("C", "col_scale"), ("ray", "ray")):
            a = getattr(run_, attr)
            assert (a.__array_interface__["data"][0] - run_.buf.__array_interface__["data"][0]) // 8 == L[name][0]
            assert a.size == L[name][1] - L[name][0]
    # the islands' offsets, laid end to end
    findex = np.array(([0] * nf + [-1] * (n - nf)) * 2, dtype=np.int64)  # nf friction rows
    state = np.where(findex >= 0, 3, 0).astype(np.int8)
    buff, ioff, answer, limits = (np.empty(k, dtype=np.int64) for k in (3, 3, 2, 2))
    flag = np.array([friction, friction], dtype=np.uint8)
    assert boxed.islands(np.array([0, n, 2 * n], dtype=np.int64), findex, flag, state,
                         flag, -1, buff, ioff, answer, limits) == -1
    assert buff.tolist() == [0, L["length"], 2 * L["length"]]
    assert ioff.tolist() == [0, L["ints_length"], 2 * L["ints_length"]]
    assert answer.tolist() == [L["answer"]] * 2
    assert limits.tolist() == [100 * (N + 1)] * 2


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


def test_acceptance_is_one_module():
    """Every kind's check is reachable from ``_certify`` by name, and no other module of the
    package calls the core's checks directly (the fronts call them through ``_certify``)."""
    from lemke import _certify

    for name in ("check_lcp", "is_lcp_solution", "is_lcp_ray", "check_mlcp", "is_mlcp_ray",
                 "box_check", "check_scales", "is_box_ray", "kkt_check", "games_check",
                 "check_farkas", "check_direction"):
        assert callable(getattr(_certify, name)), name
    kernels = {"box_check", "check_scales", "is_ray", "games_check", "qp_kkt_check",
               "lcp_check", "lcp_ray_check", "check_mlcp"}
    bad = []
    for p in PACKAGE.rglob("*.py"):
        if p.name == "_certify.py":
            continue
        for n in ast.walk(ast.parse(p.read_text())):
            if (isinstance(n, ast.Attribute) and n.attr in kernels
                    and isinstance(n.value, ast.Name) and n.value.id in ("boxed", "_core")):
                bad.append(f"{p.relative_to(PACKAGE)}:{n.lineno} {n.value.id}.{n.attr}")
            if isinstance(n, ast.ImportFrom) and (n.module or "").endswith("_core"):
                bad += [f"{p.relative_to(PACKAGE)}:{n.lineno} {a.name}" for a in n.names
                        if a.name in kernels]
    assert not bad, bad
