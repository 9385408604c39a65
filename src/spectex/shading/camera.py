"""The perspective camera over the ground plane, and the sky and haze around it.

Section 7 of ``docs/sampling.md``; the CPU kernels (``shading.view``) and the
shader (``shaders/ground.frag.glsl``) take the camera as one
:class:`ViewParams`, made by :func:`view_params`.

Conventions (shared by the CPU and GL renderers):
world metres, ``x`` east, ``y`` north, ``z`` up, the ground is ``z = 0``.
``yaw`` is a compass heading in degrees (0 looks north along +y, 90 east
along +x); ``pitch`` is degrees above the horizontal (negative looks down,
-90 straight down); ``fov`` is the vertical field of view in degrees. Image
row 0 is the top of the picture.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._validate import check_float
from .constants import DEFAULT_HAZE, FAR_HAZE_RATIO, HAZE_OFF

__all__ = ["Camera", "Atmosphere", "ViewParams", "view_params", "MAX_RENDER_PIXELS", "check_size"]

#: Largest render, pixels times supersample squared: 64 Mpx (the CPU work
#: arrays and the GL framebuffer of such a render take about 1 GiB).
MAX_RENDER_PIXELS = 1 << 26
#: Largest side of a render (a common GL_MAX_RENDERBUFFER_SIZE).
MAX_RENDER_SIDE = 16384


def check_size(shape, supersample=1, *, name: str = "shape") -> tuple[int, int]:
    """``(height, width)`` of a render, checked against the memory budget.

    ``name`` is the parameter named in the errors (the command line passes
    ``"--size"``).
    """
    from .._validate import check_int, check_shape

    n = check_int("supersample", supersample, minimum=1, maximum=16)
    h, w = check_shape(name, shape, maximum_pixels=MAX_RENDER_PIXELS)
    if h * w * n * n > MAX_RENDER_PIXELS:
        raise ValueError(f"{name} {w}x{h} with supersample {n} is {h * w * n * n} samples, over the budget "
                         f"of {MAX_RENDER_PIXELS} (about 1 GiB of work memory)")
    if max(h, w) * n > MAX_RENDER_SIDE:
        raise ValueError(f"{name} {w}x{h} with supersample {n} has a side over {MAX_RENDER_SIDE} pixels")
    return h, w


@dataclass(frozen=True)
class Camera:
    """A pinhole camera above the ground plane.

    Parameters
    ----------
    position : (float, float, float)
        World position, metres; ``z`` (the altitude) must be > 0.
    yaw : float
        Compass heading, degrees (0 north, 90 east).
    pitch : float
        Degrees above the horizontal, in [-90, 90].
    fov : float
        Vertical field of view, degrees, in [1, 170].
    """

    position: tuple[float, float, float]
    yaw: float = 0.0
    pitch: float = -10.0
    fov: float = 60.0

    def __post_init__(self):
        p = self.position
        if not isinstance(p, (tuple, list, np.ndarray)) or len(p) != 3:
            raise ValueError(f"camera position must be (x, y, z), got {p!r}")
        x = check_float("camera x", p[0])
        y = check_float("camera y", p[1])
        z = check_float("camera z", p[2])
        if z <= 0:
            raise ValueError(f"camera z must be > 0 (above the ground plane z = 0), got {z}")
        object.__setattr__(self, "position", (x, y, z))
        object.__setattr__(self, "yaw", check_float("camera yaw", self.yaw))
        object.__setattr__(self, "pitch", check_float("camera pitch", self.pitch, minimum=-90.0, maximum=90.0))
        object.__setattr__(self, "fov", check_float("fov", self.fov, minimum=1.0, maximum=170.0))

    @classmethod
    def from_tuple(cls, values, *, fov=60.0) -> "Camera":
        """From ``(x, y, z, yaw, pitch)`` as the command line gives it."""
        if len(values) != 5:
            raise ValueError(f"camera must be X,Y,Z,YAW,PITCH, got {values!r}")
        x, y, z, yaw, pitch = values
        return cls((x, y, z), yaw=yaw, pitch=pitch, fov=fov)

    def basis(self):
        """Unit vectors ``forward``, ``right``, ``up`` (float64, shape (3,) each)."""
        yaw = math.radians(self.yaw)
        pitch = math.radians(self.pitch)
        cy, sy = math.cos(yaw), math.sin(yaw)
        cp, sp = math.cos(pitch), math.sin(pitch)
        forward = np.array([cp * sy, cp * cy, sp])
        right = np.array([cy, -sy, 0.0])
        up = np.cross(right, forward)
        return forward, right, up

    def tangents(self, height: int, width: int) -> tuple[float, float]:
        """Half-extents ``(tan_x, tan_y)`` of the image plane at distance 1."""
        tan_y = math.tan(math.radians(self.fov) / 2.0)
        return tan_y * width / height, tan_y

    def ray_steps(self, height: int, width: int) -> tuple[np.ndarray, np.ndarray]:
        """How the (unnormalised) ray direction changes per pixel along x and y.

        ``d = fwd + ndc_x tan_x right + ndc_y tan_y up`` with ``ndc_x = 2 px /
        width - 1`` and ``ndc_y = 1 - 2 py / height``, so ``dd/dpx = right 2
        tan_x / width`` and ``dd/dpy = -up 2 tan_y / height``: the inputs of
        each pixel's footprint (``docs/sampling.md``, section 7), for the
        CPU kernels and the shader alike.
        """
        _, right, up = self.basis()
        tan_x, tan_y = self.tangents(height, width)
        return np.asarray(right) * (2.0 * tan_x / width), np.asarray(up) * (-2.0 * tan_y / height)

    def moved(self, **changes) -> "Camera":
        """A copy with some fields changed."""
        from dataclasses import replace

        return replace(self, **changes)


@dataclass(frozen=True)
class Atmosphere:
    """Sky gradient and distance haze.

    The ground colour at distance ``D`` along the ray becomes ``horizon + exp(-D /
    haze_distance) (ground - horizon)``; beyond ``far = FAR_HAZE_RATIO
    haze_distance`` (50, ``shading.constants``) it is
    the horizon colour (the texture is not sampled there). The sky at
    elevation ``e`` (sine of the ray's angle above the horizon) is ``horizon +
    (1 - exp(-SKY_FALLOFF e)) (zenith - horizon)`` (``SKY_FALLOFF = 4``),
    continuous with the hazed ground at the horizon.

    ``haze_distance=0`` turns the haze off (the ground keeps its colour at
    every distance, as an engine export draws it; the texture is sampled to
    the horizon): ``Atmosphere(haze_distance=0)``, or ``render(..., haze=0)``.
    The default, 12 km, leaves a 1,200 m aerial view with most of the tile's
    colour (``docs/rendering.md``; the former 4 km took two thirds of it).
    """

    horizon: tuple[float, float, float] = (0.78, 0.82, 0.86)
    zenith: tuple[float, float, float] = (0.32, 0.50, 0.78)
    haze_distance: float = DEFAULT_HAZE

    def __post_init__(self):
        for name in ("horizon", "zenith"):
            v = getattr(self, name)
            if len(v) != 3:
                raise ValueError(f"{name} must be an RGB triple, got {v!r}")
            object.__setattr__(self, name, tuple(check_float(f"{name}[{i}]", v[i], minimum=0.0, maximum=1.0)
                                                 for i in range(3)))
        object.__setattr__(self, "haze_distance", check_float("haze_distance", self.haze_distance, minimum=0.0,
                                                              maximum=HAZE_OFF))

    @property
    def effective_haze(self) -> float:
        """The haze distance the shaders use: ``HAZE_OFF`` (no haze) for 0."""
        return HAZE_OFF if self.haze_distance == 0.0 else self.haze_distance

    @property
    def far(self) -> float:
        return FAR_HAZE_RATIO * self.effective_haze


class ViewParams(NamedTuple):
    """A perspective view as the kernels and the shader take it (section 7).

    Made by :func:`view_params`; numba passes it to the render kernels as
    one argument, and ``render.gl`` sets one uniform per field.
    """

    height: float          #: camera altitude, metres (> 0)
    fwd: np.ndarray        #: (3,) unit forward vector
    right: np.ndarray      #: (3,) unit right vector (horizontal)
    up: np.ndarray         #: (3,) unit up vector of the picture
    tan_x: float           #: half-extent of the image plane at distance 1, along x
    tan_y: float           #: and along y
    ddx: np.ndarray        #: (3,) change of the ray per pixel along x (Camera.ray_steps)
    ddy: np.ndarray        #: (3,) and along y
    horizon: np.ndarray    #: (3,) RGB
    zenith: np.ndarray     #: (3,) RGB
    haze_distance: float   #: metres (``HAZE_OFF`` for no haze)
    far: float             #: no texture beyond this distance, metres
    supersample: int       #: n x n samples per pixel


def view_params(camera: Camera, shape, *, atmosphere=None, supersample=1) -> ViewParams:
    """The :class:`ViewParams` of ``camera`` for a picture of ``shape = (height, width)`` pixels."""
    if not isinstance(camera, Camera):
        raise TypeError(f"camera must be a Camera, got {type(camera).__name__}")
    atmosphere = Atmosphere() if atmosphere is None else atmosphere
    if not isinstance(atmosphere, Atmosphere):
        raise TypeError(f"atmosphere must be an Atmosphere, got {type(atmosphere).__name__}")
    h, w = shape
    fwd, right, up = camera.basis()
    tan_x, tan_y = camera.tangents(h, w)
    ddx, ddy = camera.ray_steps(h, w)
    return ViewParams(float(camera.position[2]), fwd, right, up, float(tan_x), float(tan_y), ddx, ddy,
                      np.array(atmosphere.horizon, dtype=np.float64), np.array(atmosphere.zenith, dtype=np.float64),
                      float(atmosphere.effective_haze), float(atmosphere.far), int(supersample))
