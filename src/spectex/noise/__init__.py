"""Procedural noise: Perlin (gradient) and value noise, fBm and turbulence.

NumPy in, NumPy out: coordinates broadcast; float32 stays float32, float64
stays float64. The kernels are numba-compiled on first use and cached on
disk, so the compile cost is paid once per machine.
"""

from ._api import fbm, perlin, turbulence, value
from ._tables import PERLIN_PERMUTATION, permutation

__all__ = ["perlin", "value", "fbm", "turbulence", "permutation", "PERLIN_PERMUTATION"]
