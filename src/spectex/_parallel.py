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


#: Points of at least this many are split over the threads by :func:`in_parts`.
SPLIT_MIN = 1 << 14


def in_parts(n: int, part, *, minimum: int = SPLIT_MIN) -> None:
    """Call ``part(start, stop)`` on contiguous runs of ``range(n)``, one per numba thread, at once.

    For a serial ``nogil`` kernel (``shading.stochastic``'s reference
    sampler): Python threads give it what ``prange`` would, one contiguous
    run of the loop per thread, and it compiles in half the time of a
    ``parallel=True`` kernel (numba's parallel pipeline copies and retypes the
    whole inlined loop body): 21 against 46 CPU seconds, the same bits. The
    price: the loop outlined by ``prange`` gets its arrays marked ``noalias``
    and runs faster, here 10 % (stochastic, anisotropic); 40 % for
    ``shading.sampler``'s kernel, which therefore stays ``parallel=True``, as
    do the renderers' (``bake._block``: twice as fast).
    Fewer than ``minimum`` points run in the calling thread. The thread count
    is ``numba.get_num_threads()``, so ``numba.set_num_threads(1)`` (Dask's
    workers) keeps one.
    """
    import numba

    threads = min(numba.get_num_threads(), n) if n >= minimum else 1
    if threads <= 1:
        part(0, n)
        return
    from concurrent.futures import ThreadPoolExecutor

    bounds = [n * i // threads for i in range(threads + 1)]
    with ThreadPoolExecutor(threads - 1) as pool:
        rest = [pool.submit(part, bounds[i], bounds[i + 1]) for i in range(1, threads)]
        part(bounds[0], bounds[1])
        for future in rest:
            future.result()
