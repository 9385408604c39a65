"""Rendering the spectral texture on a ground plane: camera, CPU reference, OpenGL, viewer.

``spectex.render.cpu.render_cpu`` draws with the reference sampler
(``spectex.sampling``); ``spectex.render.gl.GLRenderer`` draws the same
picture with OpenGL 3.3 through moderngl (headless EGL or a window). Both
follow ``docs/sampling.md``. Nothing heavy is imported here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..shading.camera import Atmosphere, Camera, check_size
from ..shading.constants import DEFAULT_ANISOTROPY
from .cpu import MAX_BAKE_PIXELS, bake, bake_layers

__all__ = ["Camera", "Atmosphere", "check_size", "render", "RenderResult", "DEFAULT_ANISOTROPY", "bake", "bake_layers",
           "MAX_BAKE_PIXELS"]


@dataclass(frozen=True, eq=False)
class RenderResult:
    """What :func:`render` drew.

    Attributes
    ----------
    image : ndarray of float32, shape (H, W, 3)
        The picture, RGB in [0, 1], row 0 at the top.
    backend : {"gl", "cpu"}
        The renderer that drew it.
    """

    image: np.ndarray
    backend: str


def render(texture, camera, shape, *, backend="auto", haze=None, **kwargs) -> RenderResult:
    """Render ``texture`` seen by ``camera``: a :class:`RenderResult` (``image``, ``backend``).

    ``shape`` is the picture's ``(height, width)`` in pixels.
    ``backend``: ``"gl"``, ``"cpu"`` or ``"auto"`` (GL when a context can be
    made, else the CPU). Returns a :class:`RenderResult`. The other
    keywords go to the renderer (``filter``, ``anisotropy``, default
    :data:`DEFAULT_ANISOTROPY`, ``supersample``, ``atmosphere``, ``enabled``).
    ``haze``: the haze distance in metres, 0 for none (as an engine export
    draws the texture): short for ``atmosphere=Atmosphere(haze_distance=haze)``
    (with ``atmosphere`` given too, its sky colours are kept).
    """
    from dataclasses import replace

    from .._validate import check_choice

    if haze is not None:
        atmosphere = kwargs.get("atmosphere")
        kwargs["atmosphere"] = (Atmosphere(haze_distance=haze) if atmosphere is None
                                else replace(atmosphere, haze_distance=haze))
    backend = check_choice("backend", backend, ("auto", "gl", "cpu"))
    if backend in ("auto", "gl"):
        from .gl import GLRenderer, GLUnavailable

        try:
            with GLRenderer(texture) as renderer:
                return RenderResult(renderer.render(camera, shape, **kwargs), "gl")
        except GLUnavailable:
            if backend == "gl":
                raise
    from .cpu import render_cpu

    return RenderResult(render_cpu(texture, camera, shape, **kwargs), "cpu")
