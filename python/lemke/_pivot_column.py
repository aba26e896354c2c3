"""q' and one column of M' after a principal pivoting transform, without the full tableau.

This is the computation described by H. Dai and E. Drumwright, "Computing the principal
pivoting transform for solving linear complementarity problems with Lemke's algorithm"
(Drake documentation), which follows Cottle, Pang and Stone (1992), p. 71, eq. (10).
"""
from __future__ import annotations

import re
from typing import NamedTuple

import numpy as np

from . import _core
from ._validate import real_array

_EPS = np.finfo(np.float64).eps
_LABEL = re.compile(r"([wz])([1-9][0-9]*)\Z")


class _IndexSets(NamedTuple):
    """The index sets of the note, all 0-based.

    ``alpha``: w variables that are non-basic (sorted); ``alpha_prime``: where they sit in
    ``nonbasic``. ``beta``: z variables that are basic (sorted; ``n`` is the artificial one);
    ``beta_prime``: where they sit in ``basic``. ``alpha_bar`` / ``alpha_bar_prime``: the
    basic w variables and their places in ``basic``. ``beta_bar`` / ``beta_bar_prime``: the
    non-basic z variables and their places in ``nonbasic``.
    """

    alpha: np.ndarray
    alpha_prime: np.ndarray
    beta: np.ndarray
    beta_prime: np.ndarray
    alpha_bar: np.ndarray
    alpha_bar_prime: np.ndarray
    beta_bar: np.ndarray
    beta_bar_prime: np.ndarray


def _label_list(labels, name: str) -> list:
    """``labels`` as a list (plain ``str`` where the items are strings)."""
    if isinstance(labels, (str, bytes)):
        raise ValueError(f"{name} must be a sequence of labels such as ['w1', 'z2'], not the single string {labels!r}")
    try:
        items = list(labels)
    except TypeError:
        raise ValueError(f"{name} must be a sequence of labels such as ['w1', 'z2'], got {type(labels).__name__}") from None
    return [str(x) if isinstance(x, str) else x for x in items]


def _parse_labels(items: list, n: int, name: str) -> list[tuple[str, int]]:
    """The labels as ``(kind, 0-based index)`` pairs; ValueError on anything malformed."""
    parsed = []
    for pos, label in enumerate(items):
        match = _LABEL.match(label) if isinstance(label, str) else None
        if match is None:
            raise ValueError(
                f"{name}[{pos}] = {label!r} is not a variable label: expected 'w1'..'w{n}' or 'z1'..'z{n + 1}' "
                "(1-based; z{n+1} is the artificial variable)"
            )
        kind, number = match.group(1), int(match.group(2))
        top = n if kind == "w" else n + 1
        if number > top:
            raise ValueError(
                f"{name}[{pos}] = {label!r} is out of range: with n = {n}, the labels are "
                f"'w1'..'w{n}' and 'z1'..'z{n + 1}'"
            )
        parsed.append((kind, number - 1))
    return parsed


def _index_sets(n: int, basic, nonbasic) -> _IndexSets:
    """Check the labels of a Lemke basis and return the note's index sets (0-based)."""
    b = _parse_labels(_label_list(basic, "basic"), n, "basic")
    nb = _parse_labels(_label_list(nonbasic, "nonbasic"), n, "nonbasic")
    if len(b) != n:
        raise ValueError(f"basic must list n = {n} variables, got {len(b)}")
    if len(nb) != n + 1:
        raise ValueError(f"nonbasic must list n + 1 = {n + 1} variables, got {len(nb)}")
    seen: dict[tuple[str, int], str] = {}
    for name, parsed in (("basic", b), ("nonbasic", nb)):
        for kind, i in parsed:
            label = f"{kind}{i + 1}"
            if (kind, i) in seen:
                where = seen[(kind, i)]
                if where == name:
                    raise ValueError(f"{label} appears more than once in {name}")
                raise ValueError(f"{label} appears in both basic and nonbasic")
            seen[(kind, i)] = name
    # With the counts right and no repeats, the 2n + 1 labels are exactly w1..wn, z1..z{n+1}.
    basic_set = set(b)
    for i in range(n):
        if ("w", i) in basic_set and ("z", i) in basic_set:
            raise ValueError(
                f"w{i + 1} and z{i + 1} are both basic; a Lemke basis has at most one variable of "
                "each complementary pair basic"
            )

    def split(parsed, kind):
        pairs = sorted((i, pos) for pos, (k, i) in enumerate(parsed) if k == kind)
        return (np.array([i for i, _ in pairs], dtype=np.intp), np.array([p for _, p in pairs], dtype=np.intp))

    alpha, alpha_prime = split(nb, "w")
    beta, beta_prime = split(b, "z")
    alpha_bar, alpha_bar_prime = split(b, "w")
    beta_bar, beta_bar_prime = split(nb, "z")
    return _IndexSets(alpha, alpha_prime, beta, beta_prime, alpha_bar, alpha_bar_prime, beta_bar, beta_bar_prime)


