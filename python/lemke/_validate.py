"""Validation of user input, once, at the boundary: every solver and :class:`lemke.Problem`
call these, so an error reads the same wherever it is found.

Every function returns float64 arrays; they are the caller's own arrays when those already
are float64 (no copy), so the solvers treat them as read-only and never write to them.
Errors are ``TypeError`` (not numbers at all) or ``ValueError`` (wrong shape, NaN, an
infinity where none is allowed, inconsistent data), each naming the argument and the entry.
"""
from __future__ import annotations

import os
import sys
import warnings

import numpy as np

from . import _core
from ._npc import absmax, count, every, nz, some, sub


def article(k: int) -> str:
    """The article before the number k read aloud in a message: "an" for 8, 11, 18, 80-89,
    8000, 11000 (eight, eleven, eighteen), "a" for the rest ("a 2 x 2 game", "an 8 x 3 game")."""
    digits = str(abs(int(k)))
    lead = digits[: len(digits) % 3 or 3]  # the leading group of thousands, read first
    return "an" if lead[0] == "8" or lead in ("11", "18") else "a"


def real_array(x, name: str, allow_inf: int = 0) -> np.ndarray:
    """float64 view or copy of ``x``; NaN is refused, and so is an infinite entry unless
    ``allow_inf`` is -1 (``-inf`` allowed: lower bounds) or +1 (``+inf``: upper bounds)."""
    a = float64_array(x, name)
    good = np.isfinite(a)
    if allow_inf:
        good |= a == allow_inf * np.inf
    if not every(good):
        bad = np.argwhere(~good)[0]
        what = "a NaN or infinite" if not allow_inf else f"a NaN or {'+' if allow_inf < 0 else '-'}inf"
        raise ValueError(f"{name} has {what} entry at index {tuple(int(i) for i in bad)}")
    return a


def float64_array(x, name: str) -> np.ndarray:
    """float64 view or copy of ``x`` (a TypeError naming ``name`` unless it holds real
    numbers), its entries not checked: :func:`real_array` checks them, or the kernels do."""
    if hasattr(x, "toarray") and hasattr(x, "nnz"):  # scipy.sparse: densified for now
        x = densify(x, name)
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array: {exc}") from None
    if a.dtype.kind not in "fiub":  # float, int, unsigned, bool
        raise TypeError(f"{name} must hold real numbers, got dtype {a.dtype}")
    if a.dtype != np.float64:
        return a.astype(np.float64)
    # (an unaligned one copied: the core reads its arrays as doubles, and refuses unaligned
    # ones, src/python_arrays.hpp's Aligned; the copy holds the same bits)
    return a if a.flags.aligned else a.copy()


# ------------------------------------------------ array-likes for the native fronts

_ND = np.ndarray
_F64, _I64 = np.dtype(np.float64), np.dtype(np.int64)
_asarray = np.asarray
_as_f64, _all_f64 = _core.as_f64, _core.all_f64  # (src/python_front.cpp: made_f64)


def plain(x, nd: int, dtype=_F64, kinds: str = "fiub"):
    """``x`` as the native fronts read it (a C-contiguous ndarray of ``dtype``, float64 by
    default, with ``nd`` dimensions), converted once as :func:`float64_array` and the
    kinds' shape checks convert it (``np.asarray``, then the cast and C order: the same
    values), when ``x`` is a list, tuple or ndarray (exactly) whose dtype's kind is in
    ``kinds``; else None, and the validation then does it all and names what is wrong
    (ragged rows, other dimensions, a sparse matrix, object, complex or str entries...).
    An array that needs no conversion is returned as it is."""
    t = type(x)
    if dtype is _F64 and (t is _ND or t is list or t is tuple) and (a := _as_f64(x, nd)) is not None:
        return a  # (converted natively, the same values: src/python_front.cpp, made_f64)
    if t is _ND:
        a = x
    elif t is list or t is tuple:
        try:
            a = _asarray(x)
        except Exception:  # (ragged rows and the like: the validation says so)
            return None
    else:
        return None
    if a.ndim != nd or a.dtype.kind not in kinds:
        return None
    return c_aligned(a, dtype)


