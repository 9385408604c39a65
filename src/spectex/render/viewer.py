"""``spectex view``: an interactive window flying over the spectral texture (glfw + moderngl).

The window draws with the same :class:`~spectex.render.gl.GLRenderer` (and
so the same shader and specification) as ``spectex render``. Controls:

* mouse: drag with the left button to look around; wheel: speed x1.25 / x0.8;
* keys: W/S (or Up/Down) forward/back, A/D (or Left/Right) sideways, R/F
  up/down (Space/C too), 1-8 toggle layers, M mip-mapping on/off (shows
  the aliasing it prevents), N anisotropic filtering on/off, H haze on/off,
  Esc or Q quits.

Speed scales with altitude (``speed = max(altitude, 1 m) * factor`` per
second), so that flying feels the same from 1 m to 10 km; the altitude
never goes below 5 cm. The frame rate, altitude and toggles are drawn on
screen (and in the window title).

Where there is no display (no ``DISPLAY`` or ``WAYLAND_DISPLAY`` on Linux,
or glfw cannot initialise or open an OpenGL 3.3 window),
:class:`NoDisplay` is raised with one line that points to ``spectex
render``.
"""

from __future__ import annotations

import math
import os
import sys
import time

import numpy as np

from ..shading.camera import Atmosphere, Camera
from ..shading.constants import DEFAULT_ANISOTROPY

__all__ = ["NoDisplay", "check_display", "run_viewer", "Flight"]

_HINT = "use 'spectex render TEXTURE --camera X,Y,Z,YAW,PITCH -o out.png' (or --frames N -o fly.mp4) instead"


class NoDisplay(OSError):
    """There is no display to open a window on."""


def check_display() -> None:
    """Raise :class:`NoDisplay` (one line) if no window can be opened here."""
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise NoDisplay(f"no display to open a window on (DISPLAY and WAYLAND_DISPLAY are not set); {_HINT}")
    try:
        import glfw  # noqa: F401
    except ImportError:
        raise NoDisplay(f"the viewer needs glfw: pip install 'spectex[gl]'; or {_HINT}") from None


class Flight:
    """The viewer's camera state and its response to input (no GL; testable).

    Parameters
    ----------
    camera : Camera
        Where the flight starts.
    n_layers : int
        For the layer toggles.
    """

    MIN_ALTITUDE = 0.05

    def __init__(self, camera: Camera, n_layers: int):
        self.x, self.y, self.z = camera.position
        self.yaw = camera.yaw
        self.pitch = camera.pitch
        self.fov = camera.fov
        self.speed_factor = 2.0
        self.enabled = [True] * n_layers
        self.mipmaps = True
        self.anisotropy = True
        self.haze = True

    @property
    def camera(self) -> Camera:
        return Camera((self.x, self.y, self.z), yaw=self.yaw, pitch=self.pitch, fov=self.fov)

    @property
    def speed(self) -> float:
        """Metres per second: proportional to the altitude."""
        return max(self.z, 1.0) * self.speed_factor

    def move(self, forward: float, sideways: float, upward: float, dt: float) -> None:
        """Move by key state (each -1, 0 or 1) for ``dt`` seconds."""
        step = self.speed * dt
        yaw = math.radians(self.yaw)
        fx, fy = math.sin(yaw), math.cos(yaw)
        self.x += step * (forward * fx + sideways * fy)
        self.y += step * (forward * fy - sideways * fx)
        self.z = max(self.MIN_ALTITUDE, self.z + step * upward)

    def look(self, dx_pixels: float, dy_pixels: float, height: int) -> None:
        """Turn by a mouse drag: one window height is one field of view."""
        scale = self.fov / max(height, 1)
        self.yaw = (self.yaw + dx_pixels * scale) % 360.0
        self.pitch = min(89.0, max(-89.0, self.pitch - dy_pixels * scale))

    def scroll(self, clicks: float) -> None:
        self.speed_factor = min(1000.0, max(0.01, self.speed_factor * 1.25 ** clicks))

    def toggle_layer(self, k: int) -> None:
        if 0 <= k < len(self.enabled):
            self.enabled[k] = not self.enabled[k]

    def status(self, fps: float) -> str:
        layers = "".join(str(k + 1) if on else "-" for k, on in enumerate(self.enabled))
        return (f"{fps:5.1f} fps  alt {self.z:8.2f} m  speed {self.speed:7.1f} m/s  layers {layers}  "
                f"mip {'on' if self.mipmaps else 'off'}  aniso {'on' if self.anisotropy else 'off'}  "
                f"haze {'on' if self.haze else 'off'}")


def _text_image(text: str) -> np.ndarray:
    """White text on a translucent dark box, RGBA uint8 (row 0 at the top)."""
    from PIL import Image, ImageDraw, ImageFont

    font = ImageFont.load_default()
    box = ImageDraw.Draw(Image.new("RGBA", (1, 1))).textbbox((0, 0), text, font=font)
    w, h = box[2] - box[0] + 12, box[3] - box[1] + 10
    img = Image.new("RGBA", (w, h), (0, 0, 0, 150))
    ImageDraw.Draw(img).text((6 - box[0], 5 - box[1]), text, fill=(255, 255, 255, 255), font=font)
    return np.asarray(img)


