"""Rendering the spectral texture on a ground plane: camera, CPU reference, OpenGL, viewer.

``spectex.render.cpu.render_cpu`` draws with the reference sampler
(``spectex.sampling``); ``spectex.render.gl.GLRenderer`` draws the same
picture with OpenGL 3.3 through moderngl (headless EGL or a window). Both
follow ``docs/sampling.md``. Nothing heavy is imported here.
"""

from __future__ import annotations

from ..shading.camera import Atmosphere, Camera, check_size

__all__ = ["Camera", "Atmosphere", "check_size", "render"]


def render(texture, camera, size, *, backend="auto", **kwargs):
    """Render ``texture`` seen by ``camera``: ``(H, W, 3)`` float32.

    ``backend``: ``"gl"``, ``"cpu"`` or ``"auto"`` (GL when a context can be
    made, else the CPU). Returns ``(image, backend_used)``.
    """
    from .._validate import check_choice

    backend = check_choice("backend", backend, ("auto", "gl", "cpu"))
    if backend in ("auto", "gl"):
        from .gl import GLUnavailable, GLRenderer

        try:
            with GLRenderer(texture) as renderer:
                return renderer.render(camera, size, **kwargs), "gl"
        except GLUnavailable:
            if backend == "gl":
                raise
    from .cpu import render_cpu

    return render_cpu(texture, camera, size, **kwargs), "cpu"