def _scalar_bound(x, n: int, side: int):
    """A Python number bound as :func:`blcp` expands it (``np.full(n, float(x))``), or None:
    not a float or an int64-sized int, or NaN, or an infinity the side refuses (the
    validation's message then)."""
    t = type(x)
    if t is float or (t is int and -2**63 <= x < 2**63):
        v = float(x)
        if v == v and v != -side * np.inf:
            return np.full(n, v)
    return None


def plain_lcp(M, q):
    """``(M, q)`` for ``lcp_front`` when either is an array-like that :func:`plain` converts
    (``[]`` for M is the empty matrix, as :func:`square_matrix` has it) and M is n x n for q
    of length n; None when nothing needed converting or anything is of another kind."""
    got = _lcp_pair(M, q)
    return None if got is None or (got[0] is M and got[1] is q) else got


def plain_many(Ms, qs):
    """Lists of the problems ``(M_b, q_b)`` (sequences of the same length) each made as
    :func:`plain_lcp` makes it; None when nothing needed converting or any problem is of
    another kind (the validation then checks them in order and names the first fault)."""
    if len(Ms) != len(qs):
        return None
    out_M, out_q = [], []
    same = True
    for M, q in zip(Ms, qs):
        got = _lcp_pair(M, q)
        if got is None:
            return None
        same = same and got[0] is M and got[1] is q
        out_M.append(got[0])
        out_q.append(got[1])
    return None if same else (out_M, out_q)


def _lcp_pair(M, q):
    """``(M, q)`` made by :func:`plain` (as they are when they need nothing), or None."""
    m = plain(M, 2)
    if m is None:
        if (type(M) is not list and type(M) is not tuple) or len(M):
            return None
        m = np.zeros((0, 0))
    v = plain(q, 1)
    if v is None:
        return None
    n = len(v)
    if m.shape[0] != n or m.shape[1] != n:
        return None
    return m, v


def plain_blcp(M, q, lo, hi, findex):
    """``(M, q, lo, hi, findex)`` for ``blcp_front`` as :func:`plain_lcp` makes its
    arguments (bounds also Python numbers, spread over the n rows; ``findex`` None or of an
    integer kind, made int64 as :func:`blcp` makes it); None when nothing needed converting
    or anything is of another kind."""
    got = _blcp_args(M, q, lo, hi, findex)
    return None if got is None or (got[0] is M and got[1] is q and got[2] is lo
                                   and got[3] is hi and got[4] is findex) else got


def plain_islands(M, q, lo, hi, findex):
    """Lists of the islands' ``(M_b, q_b, lo_b, hi_b, findex_b)`` of ``solve_blcp_many``
    each made as :func:`plain_blcp` makes its arguments (``lo``, ``hi``: sequences of the
    islands' bounds or one Python number for all; ``findex`` None or a sequence); None when
    nothing needed converting or any island is of another kind."""
    B = len(M)
    los, his = _each(lo, B), _each(hi, B)
    fis = (None,) * B if findex is None else _each(findex, B, False)
    if type(q) not in (list, tuple) or len(q) != B or los is None or his is None or fis is None:
        return None
    out = ([], [], [], [], [])
    same = True
    for got in map(_blcp_args, M, q, los, his, fis):
        if got is None:
            return None
        for col, x in zip(out, got):
            col.append(x)
    for col, given in zip(out, (M, q, los, his, fis)):
        same = same and all(a is b for a, b in zip(col, given))
    return None if same else out


def _each(v, B, scalar=True):
    """A sequence of B islands' ``v``, or one Python number for all (with ``scalar``), as
    a sequence; else None."""
    if type(v) is list or type(v) is tuple:
        return v if len(v) == B else None
    return (v,) * B if scalar and (type(v) is float or type(v) is int) else None


def _blcp_args(M, q, lo, hi, findex):
    """:func:`plain_blcp`'s arguments, made (as they are when they need nothing), or None."""
    m, v = plain(M, 2), plain(q, 1)
    if m is None or v is None or m.shape != (len(v), len(v)):
        return None
    n = len(v)
    a = plain(lo, 1)
    if a is None:
        a = _scalar_bound(lo, n, -1)
    b = plain(hi, 1)
    if b is None:
        b = _scalar_bound(hi, n, 1)
    f = None if findex is None else plain(findex, 1, _I64, "iu")
    if a is None or b is None or (findex is not None and f is None):
        return None
    return m, v, a, b, f


