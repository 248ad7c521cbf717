"""numba compilation for the objectives' kernels, with a pure-Python fallback.

numba is a speed-up only: without it the kernels run as plain Python (correct but slow) and
``experience`` falls back to its numpy reference. Compiled code is cached on disk
(``NUMBA_CACHE_DIR``) and keeps strict IEEE arithmetic unless a kernel asks for contraction.
A cached kernel is checked against its own module's file only: after editing a kernel that a
kernel of another module calls (``emst_prim`` under ``experience``), clear the cache, or the
caller keeps the old code.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar, cast

_numba: Any
try:  # numba is optional
    import numba as _numba
except ImportError:  # pragma: no cover - exercised only where numba is missing
    _numba = None

HAVE_NUMBA = _numba is not None

_F = TypeVar("_F", bound=Callable[..., Any])

prange: Callable[..., Any] = range if _numba is None else _numba.prange


def compiled(
    parallel: bool = False, contract: bool = False, nogil: bool = False
) -> Callable[[_F], _F]:
    """numba.njit with on-disk caching and strict IEEE arithmetic.

    ``contract`` lets the compiler fuse a multiply and an add (one rounding instead of two):
    only for float32 filters whose error bound allows it, never for a value that is returned.
    ``nogil`` releases the GIL while the kernel runs, so that it can run on a thread beside
    Python code.
    """
    if _numba is None:
        return lambda function: function
    fastmath: bool | set[str] = {"contract"} if contract else False
    return cast(
        Callable[[_F], _F],
        _numba.njit(cache=True, fastmath=fastmath, parallel=parallel, nogil=nogil),
    )


def thread_count() -> int:
    """The threads numba's parallel kernels run on (``NUMBA_NUM_THREADS``); 1 without numba."""
    return 1 if _numba is None else int(_numba.get_num_threads())
