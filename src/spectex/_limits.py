"""Resource limits: what one call may cost, checked before the work starts (issue 26).

Each limit has a default that suits a workstation and can be raised (or
lowered) for one process by an environment variable ``SPECTEX_MAX_<NAME>``
holding a whole number, read when spectex is imported::

    SPECTEX_MAX_BAKE_BYTES=$((1 << 44)) spectex bake t.toml -o big.zarr ...

The table of limits, their defaults and what they bound is in docs/limits.md.
A refusal names the parameter, the value, the limit and the variable.
"""

from __future__ import annotations

import math
import os

__all__ = ["limit", "hint", "SYNTH_EXEMPLAR_PIXELS", "SYNTH_WORK", "check_exemplar_pixels", "check_work",
           "check_quilting", "check_efros_leung", "efros_leung_work", "MAX_TILE_SIDE", "MAX_TEXT_LENGTH"]


def limit(name: str, default: int) -> int:
    """The limit ``name``: ``$SPECTEX_MAX_<name>`` if set to a whole number >= 1, else ``default``.

    A variable that is set but is not a positive whole number is ignored
    (the default holds), so that a typo can never lift a limit.
    """
    text = os.environ.get(f"SPECTEX_MAX_{name}", "").strip().replace("_", "")
    if not text.isascii():  # int() takes any script's digits ("٣"): a limit is written in ASCII
        return default
    try:
        value = int(text, 0)
    except ValueError:
        return default
    return value if value >= 1 else default


def hint(name: str) -> str:
    """The words that tell a user how to raise the limit ``name``."""
    return f"set SPECTEX_MAX_{name} to raise it"


#: Most pixels of an exemplar for quilting and Efros-Leung (their search grows with it): 2048 x 2048.
SYNTH_EXEMPLAR_PIXELS = limit("SYNTH_EXEMPLAR_PIXELS", 1 << 22)
#: Most estimated operations of one Efros-Leung synthesis (pixels x candidates x window x channels):
#: about two minutes on one core of an AMD EPYC Zen 4 (measured 0.5 to 1.2 G operations per second).
SYNTH_WORK = limit("SYNTH_WORK", 10 ** 11)

#: Largest tile side (``spectex.tiles.MAX_SIZE``): a tile of 8192 x 8192 holds 1 GiB, about 3 GiB at the
#: peak of its making. Not a variable: the renderers' textures stop there too.
MAX_TILE_SIDE = 8192

#: Most symbols one call of ``spectex.synthesis.generate_text`` makes (the text is built in memory: about
#: 10 s and a few hundred MB). Here, not in the synthesis package, so that ``spectex text`` refuses a
#: longer one before importing it (it imports numba).
MAX_TEXT_LENGTH = 10_000_000


def check_exemplar_pixels(name: str, shape, method: str) -> None:
    """Refuse an exemplar over :data:`SYNTH_EXEMPLAR_PIXELS` pixels for ``method``."""
    from . import _limits

    h, w = int(shape[0]), int(shape[1])
    if h * w > _limits.SYNTH_EXEMPLAR_PIXELS:
        raise ValueError(f"{name} of {w}x{h} = {h * w} pixels is over the limit of {_limits.SYNTH_EXEMPLAR_PIXELS} "
                         f"pixels for {method} (SPECTEX_MAX_SYNTH_EXEMPLAR_PIXELS; set it to raise the limit, "
                         "or crop or shrink the exemplar)")


def check_work(what: str, work: float, remedy: str) -> None:
    """Refuse a synthesis whose estimated operations ``work`` are over :data:`SYNTH_WORK`."""
    from . import _limits

    if work > _limits.SYNTH_WORK:
        raise ValueError(f"{what} is about {work:.2g} operations, over the limit of {_limits.SYNTH_WORK:.2g} "
                         f"(SPECTEX_MAX_SYNTH_WORK; set it to raise the limit, or {remedy})")


# The synthesis plans below need only shapes, not pixels: the library checks them after reading its
# arguments, and the command line from the exemplar's header, before decoding it or importing numba.

def check_quilting(exemplar_shape, shape, *, block, overlap, tileable, channels=1) -> tuple[int, int, int, int]:
    """Check an image quilting's sizes and cost; return ``(out_h, out_w, block, overlap)``.

    ``exemplar_shape`` is ``(height, width, ...)``; ``overlap`` None means
    ``max(1, block // 6)``; ``channels`` is the exemplar's (a lower bound is
    enough before it is read: the cost is checked again once it is).
    """
    from ._validate import check_int, check_shape

    out_h, out_w = check_shape("shape", shape)
    block = check_int("block", block, minimum=2)
    if overlap is None:
        overlap = max(1, block // 6)
    overlap = check_int("overlap", overlap, minimum=1)
    if overlap >= block:
        raise ValueError(f"overlap must be smaller than block={block}, got {overlap}")
    if tileable and 2 * overlap >= block:
        raise ValueError(f"overlap must be smaller than block/2={block / 2:g} for a tileable quilt, got {overlap}")
    eh, ew = int(exemplar_shape[0]), int(exemplar_shape[1])
    if eh < block or ew < block:
        raise ValueError(f"exemplar of {ew}x{eh} pixels is smaller than block={block}")
    check_exemplar_pixels("exemplar", exemplar_shape, "quilting")
    blocks = -(-out_h // (block - overlap)) * -(-out_w // (block - overlap))
    check_work(f"quilting of shape {out_w}x{out_h} in blocks of {block} from a {ew}x{eh} exemplar",
               blocks * eh * ew * (channels + 1) * 2.0 * max(math.log2(eh * ew), 1.0),  # an FFT correlation a block
               "use a smaller shape or exemplar, or a larger block")
    return out_h, out_w, block, overlap


def efros_leung_work(pixels, eh, ew, window, k, channels, method) -> float:
    """Estimated operations of an Efros-Leung synthesis (for the limit :data:`SYNTH_WORK`).

    Exhaustive: every output pixel compares its window with every exemplar
    position. Fast: about ``window**2 * (k + 1)`` candidates a pixel, plus
    the k-coherence sets (all pairs of exemplar positions in 24 dimensions,
    about 8 times faster per operation than the pixel loop).
    """
    n = max(eh - window + 1, 1) * max(ew - window + 1, 1)
    if method == "exhaustive":
        return float(pixels) * n * window * window * channels
    return float(pixels) * window ** 4 * (k + 1) * channels + (3.0 * n * n if k else 0.0)


def check_efros_leung(exemplar_shape, shape, *, window, k, method, channels=1) -> tuple[int, int, int, int]:
    """Check an Efros-Leung synthesis's sizes and cost; return ``(out_h, out_w, window, k)``."""
    from ._validate import check_choice, check_int, check_shape

    out_h, out_w = check_shape("shape", shape)
    window = check_int("window", window, minimum=3)
    if window % 2 == 0:
        raise ValueError(f"window must be odd, got {window}")
    method = check_choice("method", method, ("fast", "exhaustive"))
    k = check_int("k", k, minimum=0, maximum=32)
    eh, ew = int(exemplar_shape[0]), int(exemplar_shape[1])
    if eh < window or ew < window:
        raise ValueError(f"window={window} is larger than the exemplar ({ew}x{eh} pixels)")
    check_exemplar_pixels("exemplar", exemplar_shape, "efros-leung")
    check_work(f"efros-leung ({method}) of shape {out_w}x{out_h} from a {ew}x{eh} exemplar with window {window}",
               efros_leung_work(out_h * out_w, eh, ew, window, k, channels, method),
               "use a smaller shape, exemplar or window")
    return out_h, out_w, window, k