def plain_all(args, nds):
    """``args`` (a tuple, None for an argument not given) with each given one made as
    :func:`plain` makes it with its number of dimensions in ``nds``; None when nothing
    needed converting or anything is of another kind."""
    got = _all_f64(args, nds)  # (what made_f64 converts, and plain arrays: src/python_front.cpp)
    if got is not None:
        return got or None  # (False: plain arrays all, nothing to convert)
    out = []
    same = True
    for x, nd in zip(args, nds):
        if x is None:
            out.append(None)
            continue
        a = plain(x, nd)
        if a is None:
            return None
        same = same and a is x
        out.append(a)
    return None if same else out


class DensifyWarning(UserWarning):
    """A large ``scipy.sparse`` input was made dense (lemke has no sparse engine yet):
    the warning names the argument, its shape and the dense size."""


#: A sparse input whose dense float64 copy takes at least this many bytes (64 MiB: a
#: square matrix of n >= 2897) is densified with a :class:`DensifyWarning`.
DENSIFY_WARN_BYTES = 64 * 2**20


def densify(x, name: str) -> np.ndarray:
    """The scipy.sparse matrix ``x`` made dense: with a :class:`DensifyWarning` when the
    dense copy takes at least ``DENSIFY_WARN_BYTES``, and refused (a ValueError naming
    ``name``, before any allocation) when it would take more than the memory available
    (:func:`available_memory`; never refused when that is unknown)."""
    shape = tuple(int(d) for d in x.shape)
    entries = 1
    for d in shape:
        entries *= d
    size = entries * 8  # bytes of the float64 copy the solvers work on
    dims = " x ".join(map(str, shape))
    if size >= DENSIFY_WARN_BYTES:
        free = available_memory()
        if free is not None and size > free:
            raise ValueError(
                f"{name} is a scipy.sparse {dims} matrix ({x.nnz} stored entries); lemke has no "
                f"sparse engine yet and its dense {dims} float64 copy would take {_mib(size)}, "
                f"more than the {_mib(free)} of memory available: not densified")
        warnings.warn(
            f"{name}: the scipy.sparse {dims} matrix ({x.nnz} stored entries) is made dense, a "
            f"{dims} float64 array of {_mib(size)} (lemke has no sparse engine yet)",
            DensifyWarning, stacklevel=_caller_level())
    return x.toarray()


def _mib(size: int) -> str:
    return f"{size / 2**20:,.1f} MiB"


def available_memory():
    """Bytes of memory this process can still take, or None when unknown: Linux's
    ``MemAvailable`` (free memory and reclaimable caches), else the free pages of
    ``os.sysconf``; lowered to the room left under a cgroup memory limit (v2 or v1)."""
    free = None
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    free = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError, IndexError):
        pass
    if free is None:
        try:
            free = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (AttributeError, ValueError, OSError):
            return None
        if free <= 0:
            return None
    room = _cgroup_room()
    return free if room is None else min(free, room)


def _cgroup_room():
    """Bytes left under this process's cgroup memory limit (v2, else v1: the limit less
    the usage, the reclaimable ``inactive_file`` cache not counted, as ``docker stats``
    does), or None when there is no limit or it cannot be read."""
    dirs = []
    try:
        with open("/proc/self/cgroup") as f:
            path = next((line.strip()[3:] for line in f if line.startswith("0::")), None)
        if path is not None:
            dirs.append(("/sys/fs/cgroup" + path.rstrip("/"), "memory.max", "memory.current"))
    except OSError:
        pass
    dirs.append(("/sys/fs/cgroup/memory", "memory.limit_in_bytes", "memory.usage_in_bytes"))
    for base, limit_file, usage_file in dirs:
        try:
            with open(os.path.join(base, limit_file)) as f:
                limit = f.read().strip()
            if limit == "max" or int(limit) >= 2**60:
                continue  # no limit here
            with open(os.path.join(base, usage_file)) as f:
                used = int(f.read())
            try:
                with open(os.path.join(base, "memory.stat")) as f:
                    for line in f:
                        key, _, value = line.partition(" ")
                        if key == "inactive_file":
                            used -= int(value)
            except OSError:
                pass
            return max(0, int(limit) - max(used, 0))
        except (OSError, ValueError):
            continue
    return None


