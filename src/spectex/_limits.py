"""Resource limits: what one call may cost, checked before the work starts (issue 26).

Each limit has a default that suits a workstation and can be raised (or
lowered) for one process by an environment variable ``SPECTEX_MAX_<NAME>``
holding a whole number, read when spectex is imported::

    SPECTEX_MAX_BAKE_BYTES=$((1 << 44)) spectex bake t.toml -o big.zarr ...

The table of limits, their defaults and what they bound is in docs/limits.md.
A refusal names the parameter, the value, the limit and the variable.
"""

from __future__ import annotations

import os

__all__ = ["limit", "hint", "SYNTH_EXEMPLAR_PIXELS", "SYNTH_WORK", "check_exemplar_pixels", "check_work"]


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