def run_viewer(texture, *, camera: Camera | None = None, size=(720, 1280), haze=None) -> None:
    """Open the window and fly until it is closed.

    Parameters
    ----------
    texture : SpectralTexture
    camera : Camera, optional
        Start camera (default: 2 m up, looking north and slightly down).
    size : (int, int)
        Window ``(height, width)``.
    haze : float, optional
        Haze distance in metres, 0 for none (default: ``Atmosphere``'s); H toggles it.

    Raises
    ------
    NoDisplay
        If no window can be opened (one line, pointing to ``spectex render``).
    """
    check_display()
    import glfw

    from .._gl import create_context
    from .gl import GLRenderer, TextOverlay

    camera = camera or Camera((0.0, 0.0, 2.0), yaw=0.0, pitch=-10.0)
    flight = Flight(camera, len(texture.layers))
    if not glfw.init():
        raise NoDisplay(f"glfw could not initialise a display; {_HINT}")
    try:
        glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
        glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
        glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
        glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
        h, w = size
        window = glfw.create_window(int(w), int(h), "spectex view", None, None)
        if not window:
            raise NoDisplay(f"could not open an OpenGL 3.3 window; {_HINT}")
        glfw.make_context_current(window)
        glfw.swap_interval(0)
        ctx = create_context(standalone=False, what="the viewer")
        _loop(window, ctx, texture, flight, glfw, GLRenderer, TextOverlay, haze)
    finally:
        glfw.terminate()


def _press(key, window, flight, glfw) -> None:
    """One key press: quit, a layer toggle (1-8), mip-maps (M), anisotropy (N) or haze (H)."""
    if key in (glfw.KEY_ESCAPE, glfw.KEY_Q):
        glfw.set_window_should_close(window, True)
    elif glfw.KEY_1 <= key <= glfw.KEY_8:
        flight.toggle_layer(key - glfw.KEY_1)
    elif key == glfw.KEY_M:
        flight.mipmaps = not flight.mipmaps
    elif key == glfw.KEY_N:
        flight.anisotropy = not flight.anisotropy
    elif key == glfw.KEY_H:
        flight.haze = not flight.haze


def _drag(window, flight, glfw, start, fb_h):
    """Look around while the left button is held; returns the new drag start (None when released)."""
    if glfw.get_mouse_button(window, glfw.MOUSE_BUTTON_LEFT) != glfw.PRESS:
        return None
    mx, my = glfw.get_cursor_pos(window)
    if start is not None:
        flight.look(mx - start[0], my - start[1], fb_h)
    return (mx, my)


def _loop(window, ctx, texture, flight, glfw, GLRenderer, TextOverlay, haze=None):
    state = {"drag": None, "scroll": 0.0, "keys": []}

    def on_scroll(_win, _dx, dy):
        state["scroll"] += dy

    def on_key(_win, key, _scancode, action, _mods):
        if action == glfw.PRESS:
            state["keys"].append(key)

    glfw.set_scroll_callback(window, on_scroll)
    glfw.set_key_callback(window, on_key)
    overlay = TextOverlay(ctx)
    renderer = GLRenderer(texture, ctx=ctx)
    hazed = Atmosphere() if haze is None else Atmosphere(haze_distance=haze)  # haze: metres, 0 = none
    no_haze = Atmosphere(haze_distance=0.0)
    last = time.perf_counter()
    fps_t, fps_n, fps = last, 0, 0.0
    try:
        while not glfw.window_should_close(window):
            glfw.poll_events()
            now = time.perf_counter()
            dt = min(now - last, 0.25)
            last = now
            for key in state["keys"]:
                _press(key, window, flight, glfw)
            state["keys"].clear()
            if state["scroll"]:
                flight.scroll(state["scroll"])
                state["scroll"] = 0.0

            def held(*keys):
                return any(glfw.get_key(window, k) == glfw.PRESS for k in keys)

            fwd = held(glfw.KEY_W, glfw.KEY_UP) - held(glfw.KEY_S, glfw.KEY_DOWN)
            side = held(glfw.KEY_D, glfw.KEY_RIGHT) - held(glfw.KEY_A, glfw.KEY_LEFT)
            up = held(glfw.KEY_R, glfw.KEY_SPACE) - held(glfw.KEY_F, glfw.KEY_C)
            flight.move(fwd, side, up, dt)
            fb_w, fb_h = glfw.get_framebuffer_size(window)
            state["drag"] = _drag(window, flight, glfw, state["drag"], fb_h)
            if fb_w < 1 or fb_h < 1:
                continue
            ctx.screen.use()
            ctx.viewport = (0, 0, fb_w, fb_h)
            renderer.draw(flight.camera, (fb_h, fb_w), filter="trilinear" if flight.mipmaps else "linear",
                          anisotropy=DEFAULT_ANISOTROPY if flight.anisotropy else 1.0, enabled=flight.enabled,
                          atmosphere=hazed if flight.haze else no_haze)
            fps_n += 1
            if now - fps_t >= 0.5:
                fps = fps_n / (now - fps_t)
                fps_t, fps_n = now, 0
                text = flight.status(fps)
                glfw.set_window_title(window, f"spectex view  {text}")
                overlay.set_image(_text_image(text))
            overlay.draw(fb_w, fb_h, margin=8)
            glfw.swap_buffers(window)
    finally:
        renderer.release()
        overlay.release()
