"""The texture object of the reference sampler: a mip chain with its sampler state (plain data).

:class:`MipTexture` holds what an OpenGL texture object holds (the levels, as
RGBA float32 texels, quantised as an ``RGBA8`` texture stores them, and the
wrap, filter, anisotropy and level-of-detail state) and checks it; it runs no
kernel. ``shading.sampler`` samples it (numba), ``shading.resources`` builds
the ones a texture's layers read, and the exports read their texels, so it
lives apart from the kernels: making one imports no numba. The names of its filters and wrap modes become the codes
of ``shading.constants`` here (:func:`filter_code`, :func:`wrap_code`; ``shading.tables`` packs them).
"""

from __future__ import annotations

import numpy as np

from .._validate import check_choice, check_float, check_image
from ..tiles.mipmap import gl_level_shapes, quantize
from .constants import DEFAULT_MAX_LOD, DEFAULT_MIN_LOD, FILTER_ALIASES, FILTERS, WRAP_MODES

__all__ = ["MAX_TEXELS", "MipTexture", "default_mip_chain", "filter_code", "wrap_code"]


def filter_code(name: str, value) -> int:
    """The integer code of a filter name (aliases allowed); ``name`` is the parameter's, for the error."""
    if isinstance(value, str):
        value = FILTER_ALIASES.get(value.lower(), value.lower())
    return FILTERS.index(check_choice(name, value, FILTERS))


def wrap_code(name: str, value) -> int:
    """The integer code of a wrap-mode name; ``name`` is the parameter's, for the error."""
    if isinstance(value, str):
        value = value.lower()
    return WRAP_MODES.index(check_choice(name, value, WRAP_MODES))


# Largest number of texels (over all levels) a MipTexture may hold: 64 Mi
# texels, 1 GiB as float32 RGBA.
MAX_TEXELS = 1 << 26


def default_mip_chain(image: np.ndarray) -> list[np.ndarray]:
    """The mip chain of ``image``: ``spectex.tiles.mip_chain`` (imported lazily)."""
    from ..tiles import mip_chain

    return [np.asarray(level, dtype=np.float32) for level in mip_chain(image)]


