"""The common ground of spectex's result objects (docs/conventions.md, "Results").

A result that holds several numbers is a frozen dataclass with attribute
names. Several used to be dicts: :class:`DictAccess` keeps their old
``result["key"]`` access working for one release, with a
``DeprecationWarning`` that names the attribute, and gives every result an
``as_dict()`` for JSON.
"""

from __future__ import annotations

import warnings
from dataclasses import fields

import numpy as np


def _plain(value):
    if isinstance(value, DictAccess):  # a result inside a result
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


class DictAccess:
    """Mixin for dataclasses that replaced a dict: ``as_dict()``, and the old
    ``result[key]`` / ``keys()`` access, deprecated."""

    #: Old dict keys that became attributes of another name: ``{old: new}``.
    _renamed: dict = {}

    def as_dict(self) -> dict:
        """The fields as plain Python values (lists for arrays and tuples), for JSON."""
        return {f.name: _plain(getattr(self, f.name)) for f in fields(self)}

    def keys(self):
        """The attribute names (deprecated: for code that used the old dict)."""
        self._warn(".keys()", "as_dict() or the attributes")
        return [f.name for f in fields(self)]

    def items(self):
        """``(name, value)`` pairs (deprecated: for code that used the old dict)."""
        self._warn(".items()", "as_dict().items()")
        return [(f.name, getattr(self, f.name)) for f in fields(self)]

    def get(self, key, default=None):
        """``result[key]`` or ``default`` (deprecated: for code that used the old dict)."""
        name = self._renamed.get(key, key)
        self._warn(f".get({key!r})", f"its attribute .{name}")
        return getattr(self, name) if name in {f.name for f in fields(self)} else default

    def __iter__(self):
        self._warn(" iterated", "as_dict()")
        return iter([f.name for f in fields(self)])

    def __contains__(self, key):
        self._warn(" 'in'", "hasattr() or as_dict()")
        return self._renamed.get(key, key) in {f.name for f in fields(self)}

    def __getitem__(self, key):
        name = self._renamed.get(key, key)
        if not isinstance(name, str) or name not in {f.name for f in fields(self)}:
            raise KeyError(key)
        self._warn(f"[{key!r}]", f"its attribute .{name}")
        return getattr(self, name)

    def _warn(self, what: str, instead: str) -> None:
        kind = type(self).__name__
        warnings.warn(f"{kind}{what} is deprecated and will be removed in the next release (the result "
                      f"was a dict; it is a {kind}): use {instead}", DeprecationWarning, stacklevel=3)