def _solve_block(A: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``A^{-1} rhs``; LinAlgError when ``A`` is singular to working precision.

    With the core's own single-threaded elimination (``invert_in_place`` and ``linalg_solve``
    of ``src/lemke/linalg.cpp``: no LAPACK, so no BLAS
    thread pool): the inverse gives the exact 1-norm condition number, and the solve
    is an LU solve with partial pivoting."""
    m = A.shape[0]
    if m == 0:
        return np.zeros_like(rhs)
    inv = np.array(A, dtype=np.float64, order="C")
    if not _core.invert_in_place(inv, m):
        raise np.linalg.LinAlgError(
            f"the block M^(alpha beta) ({m} x {m}) is singular: these basic variables do not form a basis"
        )
    anorm = float(np.max(np.sum(np.abs(A), axis=0)))
    rcond = 1.0 / (anorm * float(np.max(np.sum(np.abs(inv), axis=0))))
    if not rcond >= _EPS:
        raise np.linalg.LinAlgError(
            f"the block M^(alpha beta) ({m} x {m}) is singular to working precision "
            f"(reciprocal condition number {rcond:.3g}): these basic variables do not form a basis"
        )
    A = np.ascontiguousarray(A, dtype=np.float64)
    x = np.empty_like(rhs)
    for j in range(rhs.shape[1]):
        ok, x[:, j] = _core.linalg_solve(A, np.ascontiguousarray(rhs[:, j]))
        if not ok:
            raise np.linalg.LinAlgError(f"the block M^(alpha beta) ({m} x {m}) is singular to working precision")
    return x


def pivot_column(M, q, basic, nonbasic, driving):
    r"""q' and the driving column of M' for a Lemke basis, by a solve with one square block.

    The augmented LCP system has ``n`` dependent variables ``w`` and ``n + 1`` independent
    variables ``z`` (the last one, :math:`z_{n+1}`, is Lemke's artificial variable):

    .. math::  w = M z + q, \qquad M \in \mathbb{R}^{n \times (n+1)},

    where the last column of ``M`` is the covering vector. Exchanging some w's with some z's
    gives the basic variables ``w'`` (listed in ``basic``) and the non-basic ones ``z'``
    (listed in ``nonbasic``), related by the same kind of equation,

    .. math::  w' = M' z' + q'.

    This function returns :math:`q'` (the values of the basic variables when every non-basic
    one is zero) and the column of :math:`M'` that multiplies the driving variable, that is
    :math:`\partial w' / \partial z'_{\mathrm{driving}}`, without forming :math:`M'`.

    Let :math:`\alpha` be the indices of the w's that are non-basic, :math:`\beta` those of
    the z's that are basic (both have the same size m), :math:`\bar\alpha` those of the basic
    w's, and let a prime denote where a variable sits in ``basic``. Solving the rows
    :math:`\alpha` of :math:`w = Mz + q` for :math:`z_\beta` and substituting into the rows
    :math:`\bar\alpha` gives (Dai and Drumwright, eqs. 2-3)

    .. math::
        q'_{\beta'} = -(M_{\alpha\beta})^{-1} q_\alpha, \qquad
        q'_{\bar\alpha'} = q_{\bar\alpha} + M_{\bar\alpha\beta}\, q'_{\beta'} .

    If the driving variable is :math:`w_{\alpha_\gamma}` (eqs. 4-6), with :math:`e_\gamma`
    the :math:`\gamma`-th unit vector of length m,

    .. math::
        c_{\beta'} = (M_{\alpha\beta})^{-1} e_\gamma, \qquad
        c_{\bar\alpha'} = M_{\bar\alpha\beta}\, c_{\beta'} ;

    if it is :math:`z_\zeta` (eqs. 7-8), with :math:`g = M_{:,\zeta}`,

    .. math::
        c_{\beta'} = -(M_{\alpha\beta})^{-1} g_\alpha, \qquad
        c_{\bar\alpha'} = g_{\bar\alpha} + M_{\bar\alpha\beta}\, c_{\beta'} .

    Only the m x m block :math:`M_{\alpha\beta}` is factorized (once, for both right-hand
    sides).

    Parameters
    ----------
    M : (n, n + 1) array_like
        The LCP matrix with the covering vector appended as its last column.
    q : (n,) array_like
        The constant vector.
    basic : sequence of str
        The n basic variables, in the order of ``w'``. Labels are 1-based: ``"w1"`` ..
        ``"wn"`` and ``"z1"`` .. ``"z{n+1}"``, where ``"z{n+1}"`` is the artificial variable.
    nonbasic : sequence of str
        The n + 1 non-basic variables, in the order of ``z'``.
    driving : str
        The driving (entering) variable; one of ``nonbasic``.

    Returns
    -------
    q_prime : (n,) ndarray of float64
        :math:`q'`, in the order of ``basic``.
    column : (n,) ndarray of float64
        The column of :math:`M'` for ``driving``, in the order of ``basic``: entry i is the
        rate at which ``basic[i]`` changes as ``driving`` increases, the other non-basic
        variables held at zero.

    Raises
    ------
    ValueError
        If ``M`` is not n x (n + 1), ``q`` is not of length n, either holds a NaN or an
        infinity, or the labels do not describe a Lemke basis: a malformed or out-of-range
        label, ``basic`` not of length n or ``nonbasic`` not of length n + 1, a variable
        listed twice (in one list or in both), a complementary pair :math:`w_i, z_i` both
        basic, or ``driving`` not in ``nonbasic``. Valid label sets are exactly Lemke's
        bases: complementary ones (:math:`z_{n+1}` non-basic, one variable of each pair
        basic) and almost-complementary ones (:math:`z_{n+1}` basic, exactly one pair with
        both variables non-basic).
    numpy.linalg.LinAlgError
        If :math:`M_{\alpha\beta}` is singular to working precision (its reciprocal
        condition number is below machine epsilon), so that the basic variables do not form
        a basis. ``LinAlgError`` is a subclass of ``ValueError``.
    TypeError
        If ``M`` or ``q`` does not hold real numbers.

    Notes
    -----
    The sign convention is Drake's, :math:`w = Mz + q`. In the equivalent tableau form
    :math:`[I \mid -M]\,(w, z) = q` with basis matrix B, ``q_prime`` is :math:`B^{-1} q` and
    ``column`` is :math:`-B^{-1} a`, where a is the driving variable's column of
    :math:`[I \mid -M]`.

    Examples
    --------
    The running example of the note (Cottle, Pang and Stone, Example 4.4.7), with the
    artificial variable z4 basic:

    >>> import numpy as np
    >>> import lemke
    >>> M = np.array([[0, -1, 2, 1], [2, 0, -2, 1], [-1, 1, 0, 1]])
    >>> q = np.array([-3, 6, -1])
    >>> q_prime, column = lemke.pivot_column(M, q, ["z4", "w2", "z3"], ["w1", "w3", "z2", "z1"], "w1")
    >>> q_prime
    array([1., 5., 1.])
    >>> column
    array([ 0. , -1. ,  0.5])
    """
    M = real_array(M, "M")
    if M.ndim != 2 or M.shape[1] != M.shape[0] + 1:
        raise ValueError(
            f"M must be n x (n + 1), the LCP matrix with the covering vector as its last column; got shape {M.shape}"
        )
    n = M.shape[0]
    q = real_array(q, "q")
    if q.shape != (n,):
        raise ValueError(f"q must have shape ({n},) to match M of shape {M.shape}, got shape {q.shape}")
    basic = _label_list(basic, "basic")
    nonbasic = _label_list(nonbasic, "nonbasic")
    sets = _index_sets(n, basic, nonbasic)
    if not isinstance(driving, str) or driving not in nonbasic:
        raise ValueError(f"driving = {driving!r} is not one of the non-basic variables {nonbasic}")
    kind, index = driving[0], int(driving[1:]) - 1

    alpha, beta, alpha_bar = sets.alpha, sets.beta, sets.alpha_bar
    m = alpha.size
    M_ab = M[np.ix_(alpha, beta)]
    M_abar_b = M[np.ix_(alpha_bar, beta)]

    rhs = np.empty((m, 2))
    rhs[:, 0] = -q[alpha]
    if kind == "w":  # eqs. 4-5: the gamma-th column of the inverse
        gamma = int(np.flatnonzero(alpha == index)[0])
        rhs[:, 1] = 0.0
        rhs[gamma, 1] = 1.0
        g_bar = np.zeros(alpha_bar.size)
    else:  # eq. 7
        rhs[:, 1] = -M[alpha, index]
        g_bar = M[alpha_bar, index]
    x = _solve_block(np.ascontiguousarray(M_ab), rhs)

    q_prime = np.empty(n)
    column = np.empty(n)
    q_prime[sets.beta_prime] = x[:, 0]
    q_prime[sets.alpha_bar_prime] = q[alpha_bar] + M_abar_b @ x[:, 0]  # eq. 3
    column[sets.beta_prime] = x[:, 1]
    column[sets.alpha_bar_prime] = g_bar + M_abar_b @ x[:, 1]  # eqs. 6 and 8
    return q_prime, column