class MipTexture:
    """A mip-mapped texture with its sampler state, like an OpenGL texture object.

    Parameters
    ----------
    levels : sequence of ndarray
        The mip levels, level 0 first, each ``(h_d, w_d, C)`` (or ``(h_d,
        w_d)``) with ``C`` in 1..4 and values in [0, 1]. Their shapes must be
        those OpenGL allocates (:func:`gl_level_shapes`); a single level
        makes a texture without mip-maps (``max_level = 0``). Row 0 of each
        array is ``t = 0``: the texture is addressed in the array's own
        order; no flip.
    wrap : str or (str, str)
        Wrap mode for ``s`` and ``t``: ``"repeat"``, ``"clamp_to_edge"`` or
        ``"mirrored_repeat"``.
    min_filter, mag_filter : str
        One of :data:`FILTERS` (``mag_filter`` only ``"nearest"`` or
        ``"linear"``).
    max_anisotropy : float
        1 disables anisotropic filtering; up to 16.
    lod_bias, min_lod, max_lod : float
        As ``GL_TEXTURE_LOD_BIAS``, ``GL_TEXTURE_MIN_LOD``, ``GL_TEXTURE_MAX_LOD``.
    bits : {8, None}
        Quantise the texels to 8 bits per channel (an ``RGBA8`` texture),
        or keep them as float32 (``None``).

    Attributes
    ----------
    data : ndarray, shape (N, 4), float32
        All levels' texels, RGBA (missing channels filled as OpenGL does:
        grey ``(L, L, L, 1)``, grey-alpha ``(L, L, L, A)``, RGB ``(R, G, B, 1)``).
    offsets, widths, heights : ndarray of int64
        Per level: first row in ``data``, width, height.
    """

    def __init__(self, levels, *, wrap="repeat", min_filter="linear_mipmap_linear",
                 mag_filter="linear", max_anisotropy=1.0, lod_bias=0.0, min_lod=DEFAULT_MIN_LOD,
                 max_lod=DEFAULT_MAX_LOD, bits=8):
        if isinstance(levels, np.ndarray):
            levels = [levels]
        levels = list(levels)
        if not levels:
            raise ValueError("levels must hold at least one level, got 0")
        if bits not in (8, None):
            raise ValueError(f"bits must be 8 or None, got {bits!r}")
        checked = []
        for d, level in enumerate(levels):
            level = check_image(f"levels[{d}]", level)
            if level.ndim == 2:
                level = level[:, :, None]
            checked.append(level)
        expected = gl_level_shapes(*checked[0].shape[:2])
        for d, level in enumerate(checked):
            if d >= len(expected) or level.shape[:2] != expected[d]:
                want = expected[d] if d < len(expected) else "no level"
                raise ValueError(f"levels[{d}] has shape {level.shape[:2]}, OpenGL's level {d} of a "
                                 f"{expected[0][1]}x{expected[0][0]} texture is {want}")
            if level.shape[2] != checked[0].shape[2]:
                raise ValueError(f"levels[{d}] has {level.shape[2]} channels, level 0 has "
                                 f"{checked[0].shape[2]}")
        total = sum(lv.shape[0] * lv.shape[1] for lv in checked)
        if total > MAX_TEXELS:
            raise ValueError(f"levels hold {total} texels, over the limit of {MAX_TEXELS}")
        if isinstance(wrap, str):
            wrap = (wrap, wrap)
        if not isinstance(wrap, (tuple, list)) or len(wrap) != 2:
            raise ValueError(f"wrap must be a mode or a pair of modes, got {wrap!r}")
        self.wrap = (WRAP_MODES[wrap_code("wrap[0]", wrap[0])], WRAP_MODES[wrap_code("wrap[1]", wrap[1])])
        self.min_filter = FILTERS[filter_code("min_filter", min_filter)]
        self.mag_filter = FILTERS[filter_code("mag_filter", mag_filter)]
        if self.mag_filter not in ("nearest", "linear"):
            raise ValueError(f"mag_filter must be 'nearest' or 'linear', got {mag_filter!r}")
        self.max_anisotropy = check_float("max_anisotropy", max_anisotropy, minimum=1.0, maximum=16.0)
        self.lod_bias = check_float("lod_bias", lod_bias)
        self.min_lod = check_float("min_lod", min_lod)
        self.max_lod = check_float("max_lod", max_lod)
        self.bits = bits
        self.channels = checked[0].shape[2]
        self.levels = [quantize(_to_rgba(lv), bits) for lv in checked]
        self.widths = np.array([lv.shape[1] for lv in self.levels], dtype=np.int64)
        self.heights = np.array([lv.shape[0] for lv in self.levels], dtype=np.int64)
        sizes = self.widths * self.heights
        self.offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self.data = np.ascontiguousarray(np.concatenate([lv.reshape(-1, 4) for lv in self.levels]),
                                         dtype=np.float32)

    @classmethod
    def from_image(cls, image, *, mipmaps=True, **kwargs):
        """A texture from one image, with its mip chain (``spectex.tiles.mip_chain``).

        With ``mipmaps=False`` the texture has level 0 only.
        """
        image = check_image("image", image)
        levels = default_mip_chain(image) if mipmaps else [image]
        return cls(levels, **kwargs)

    @property
    def shape(self) -> tuple[int, int]:
        """``(height, width)`` of level 0."""
        return int(self.heights[0]), int(self.widths[0])

    @property
    def max_level(self) -> int:
        return len(self.levels) - 1

    @property
    def nbytes_gpu(self) -> int:
        """Bytes the texture takes on the GPU (all levels, RGBA, 1 or 4 bytes per channel)."""
        return int(self.data.shape[0]) * 4 * (1 if self.bits == 8 else 4)

    def state(self) -> tuple:
        """Sampler state as kernel arguments."""
        return (wrap_code("wrap", self.wrap[0]), wrap_code("wrap", self.wrap[1]),
                filter_code("min_filter", self.min_filter), filter_code("mag_filter", self.mag_filter),
                self.max_anisotropy, self.lod_bias, self.min_lod, self.max_lod)

    def __repr__(self):
        h, w = self.shape
        return (f"MipTexture({w}x{h}, levels={len(self.levels)}, wrap={self.wrap}, "
                f"min_filter={self.min_filter!r}, mag_filter={self.mag_filter!r}, "
                f"max_anisotropy={self.max_anisotropy}, bits={self.bits})")


def _to_rgba(level: np.ndarray) -> np.ndarray:
    c = level.shape[2]
    if c == 4:
        return level
    h, w = level.shape[:2]
    out = np.ones((h, w, 4), dtype=np.float32)
    if c == 1:
        out[:, :, :3] = level
    elif c == 2:
        out[:, :, :3] = level[:, :, :1]
        out[:, :, 3] = level[:, :, 1]
    else:
        out[:, :, :3] = level
    return out