def _caller_level() -> int:
    """The ``stacklevel`` of a warning that points at the first frame outside lemke."""
    here = os.path.dirname(os.path.abspath(__file__))
    level, frame = 1, sys._getframe(1)
    while frame is not None:
        d = os.path.dirname(os.path.abspath(frame.f_code.co_filename))
        if d != here and not d.startswith(here + os.sep):
            break
        frame = frame.f_back
        level += 1
    return level


def kernel_array(a: np.ndarray) -> np.ndarray:
    """``a`` as the core's bindings take it: C-contiguous, aligned and writable (a copy only
    when it is not; the core never writes to its input, but some bindings take their inputs
    as plain, writable arrays, and all refuse unaligned ones)."""
    return a if a.flags.carray else np.array(a, order="C")


def c_aligned(a, dtype=None) -> np.ndarray:
    """``np.ascontiguousarray(a, dtype)``, copied once more when that is not aligned (as an
    array that starts off its scalar's alignment inside a buffer stays): the core's bindings
    read their arrays as doubles or int64 and refuse unaligned ones (src/python_arrays.hpp's
    ``Aligned``); the copy holds the same values."""
    a = np.ascontiguousarray(a, dtype=dtype)
    return a if a.flags.aligned else a.copy()


def square_matrix(M, name: str = "M") -> np.ndarray:
    """A square, C-contiguous float64 ``M`` (dense or scipy.sparse)."""
    a = real_array(M, name)
    if a.ndim == 1 and a.size == 0:
        a = np.zeros((0, 0))  # [] is the empty matrix
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise ValueError(f"{name} must be a square 2-D matrix, got shape {a.shape}")
    return np.ascontiguousarray(a)  # (a is aligned: real_array; so is any copy)


def vector(v, n: int, name: str) -> np.ndarray:
    """A float64 ``v``, which must have shape (n,)."""
    a = real_array(v, name)
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},) to match M, got shape {a.shape}")
    return a


def length(x, name: str) -> int:
    """The length of the vector ``x`` (which fixes a dimension of a problem)."""
    try:
        a = np.asarray(x)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric array: {exc}") from None
    if a.ndim != 1:
        raise ValueError(f"{name} must be a 1-D vector, got shape {a.shape}")
    return a.shape[0]


def _shape(x) -> tuple | None:
    """The shape of ``x`` without converting it (None when it has none, e.g. ragged rows)."""
    shape = getattr(x, "shape", None)  # an array, or scipy.sparse
    if shape is None:
        try:
            shape = np.shape(x)
        except (TypeError, ValueError):
            return None
    return tuple(int(k) for k in shape) if isinstance(shape, tuple) else None


def _sizes(x, name: str, axes: tuple, ndim: int) -> list:
    """The votes of ``x`` for the dimensions it fixes: ``(name, size)`` for each axis of
    ``axes`` when ``x`` has ``ndim`` dimensions (and, a matrix, entries: ``[]`` stands for
    any empty matrix); none otherwise."""
    shape = _shape(x)
    if shape is None or len(shape) != ndim or (ndim == 2 and 0 in shape):
        return []
    return [(name, shape[a]) for a in axes]


def _agreed(votes: list):
    """The size most of the arrays agree on, and the names of those that say so.

    ``votes`` are ``(name, size)`` pairs (a square matrix votes twice, once per axis); a tie
    goes to the earliest vote.  Data whose sizes disagree is reported as a fault of the
    argument that disagrees with the others (a q of the wrong length beside a square M is
    a wrong q, not a wrong M).  Returns ``(None, ())`` when nothing votes."""
    sizes = [size for _, size in votes]
    if not sizes:
        return None, ()
    best = max(sizes, key=lambda s: (sizes.count(s), -sizes.index(s)))
    return best, tuple(dict.fromkeys(name for name, size in votes if size == best))


def _because(name: str, names: tuple) -> str:
    """`` to match M and q``: the others that fix the size ``name`` was checked against."""
    others = _listed(names, name)
    return f" to match {others}" if others else ""


def block(x, name: str, shape: tuple, why: str = "") -> np.ndarray:
    """A float64 ``x`` of the given shape; ``[]`` (any array with no entries) stands for any
    empty shape, e.g. a C of shape (0, m), which a list of no rows cannot spell."""
    a = real_array(x, name)
    if a.size == 0 and 0 in shape:
        a = np.zeros(shape)
    if a.shape != shape:
        raise ValueError(f"{name} must have shape {shape}{why}, got shape {a.shape}")
    return a


