"""numba kernels: the only modules that import numba.  They trust their input and never raise.

Every kernel is ``njit(cache=True, nogil=True)``: compiled lazily on first call (importing
``lemke`` compiles nothing), cached on disk, and run without the GIL.  NumPy's error model
makes a division by zero give inf or nan instead of raising.  With ``NUMBA_DISABLE_JIT=1``
they run as plain Python, for debugging.
"""
from numba import njit

kernel = njit(cache=True, nogil=True, error_model="numpy")
