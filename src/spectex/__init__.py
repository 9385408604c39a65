"""spectex: spectral texturing and the procedural and by-example texture
techniques around it.

The names most programs need are here: :class:`SpectralTexture` and
:class:`Layer` (the texture), :func:`make_tile` and :func:`make_seamless`
(its tile), :func:`fit` (a texture from a photograph), :class:`Camera` and
:class:`Atmosphere` (a view; ``spectex.render.render`` draws it),
:func:`read_image` and :func:`write_image`. Each concept has one module:
``noise`` and ``procedural`` (procedural noise and textures), ``spectral``
(spectral synthesis), ``spectrum`` (power spectra), ``periodic`` (Moisan's
decomposition), ``tiles``, ``texture``, ``shading``, ``render``, ``bake``,
``synthesis`` (texture synthesis by example), ``analysis`` and ``fitting``,
``metrics``, ``color``, ``io``, ``export``.

The package imports nothing heavy at start-up: submodules (``spectex.noise``,
``spectex.tiles``, ...) are loaded on first attribute access, so that
``import spectex`` and ``spectex --help`` stay instant.
"""

from __future__ import annotations

import importlib

from ._version import __version__


def _numba_cache() -> None:
    from pathlib import Path

    from ._numba_cache import fall_back

    fall_back(Path(__file__).resolve().parent)


_numba_cache()

_SUBMODULES = (
    "analysis",
    "bake",
    "color",
    "export",
    "fitting",
    "figures",
    "io",
    "metrics",
    "noise",
    "periodic",
    "procedural",
    "render",
    "sampling",
    "shading",
    "spectral",
    "spectrum",
    "synthesis",
    "texture",
    "tiles",
)

# Public names that live in a submodule: name -> module. ``render`` is the
# rendering package (``spectex.render.render`` draws a picture), so it is not
# a name here: a submodule and a function cannot share it.
_LAZY_NAMES = {
    "SpectralTexture": "texture",
    "Layer": "texture",
    "Camera": "shading.camera",
    "Atmosphere": "shading.camera",
    "fit": "fitting",
    "make_tile": "tiles",
    "make_seamless": "tiles",
    "read_image": "io",
    "write_image": "io",
    "fit_result": "fitting",
}

__all__ = ["__version__", *_SUBMODULES, *_LAZY_NAMES]


def __getattr__(name: str):
    if name in _SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    if name in _LAZY_NAMES:
        module = importlib.import_module(f"{__name__}.{_LAZY_NAMES[name]}")
        return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
