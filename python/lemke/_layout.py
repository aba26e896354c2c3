"""The LCP driver's codes and the layout of its output buffer, in Python: what the fronts
read from the C++ core's answers (``src/lemke/lcp.hpp``: ``BufferLayout``, ``NOT_FINITE``,
``TRIVIAL``, ``Method``; a test checks that the two agree).  No numpy and no kernel here,
so that a front that only reads the layout loads neither.

The output buffer of a solve of size n is ``[z | z0 | ray (n + 1) | w | covering d | row
scales | column scales]``, 6n + 2 floats; ``solve_lcp`` allocates n more after it for the
basic z's (int64).
"""
import functools

NOT_FINITE = -1  # M or q has a NaN or an infinity (or sizes that do not match): the front reports it
TRIVIAL = -2  # q >= 0: z = 0 solves it, no pivot
TABLEAU = 0
UNREVISED = 1
#: The methods by name, with the code the core dispatches on: the one method registry.
METHODS = {"tableau": TABLEAU, "unrevised": UNREVISED}

#: The fields of the output buffer, in order, with their lengths as functions of n.
BUFFER = (("z", lambda n: n), ("z0", lambda n: 1), ("ray", lambda n: n + 1), ("w", lambda n: n),
          ("covering", lambda n: n), ("row_scale", lambda n: n), ("col_scale", lambda n: n))


@functools.lru_cache(maxsize=256)
def fields(n):
    """``{name: slice}`` of the output buffer for size n (``z0`` is an index)."""
    out, at = {}, 0
    for name, length in BUFFER:
        k = length(n)
        out[name] = at if name == "z0" else slice(at, at + k)
        at += k
    return out


@functools.lru_cache(maxsize=256)
def buffer_length(n):
    """The length of the output buffer for size n."""
    return sum(length(n) for _, length in BUFFER)


#: The smallest n at which a warm start whose basis fails is restarted from that basis
#: (``lemke::RESTART_FROM``); below it the problem goes cold.  Measured in
#: the history of the former numba driver (kernels/cold.py, ported and removed): the restart
#: pays from about n = 100 on (contact problems lose below, and restarts end in bases with
#: more z's basic at zero, which every later 0-pivot step pays in its LU).
RESTART_FROM = 100


#: The LCP driver's codes of a run whose answer is final when the kernel checked it (``ok``):
#: SOLVED, TRIVIAL (q >= 0: z = 0) and RAY_TERMINATION (``lemke::lcp_settled``).
SETTLED = frozenset({0, TRIVIAL, 2})


def public_status(code):
    """The LCP driver's code (an int, or an int64 array of them) as a public status code
    (``lemke::lcp_status`` in src/lemke/status.hpp): TRIVIAL is SOLVED's 0, every other code
    is itself (a Status, or NOT_FINITE, which the fronts report as an error).  Python's one
    place where the driver's codes become statuses (_lcp, _batch, _result)."""
    return code + (code == TRIVIAL) * -TRIVIAL
