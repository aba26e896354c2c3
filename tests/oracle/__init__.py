"""numba kernels: the only modules that import numba.  They trust their input and never raise.

Every kernel is ``njit(cache=True, nogil=True)``: compiled lazily on first call (importing
``lemke`` compiles nothing), cached on disk, and run without the GIL.  NumPy's error model
makes a division by zero give inf or nan instead of raising.  With ``NUMBA_DISABLE_JIT=1``
they run as plain Python, for debugging.

``inline_kernel`` is the same with ``inline="always"``: the glue between the entry kernels
and the methods is inlined into its callers at numba's IR level.  A ``kernel`` is compiled
into an LLVM module of its own, and every kernel that calls it links that module into its
own and optimizes and generates machine code for all of it again, so each level of plain
kernels between an entry point and the methods would compile the methods once more.

**No literal constants as arguments of kernels.**  numba types a constant argument (``0``,
``False``, and a variable that holds one at the call, such as ``k = 0`` before a loop) as a
literal type and compiles the callee, and everything it calls, once more for that value: an
``invert_in_place(G, 0)`` beside ``invert_in_place(G, k)`` doubled the compile of the
unrevised method's whole tree.  Pass ``np.int64(0)``, ``np.False_`` or ``np.True_``
instead (typed int64 and bool).
"""
from numba import njit

kernel = njit(cache=True, nogil=True, error_model="numpy")
inline_kernel = njit(cache=True, nogil=True, error_model="numpy", inline="always")


def entry_point(dispatcher, *samples):
    """The compiled entry point of ``dispatcher`` for the types of the sample arguments
    ``samples`` (arrays of the right dtype, dimensions, layout and flags; Python ints and
    floats), once that signature is compiled: calling it skips numba's dispatch (typing
    every argument, 0.3 us and more for a dozen).  Until then, or for a stand-in that is not
    a numba dispatcher (tests), the dispatcher itself: the caller then gets the usual
    dispatch.  The caller must pass exactly those types (the entry point does not check),
    and keeps what this returns once it is not the dispatcher."""
    overloads = getattr(dispatcher, "overloads", None)
    if overloads is None:
        return dispatcher
    compiled = overloads.get(tuple(dispatcher.typeof_pyval(v) for v in samples))
    if compiled is None:
        return dispatcher
    return compiled.entry_point
