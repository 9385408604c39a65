"""spectex: spectral texturing and the procedural and by-example texture
techniques around it.

The package imports nothing heavy at start-up: submodules (``spectex.noise``,
``spectex.tiles``, ...) are loaded on first attribute access, so that
``import spectex`` and ``spectex --help`` stay instant.
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

_SUBMODULES = (
    "analysis",
    "color",
    "figures",
    "io",
    "metrics",
    "noise",
    "procedural",
    "render",
    "sampling",
    "spectral",
    "synthesis",
    "texture",
    "tiles",
)

# Public names that live in a submodule: name -> module.
_LAZY_NAMES = {
    "SpectralTexture": "texture",
    "fit": "analysis",
    "fit_result": "analysis",
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
