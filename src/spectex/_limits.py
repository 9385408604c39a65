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

__all__ = ["limit", "hint"]


def limit(name: str, default: int) -> int:
    """The limit ``name``: ``$SPECTEX_MAX_<name>`` if set to a whole number >= 1, else ``default``.

    A variable that is set but is not a positive whole number is ignored
    (the default holds), so that a typo can never lift a limit.
    """
    text = os.environ.get(f"SPECTEX_MAX_{name}", "").strip().replace("_", "")
    try:
        value = int(text, 0)
    except ValueError:
        return default
    return value if value >= 1 else default


def hint(name: str) -> str:
    """The words that tell a user how to raise the limit ``name``."""
    return f"set SPECTEX_MAX_{name} to raise it"
