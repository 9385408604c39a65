"""The exports' template files (``export/templates/``), written in spectex's template language.

The language (values, ``{{#if}}`` and ``{{#each}}`` blocks) is
:mod:`spectex._template`'s, shared with the shading core's own templates
(``shading/shaders/``). Everything a shader states is in the template; the
Python side gives names, numbers and literals only (MaterialX ShaderGen's
split of a target into a ``Syntax`` and its code templates).
"""

from __future__ import annotations

from importlib import resources

from .._template import render_text

__all__ = ["read", "render"]


def read(name: str) -> str:
    """The text of ``export/templates/NAME``."""
    return resources.files("spectex.export").joinpath("templates", name).read_text(encoding="utf-8")


def render(name: str, context: dict) -> str:
    """The template ``export/templates/NAME`` for ``context`` (values, flags and lists: :mod:`spectex._template`)."""
    return render_text(read(name), context)
