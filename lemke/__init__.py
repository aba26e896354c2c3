"""lemke: linear complementarity problems by Lemke's complementary pivoting method.

Public API: :func:`solve_lcp` (methods in ``METHODS``), :func:`solve_lcp_batch` (many LCPs
of one size in parallel threads), :func:`solve_lcp_many` (many of different sizes), :func:`solve_lcp_batch_dask` (a batch over a
Dask cluster),
:func:`solve_mlcp` (mixed LCPs), :func:`solve_qp` (convex QPs, with :class:`Certificate` when there is no optimum), their results :class:`LCPResult`,
:class:`LCPBatchResult`, :class:`LCPManyResult` (with :class:`WarmStartBatch`), :class:`MLCPResult`, :class:`QPResult`, :class:`Status`,
:class:`Options`, :class:`WarmStart`, :class:`PathsResult` (what :func:`lemke_paths` returns),
:class:`DensifyWarning` (a large scipy.sparse input made dense), :func:`pivot_column` (one step of the unrevised
method), the checks :func:`is_lcp_solution` and :func:`is_lcp_ray`; problems as values
(:class:`Problem`) and in files (:func:`read_problem`, :func:`write_problem`,
:func:`write_result`, :class:`ProblemFormatError`).
"""
from ._batch import solve_lcp_batch, solve_lcp_many
from ._dask import solve_lcp_batch_dask
from ._blcp import BLCPResult, BoxWarmStart, solve_blcp
from ._io import ProblemFormatError, read_problem, result_to_dict, write_problem, write_result
from ._games import BimatrixResult, GameBasis, PathsResult, lemke_paths, solve_bimatrix
from ._certify import is_lcp_ray, is_lcp_solution, lcp_residual
from ._lcp import METHODS, solve_lcp
from ._mlcp import MLCPResult, solve_mlcp
from ._options import Options
from ._pivot_column import pivot_column
from ._problem import Problem
from ._qp import Certificate, QPResult, solve_qp, solve_qpsolvers_problem
from ._result import LCPBatchResult, LCPManyResult, LCPResult, WarmStart, WarmStartBatch
from ._status import Status
from ._validate import DensifyWarning
from ._version import __version__


__all__ = [
    "METHODS",
    "BLCPResult",
    "BoxWarmStart",
    "BimatrixResult",
    "GameBasis",
    "Certificate",
    "DensifyWarning",
    "LCPBatchResult",
    "LCPManyResult",
    "LCPResult",
    "MLCPResult",
    "Options",
    "PathsResult",
    "Problem",
    "ProblemFormatError",
    "QPResult",
    "Status",
    "WarmStart",
    "WarmStartBatch",
    "is_lcp_ray",
    "is_lcp_solution",
    "lcp_residual",
    "lemke_paths",
    "pivot_column",
    "read_problem",
    "result_to_dict",
    "solve_bimatrix",
    "solve_blcp",
    "solve_lcp",
    "solve_lcp_batch",
    "solve_lcp_batch_dask",
    "solve_lcp_many",
    "solve_mlcp",
    "solve_qp",
    "solve_qpsolvers_problem",
    "write_problem",
    "write_result",
    "__version__",
]