# --------------------------------------------------------------------------- the kinds

def lcp(M, q, d=None):
    """An LCP: ``(M, q, d)`` as float64; ``d`` (the covering vector, positive) is None when
    not given."""
    M = square_matrix(M)
    n = M.shape[0]
    q = vector(q, n, "q")
    if d is not None:
        d = vector(d, n, "d")
        if n and not np.all(d > 0):
            raise ValueError(f"the covering vector d must be positive; d[{int(np.argmin(d))}] = {d.min()}")
    return M, q, d


def lcp_fields(M, q) -> dict:
    """The arrays of an LCP by name (what :class:`lemke.Problem` stores).  n is the size most
    of M's two sides and q's length agree on, so the one that differs is named."""
    n, names = _agreed(_sizes(q, "q", (0,), 1) + _sizes(M, "M", (0, 1), 2))
    if n is None:
        n = length(q, "q")  # q is not a vector: says so
    return {"M": block(M, "M", (n, n), _because("M", names)), "q": block(q, "q", (n,), _because("q", names))}


def mlcp(A, B, C, D, a, b) -> dict:
    """The six blocks of an MLCP (Siconos' storage 2), by name; n is the length of a, m that
    of b (a scalar is a vector of length 1)."""
    a = real_array(a, "a").reshape(-1) if np.ndim(a) <= 1 else real_array(a, "a")
    b = real_array(b, "b").reshape(-1) if np.ndim(b) <= 1 else real_array(b, "b")
    if a.ndim != 1:
        raise ValueError(f"a must be a vector, got shape {a.shape}")
    if b.ndim != 1:
        raise ValueError(f"b must be a vector, got shape {b.shape}")
    # n and m are the sizes most of the blocks agree on (a tie: those of a and b), so that
    # the block that differs is the one named
    n, n_from = _agreed([("a", a.size)] + _sizes(A, "A", (0, 1), 2) + _sizes(C, "C", (0,), 2)
                       + _sizes(D, "D", (1,), 2))
    m, m_from = _agreed([("b", b.size)] + _sizes(B, "B", (0, 1), 2) + _sizes(D, "D", (0,), 2)
                       + _sizes(C, "C", (1,), 2))

    def why(name):
        return (f" (n = {n} from {_listed(n_from, name) or 'a'}, "
                f"m = {m} from {_listed(m_from, name) or 'b'})")

    for name, v, size in (("a", a, n), ("b", b, m)):
        if v.size != size:
            raise ValueError(f"{name} must have shape ({size},){why(name)}, got shape {v.shape}")
    out = {name: block(x, name, shape, why(name))
           for name, x, shape in (("A", A, (n, n)), ("B", B, (m, m)), ("C", C, (n, m)), ("D", D, (m, n)))}
    out["a"], out["b"] = a, b
    return {k: out[k] for k in "ABCDab"}


def _listed(names: tuple, leave_out: str) -> str:
    """``A, C and D``: ``names`` without ``leave_out``, in words."""
    names = [n for n in names if n != leave_out]
    return ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else "".join(names)


