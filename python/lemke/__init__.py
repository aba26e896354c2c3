"""lemke: linear complementarity problems by Lemke's complementary pivoting method.

Public API: :func:`solve_lcp` (methods in ``METHODS``), :func:`solve_lcp_batch` (many LCPs
of one size in parallel threads), :func:`solve_lcp_many` (many of different sizes), :func:`solve_lcp_batch_dask` (a batch over a
Dask cluster),
:func:`solve_mlcp` (mixed LCPs), :func:`solve_blcp` / :func:`solve_blcp_many` (box LCPs, one or many islands, with
:class:`BoxWarmStart` / :class:`BoxWarmStartBatch`), :func:`solve_qp` (convex QPs, with :class:`Certificate` when there is no optimum), their results :class:`LCPResult`,
:class:`LCPBatchResult`, :class:`LCPManyResult` (with :class:`WarmStartBatch`), :class:`MLCPResult`, :class:`QPResult`, :class:`Status`,
:class:`Options`, :class:`WarmStart`, :class:`PathsResult` (what :func:`lemke_paths` returns),
:class:`DensifyWarning` (a large scipy.sparse input made dense), :func:`pivot_column` (one step of the unrevised
method), the checks :func:`is_lcp_solution` and :func:`is_lcp_ray`; problems as values
(:class:`Problem`) and in files (:func:`read_problem`, :func:`write_problem`,
:func:`write_result`, :class:`ProblemFormatError`).
"""
import importlib as _importlib

from ._version import __version__

#: Where each public name lives.  The solvers' modules (numpy and the core with them) are
#: imported with the package, so that no solver's first call waits for an import (about
#: 20 ms of the package's own, numpy's apart); the rest (``_io``: problem files, 20 ms more) when a name of
#: theirs is first used (PEP 562).
_EXPORTS = {
    "solve_lcp_batch": "_batch", "solve_lcp_many": "_batch",
    "solve_lcp_batch_dask": "_dask",
    "BLCPResult": "_blcp", "BoxWarmStart": "_blcp", "solve_blcp": "_blcp",
    "BLCPManyResult": "_blcp_many", "BoxWarmStartBatch": "_blcp_many",
    "solve_blcp_many": "_blcp_many",
    "ProblemFormatError": "_io", "read_problem": "_io", "result_to_dict": "_io",
    "write_problem": "_io", "write_result": "_io",
    "BimatrixResult": "_games", "GameBasis": "_games", "PathsResult": "_games",
    "lemke_paths": "_games", "solve_bimatrix": "_games",
    "is_lcp_ray": "_certify", "is_lcp_solution": "_certify", "lcp_residual": "_certify",
    "METHODS": "_lcp", "solve_lcp": "_lcp",
    "MLCPResult": "_mlcp", "solve_mlcp": "_mlcp",
    "Options": "_options",
    "pivot_column": "_pivot_column",
    "Problem": "_problem",
    "Certificate": "_qp", "QPResult": "_qp", "solve_qp": "_qp", "solve_qpsolvers_problem": "_qp",
    "LCPBatchResult": "_result", "LCPManyResult": "_result", "LCPResult": "_result",
    "WarmStart": "_result", "WarmStartBatch": "_result",
    "Status": "_status",
    "DensifyWarning": "_validate",
}

__all__ = sorted(_EXPORTS) + ["__version__"]
_LAZY = ("_io",)

for _where in [w for w in dict.fromkeys(_EXPORTS.values()) if w not in _LAZY]:
    _module = _importlib.import_module("." + _where, __name__)
    globals().update((name, getattr(_module, name)) for name, w in _EXPORTS.items() if w == _where)
del _where, _module


def _warm_up():
    """Solve one tiny problem on each engine and path (LCP, box LCP, the QP's box, fused
    and KKT-MLCP paths, MLCP, bimatrix game), so that a solver's first call in a process
    finds the core's code and its caches as its second does (about 1 ms at import, against
    a first call 3-10 times the second's, tens of microseconds, without it)."""
    import numpy as np

    M, q, one = np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-1.0, 1.0]), np.ones(2)
    row = np.ones((1, 2))
    solve_lcp(M, q)
    solve_blcp(M, q, -one, one)
    solve_qp(M, q, lb=-one, ub=one)
    solve_qp(M, q, G=row, h=one[:1])
    solve_qp(M, q, A=row, b=one[:1])
    # the KKT-MLCP path, P semidefinite with a coupled block (its Cholesky check's LAPACK call)
    flat = np.zeros((3, 3))
    flat[:2, :2] = 1.0
    solve_qp(flat, np.array([-1.0, 1.0, 1.0]), G=np.ones((1, 3)), h=one[:1], lb=-np.ones(3))
    solve_mlcp(M[:1, :1], M[:1, 1:], M[1:, :1], M[1:, 1:], q[:1], q[1:])
    solve_bimatrix(M + 1.0, M.T + 2.0)


_warm_up()


def __getattr__(name):
    where = _EXPORTS.get(name)
    if where is None:
        raise AttributeError(f"module 'lemke' has no attribute {name!r}")
    value = getattr(_importlib.import_module("." + where, __name__), name)
    globals()[name] = value  # the next read is a plain attribute
    return value


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
