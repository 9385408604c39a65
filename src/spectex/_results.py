"""The common ground of spectex's result objects (docs/conventions.md, "Results").

A result that holds several numbers is a frozen dataclass with attribute
names; :class:`AsDict` gives it an ``as_dict()`` for JSON.
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np


def _plain(value):
    if isinstance(value, AsDict):  # a result inside a result
        return value.as_dict()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


class AsDict:
    """Mixin for result dataclasses: ``as_dict()``, the fields as plain values."""

    def as_dict(self) -> dict:
        """The fields as plain Python values (lists for arrays and tuples), for JSON."""
        return {f.name: _plain(getattr(self, f.name)) for f in fields(self)}