def qp(P, q, G=None, h=None, A=None, b=None, lb=None, ub=None) -> dict:
    """The arrays of a QP in qpsolvers' form, by name, only those given (G with h, A with
    b).  A 1-D G or A is one row; a scalar bound applies to every variable; ``lb`` may hold
    -inf and ``ub`` +inf (no bound; magnitudes >= 1e20 count as infinite), and lb <= ub.  Convexity is the solver's check
    (:func:`symmetric_psd`), not a property of the data's form."""
    q = real_array(q, "q")
    if q.ndim != 1:
        raise ValueError(f"q must be a vector, got shape {q.shape}")
    # n = 0 is allowed: the constraints are then constant rows 0 <= h, 0 = b.  n is the size
    # most of q, P's sides, G's and A's columns and the bound vectors agree on (a tie: q's),
    # so the one that differs is named
    votes = [("q", q.size)] + _sizes(P, "P", (0, 1), 2)
    for M, name in ((G, "G"), (A, "A")):
        votes += _sizes(M, name, (1,), 2) or _sizes(M, name, (0,), 1)  # a 1-D G or A is one row
    for v, name in ((lb, "lb"), (ub, "ub")):
        votes += _sizes(v, name, (0,), 1)
    n, names = _agreed(votes)
    if q.size != n:
        raise ValueError(f"q must have shape ({n},){_because('q', names)}, got shape {q.shape}")
    P = real_array(P, "P")
    if n == 0 and P.size == 0:
        P = np.zeros((0, 0))  # [] or any other empty array
    if P.shape != (n, n):
        raise ValueError(f"P must have shape ({n}, {n}){_because('P', names)}, got {P.shape}")
    out = {"P": P, "q": q}
    for M, v, mname, vname in ((G, h, "G", "h"), (A, b, "A", "b")):
        if M is not None or v is not None:
            out[mname], out[vname] = _rows(M, v, n, mname, vname)
    for v, name, sign in ((lb, "lb", -1), (ub, "ub", 1)):
        if v is not None:
            out[name] = _bound(v, n, name, sign)
    if "lb" in out and "ub" in out:
        bad = nz(out["lb"] > out["ub"])
        if bad.size:
            j = int(bad[0])
            raise ValueError(f"lb[{j}] = {out['lb'][j]} exceeds ub[{j}] = {out['ub'][j]}: no x satisfies the bounds")
    return out


def _rows(M, v, n, mname, vname):
    if M is None or v is None:
        given, missing = (mname, vname) if v is None else (vname, mname)
        raise ValueError(f"{given} was given without {missing}: pass both or neither")
    M = real_array(M, mname)
    v = real_array(v, vname).reshape(-1) if np.ndim(v) == 0 else real_array(v, vname)
    if M.size == 0 and v.ndim == 1 and (n == 0 or v.size == 0):
        M = np.zeros((v.size, n))  # [] for rows of no variables, or for no rows at all
    elif M.ndim == 1:
        M = M.reshape(1, -1)
    if M.ndim != 2 or M.shape[1] != n:
        raise ValueError(f"{mname} must have {n} columns (the size of P and q), got shape {M.shape}")
    if v.shape != (M.shape[0],):
        raise ValueError(f"{vname} must have shape ({M.shape[0]},) to match {mname}, got {v.shape}")
    return M, v


INFINITY = 1e20  # bounds at least this large in magnitude are infinite, as in qpsolvers


def _bound(v, n, name, sign):
    """A bound vector (a scalar applies to all n; entries of magnitude >= 1e20 become
    infinite); NaN refused, and an infinity of the wrong sign (a lower bound of +inf, an
    upper bound of -inf)."""
    try:
        a = np.array(v, dtype=np.float64).reshape(-1) if np.ndim(v) else np.full(n, float(v))
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a numeric vector: {exc}") from None
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},) to match q, got {a.shape}")
    if some(np.isnan(a)):
        raise ValueError(f"{name} has a NaN entry at index {int(np.flatnonzero(np.isnan(a))[0])}")
    a[a >= INFINITY] = np.inf
    a[a <= -INFINITY] = -np.inf
    if sign < 0 and some(a == np.inf):
        raise ValueError(f"{name} has an entry +inf: a lower bound must be below +inf")
    if sign > 0 and some(a == -np.inf):
        raise ValueError(f"{name} has an entry -inf: an upper bound must be above -inf")
    return a


def bimatrix(A, B) -> dict:
    """The payoffs of a bimatrix game by name: two finite, non-empty real m x n arrays
    (A the row player's, B the column player's)."""
    out = []
    for name, P in (("A", A), ("B", B)):
        try:
            P = np.asarray(P, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"payoff matrix {name} must be a 2-D array of real numbers") from None
        if P.ndim != 2:
            raise ValueError(f"payoff matrix {name} must be 2-D (m x n), got {P.ndim} dimension(s)")
        if P.shape[0] == 0 or P.shape[1] == 0:
            raise ValueError(f"payoff matrix {name} is {P.shape[0]} x {P.shape[1]}: "
                             "each player needs at least one action (empty strategy set)")
        bad = np.argwhere(~np.isfinite(P))
        if bad.size:
            i, j = bad[0]
            raise ValueError(f"payoff matrix {name} has a non-finite entry {P[i, j]} at ({i}, {j})")
        out.append(c_aligned(P))
    A, B = out
    if A.shape != B.shape:
        raise ValueError(f"payoff matrices A and B must have the same shape (m x n), got "
                         f"{A.shape[0]} x {A.shape[1]} and {B.shape[0]} x {B.shape[1]}")
    return {"A": A, "B": B}


