"""How many threads a transform or a numba kernel uses (private to spectex).

Arrays of at least :data:`PARALLEL_MIN` elements are worked on with every
core; smaller ones with one thread, which is faster for them, and much faster
when the cores are busy with other work (thread start-up and waiting).
"""

from __future__ import annotations

import contextlib

#: Arrays of at least this many elements are transformed with every core.
PARALLEL_MIN = 1 << 20


def fft_workers(n: int) -> int:
    """scipy.fft ``workers`` for a transform over ``n`` elements."""
    return -1 if n >= PARALLEL_MIN else 1


@contextlib.contextmanager
def threads_for(n: int):
    """Run numba's parallel kernels on one thread for arrays under :data:`PARALLEL_MIN` elements."""
    if n >= PARALLEL_MIN:
        yield
        return
    import numba

    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        yield
    finally:
        numba.set_num_threads(before)
