"""Rendering the spectral texture on a ground plane: camera, CPU reference, OpenGL, viewer.

``spectex.render.cpu.render_cpu`` draws with the reference sampler
(``spectex.sampling``); ``spectex.render.gl.GLRenderer`` draws the same
picture with OpenGL 3.3 through moderngl (headless EGL or a window). Both
follow ``docs/sampling.md``. Nothing heavy is imported here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import DEPRECATED
from ..shading.camera import Atmosphere, Camera, check_size

__all__ = ["Camera", "Atmosphere", "check_size", "render", "RenderResult", "DEFAULT_ANISOTROPY"]

#: The renderers' default maximum anisotropy (EXT_texture_filter_anisotropic's
#: ``N`` samples along the footprint's major axis, at most this many). Chosen
#: by ``benchmarks/bench_anisotropy.py`` (issue 18): on a full-contrast tile,
#: against an 8 x 8 supersampled truth, trilinear alone (1) scores 36.6 to
#: 40.6 dB on the views that minify (close-up 67 dB), 8 scores 45.1 to 47.8 dB
#: (16 gains under 0.5 dB more); a 1920 x 1080 ground view costs about 4x the
#: GL time of trilinear on llvmpipe and takes the CPU renderer off its fast
#: isotropic kernel. The viewer and the web export use the same 8. Pass
#: ``anisotropy=1`` for trilinear only.
DEFAULT_ANISOTROPY = 8.0


@dataclass(frozen=True, eq=False)
class RenderResult:
    """What :func:`render` drew.

    Attributes
    ----------
    image : ndarray of float32, shape (H, W, 3)
        The picture, RGB in [0, 1], row 0 at the top.
    backend : {"gl", "cpu"}
        The renderer that drew it.

    Unpacking (``image, backend = render(...)``), the old tuple return, still
    works for one release.
    """

    image: np.ndarray
    backend: str

    def __iter__(self):
        return iter((self.image, self.backend))

    def __getitem__(self, index):
        return (self.image, self.backend)[index]


def render(texture, camera, shape=DEPRECATED, *, backend="auto", size=DEPRECATED, **kwargs) -> RenderResult:
    """Render ``texture`` seen by ``camera``: a :class:`RenderResult` (``image``, ``backend``).

    ``shape`` is the picture's ``(height, width)`` in pixels (``size=``, the
    old name, still works for one release with a ``DeprecationWarning``).
    ``backend``: ``"gl"``, ``"cpu"`` or ``"auto"`` (GL when a context can be
    made, else the CPU). Returns a :class:`RenderResult`. The other
    keywords go to the renderer (``filter``, ``anisotropy``, default
    :data:`DEFAULT_ANISOTROPY`, ``supersample``, ``atmosphere``, ``enabled``).
    """
    from .._validate import check_choice, renamed

    shape = _required(renamed("render", "shape", shape, "size", size), "render", "shape")
    backend = check_choice("backend", backend, ("auto", "gl", "cpu"))
    if backend in ("auto", "gl"):
        from .gl import GLUnavailable, GLRenderer

        try:
            with GLRenderer(texture) as renderer:
                return RenderResult(renderer.render(camera, shape, **kwargs), "gl")
        except GLUnavailable:
            if backend == "gl":
                raise
    from .cpu import render_cpu

    return RenderResult(render_cpu(texture, camera, shape, **kwargs), "cpu")


def _required(value, where: str, name: str):
    """``value``, unless a required argument was given under neither name."""
    if value is DEPRECATED:
        raise TypeError(f"{where}() missing 1 required argument: '{name}'")
    return value