def blcp(M, q, lo, hi, findex=None) -> dict:
    """A box LCP by name: float64 ``M, q, lo, hi`` (a scalar bound applies to every row) and,
    when given, ``findex`` as int64 (-1: no friction).
    ValueError naming the entry for a NaN, lo > hi, lo = +inf or hi = -inf, and for a
    friction index out of range, pointing at its own row or at another friction row, with
    mu < 0, with lo_i != -hi_i, or whose normal row has lo_f < 0."""
    # n is the size most of M's sides, q, lo, hi and findex agree on (a tie: M's), so the one
    # that differs is named
    votes = _sizes(M, "M", (0, 1), 2) + _sizes(q, "q", (0,), 1)
    for v, name in ((lo, "lo"), (hi, "hi"), (findex, "findex")):
        votes += _sizes(v, name, (0,), 1)
    n, names = _agreed(votes)
    if n is not None and _shape(M) not in (None, (n, n)) and 0 not in _shape(M):
        raise ValueError(f"M must have shape ({n}, {n}){_because('M', names)}, got shape {_shape(M)}")
    M = square_matrix(M)
    n = M.shape[0]
    q = vector(q, n, "q")
    lo = _box_bound(lo, n, "lo", -1)
    hi = _box_bound(hi, n, "hi", +1)
    if findex is not None:
        findex = _findex(findex, n, lo, hi)
    above = np.flatnonzero(lo > hi)
    if above.size:
        i = int(above[0])
        raise ValueError(f"lo[{i}] = {lo[i]} > hi[{i}] = {hi[i]}: every lower bound must be <= its upper bound")
    out = {"M": M, "q": q, "lo": lo, "hi": hi}
    if findex is not None:
        out["findex"] = findex
    return out


def _findex(findex, n, lo, hi):
    """The friction index as int64, checked (see :func:`as_blcp`)."""
    f = np.asarray(findex)
    if f.shape != (n,):
        raise ValueError(f"findex must have shape ({n},) to match M, got shape {f.shape}")
    if f.dtype.kind not in "iu":
        if f.dtype.kind != "f" or not np.all(np.isfinite(f)) or np.any(f != np.round(f)):
            bad = np.flatnonzero(~np.isfinite(f) | (f != np.round(f))) if f.dtype.kind == "f" else [0]
            raise ValueError(f"findex must hold integers; findex[{int(bad[0])}] = {f.flat[int(bad[0])]!r}")
    f = f.astype(np.int64)
    for i in np.flatnonzero(f != -1):
        fi = int(f[i])
        if not 0 <= fi < n:
            raise ValueError(f"findex[{i}] = {fi} is out of range: -1 (no friction) or a row in [0, {n})")
        if fi == i:
            raise ValueError(f"findex[{i}] = {i} points at its own row")
        if f[fi] != -1:
            raise ValueError(f"findex[{i}] = {fi} points at another friction row (findex[{fi}] = {int(f[fi])})")
        if hi[i] < 0:
            raise ValueError(f"friction row {i}: mu = hi[{i}] = {hi[i]} < 0")
        if not np.isfinite(hi[i]):
            raise ValueError(f"friction row {i}: mu = hi[{i}] must be finite")
        if lo[i] != -hi[i]:
            raise ValueError(f"friction row {i}: lo[{i}] = {lo[i]} must be -mu = -hi[{i}] = {-hi[i]} "
                             "(the ODE/Bullet convention)")
        if lo[fi] < 0:
            raise ValueError(f"findex[{i}] = {fi}: the normal row's lower bound lo[{fi}] = {lo[fi]} must be >= 0")
    return f


def _box_bound(x, n, name, side):
    a = real_array(x, name, allow_inf=side)
    if a.ndim == 0:
        a = np.full(n, float(a))
    if a.shape != (n,):
        raise ValueError(f"{name} must be a scalar or have shape ({n},) to match M, got shape {a.shape}")
    return np.ascontiguousarray(a)  # (a is aligned: real_array or np.full)


SYMMETRY_TOL = 1e-10  # relative: a larger asymmetry of P is an error, a smaller one rounding
CONVEXITY_TOL = 1e-10  # relative: P + CONVEXITY_TOL max|P| I must have a Cholesky factor


