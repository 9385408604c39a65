"""The one way spectex makes an OpenGL context (moderngl), for the renderer, the
GPU magnification and the export's host drawing; errors say what to install."""

from __future__ import annotations

__all__ = ["GLUnavailable", "create_context"]

_INSTALL = "install Mesa's EGL and drivers (Debian/Ubuntu: libegl1 libgl1-mesa-dri)"


class GLUnavailable(OSError):
    """No OpenGL 3.3 context could be made (no moderngl, no EGL, no display)."""


def create_context(*, standalone: bool = True, what: str = "OpenGL rendering"):
    """A moderngl OpenGL 3.3 core context: headless EGL (``standalone=True``) or the current window's.

    ``what`` names the work that needs it, in the error message.

    Raises
    ------
    GLUnavailable
        An ``OSError``: moderngl is missing (``pip install 'spectex[gl]'``) or
        no OpenGL 3.3 context can be made (on Debian/Ubuntu, Mesa's EGL and
        llvmpipe come with ``libegl1`` and ``libgl1-mesa-dri``).
    """
    try:
        import moderngl
    except ImportError:
        raise GLUnavailable(f"{what} needs moderngl: pip install 'spectex[gl]'") from None
    try:
        if standalone:
            return moderngl.create_standalone_context(backend="egl", require=330)
        return moderngl.create_context(require=330)
    except Exception as exc:  # moderngl raises plain Exception subclasses
        text = " ".join(str(exc).split()) or type(exc).__name__
        kind = "EGL" if standalone else "window"
        raise GLUnavailable(f"no OpenGL 3.3 context ({kind}) for {what}: {text}"
                            + (f"; {_INSTALL}" if standalone else "")) from None
