"""The numba decorators the shading kernels' steps share: one home for how a step is compiled.

* :data:`jit_inline`: a small step, inlined by LLVM into its caller (``forceinline``: LLVM's
  ``alwaysinline``), compiled once per signature and linked into every kernel that calls it. numba's
  own ``inline="always"`` inlines at the level of its IR and types the caller again with every
  callee in it: the bake kernel took 100 s to compile cold that way (the first ``spectex fit`` after
  an install: 3 min 42 s), 25 s this way, and renders the same numbers to the bit (LLVM sees the same
  operations).
* :data:`jit_call`: a function called, not inlined (``shading._layers.shade_ground``).

Compiled on first use (``cache=True``), never at import.
"""

from __future__ import annotations

import numba

__all__ = ["jit", "jit_inline", "jit_call"]

#: A step compiled on its own, called where LLVM does not inline it.
jit = numba.njit(cache=True, nogil=True, fastmath=True)
#: A step inlined into its caller by LLVM.
jit_inline = numba.njit(cache=True, nogil=True, fastmath=True, forceinline=True)
#: A function called, not inlined: compiled once and shared by every kernel that calls it (the
#: renderer's and the bake's kernels both shade a ground point with ``shade_ground``; inlined, each
#: compiled its own copy of every sampler below it). Without numba's reference counting
#: (``_nrt=False``: it allocates nothing), so passing the tables' arrays costs no atomic increments
#: per call (with them, a call per ground point made the bake 3x slower on two threads); the same
#: numbers as inlined.
jit_call = numba.njit(cache=True, nogil=True, fastmath=True, _nrt=False)