def symmetric_psd(P):
    """``(P + P') / 2`` after checking that P is symmetric (to a relative 1e-10: a triangle
    passed for the whole matrix is a common slip) and positive semidefinite (a Cholesky
    factor of ``P + 1e-10 max|P| I``)."""
    scale = absmax(P)
    if scale == 0.0:
        return np.zeros_like(P)
    # |P - P'|, then (P + P') / 2, in one n x n buffer (a fresh temporary costs a minor
    # fault per page: PRIMAL1's 325 x 325, 207 faults each)
    Ps = P - P.T
    np.abs(Ps, out=Ps)
    if Ps.max() > SYMMETRY_TOL * scale:
        i, j = np.unravel_index(int(np.argmax(Ps)), Ps.shape)
        raise ValueError(
            f"P is not symmetric: P[{i}, {j}] = {P[i, j]:.6g} but P[{j}, {i}] = {P[j, i]:.6g} "
            "(pass the full symmetric matrix, not one triangle)"
        )
    np.add(P, P.T, out=Ps)
    Ps *= 0.5  # (the bits of 0.5 * (P + P'))
    if not _has_cholesky(Ps, CONVEXITY_TOL * scale):
        lam = np.linalg.eigvalsh(Ps)
        raise ValueError(
            f"P is not positive semidefinite: its smallest eigenvalue is {lam[0]:.3g} (largest "
            f"{lam[-1]:.3g}); solve_qp solves convex QPs only, a KKT point of a non-convex one "
            "need not be a minimum"
        ) from None
    return Ps


def _has_cholesky(Ps, shift):
    """Whether ``Ps + shift I`` has a Cholesky factor (LAPACK's, ``np.linalg.cholesky``), the
    factorization restricted to the rows that have an off-diagonal non-zero: a row and
    column of Ps that are zero off the diagonal stay zero in the factor (each of its
    entries a sum of products with a zero factor), so LAPACK's step there computes
    ``sqrt(Ps_jj + shift)`` exactly and fails iff that argument is not positive; the coupled
    rows' factor is the factor of their own block.  On the LP-like Maros-Meszaros problems
    (a few tens of coupled rows among hundreds, PRIMAL*'s P diagonal) this skips an
    n x n factorization."""
    d = Ps.diagonal()
    coupled = count(Ps != 0.0, axis=1) > (d != 0.0)
    if not every(d[~coupled] + shift > 0.0):  # (a NaN fails, as in LAPACK)
        return False
    idx = nz(coupled)
    if idx.size:
        try:
            np.linalg.cholesky(sub(Ps, idx, idx) + shift * np.eye(idx.size))
        except np.linalg.LinAlgError:
            return False
    return True


def positive_int_or_none(value, name: str):
    """``value`` as an int, or None; anything else (a bool, a float, zero) is a ValueError."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name} must be a positive integer or None, got {value!r}")
    return int(value)


def method(name, methods) -> None:
    """``name`` must be one of ``methods``."""
    if name not in methods:
        raise ValueError(f"unknown method {name!r}; choose one of {', '.join(map(repr, methods))}")


def warm_start(ws, cls, size: int, what: str) -> None:
    """``ws`` must be None or a ``cls`` (WarmStart) for ``size`` pairs."""
    if ws is None:
        return
    if not isinstance(ws, cls):
        wrong_kind(ws, "warm_start", "lemke.WarmStart")
        raise TypeError(f"warm_start must be a lemke.WarmStart, got {type(ws).__name__}")
    if ws.n != size:
        raise ValueError(what.format(ws=ws.n, n=size))


def wrong_kind(ws, what, want):
    """A warm start of a box LCP (or a batch of either kind) where ``want`` is expected: a
    ValueError naming ``what`` (a warm start, but of another kind of problem; any other
    object is left to the caller's TypeError)."""
    kind = type(ws).__name__
    if kind in ("BoxWarmStart", "BoxWarmStartBatch", "WarmStartBatch", "WarmStart"):
        box = kind.startswith("Box")
        raise ValueError(f"{what} must be a {want}, got a lemke.{kind}"
                         + ("" if box == ("Box" in want) else
                            " (of a box LCP)" if box else " (of an LCP)"))
