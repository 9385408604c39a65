"""The one small template language of spectex's generated text: shaders, engine files, scripts.

A template is the target's own text with three kinds of marks:

* ``{{name}}``: replaced by the value ``name`` of the context (text);
* a line ``{{#if name}}`` or ``{{#if not name}}`` ... ``{{/if}}``: the lines
  between are kept when the context's ``name`` is true (false);
* a line ``{{#each name}}`` ... ``{{/each}}``: the lines between, once per
  item of the context's list ``name`` (each item a dict whose entries join
  the context for that copy).

A line that starts with ``{{!`` is a comment of the template (what it is,
who fills it in), dropped with the directive lines. Everything a shader states is in
the template; the Python side gives names, numbers and literals only
(MaterialX ShaderGen's split of a target into a ``Syntax`` and its code
templates). The templates live beside their users: the shading core's in
``shading/shaders/`` (:mod:`spectex.shading.glsl`), the exports' in
``export/templates/`` (:mod:`spectex.export._template`).
"""

from __future__ import annotations

import re

__all__ = ["fill", "render_text", "each_block"]

_VALUE = re.compile(r"\{\{(\w+)\}\}")
_DIRECTIVE = re.compile(r"\s*\{\{([#/])(\w+)(?: (not )?(\w+))?\}\}\s*")


def fill(text: str, context: dict) -> str:
    """``text`` with every ``{{name}}`` replaced by ``str(context[name])`` (a missing name is an error)."""
    def value(match):
        key = match.group(1)
        if key not in context:
            raise KeyError(f"template: no value for {{{{{key}}}}}")
        return str(context[key])

    return _VALUE.sub(value, text)


def _block(lines: list[str], start: int) -> int:
    """The index of the line that closes the block opened at ``lines[start]``."""
    depth = 0
    for i in range(start, len(lines)):
        m = _DIRECTIVE.fullmatch(lines[i])
        if m is None:
            continue
        depth += 1 if m.group(1) == "#" else -1
        if depth == 0:
            return i
    raise ValueError(f"template: {lines[start].strip()} is not closed")


def _render(lines: list[str], context: dict) -> list[str]:
    out = []
    i = 0
    while i < len(lines):
        if lines[i].startswith("{{!"):  # the template's own comment
            i += 1
            continue
        m = _DIRECTIVE.fullmatch(lines[i])
        if m is None:
            out.append(fill(lines[i], context))
            i += 1
            continue
        kind, word, negate, name = m.groups()
        if kind == "/":
            raise ValueError(f"template: {lines[i].strip()} closes nothing")
        end = _block(lines, i)
        body = lines[i + 1:end]
        if word == "if":
            if bool(context[name]) != bool(negate):
                out += _render(body, context)
        elif word == "each":
            for item in context[name]:
                out += _render(body, {**context, **item})
        else:
            raise ValueError(f"template: unknown directive {lines[i].strip()}")
        i = end + 1
    return out


def render_text(text: str, context: dict) -> str:
    """The template ``text`` for ``context`` (values, flags and lists, see above)."""
    return "\n".join(_render(text.split("\n"), context))


def each_block(text: str, name: str) -> str:
    """The body of the template's (first) ``{{#each name}}`` block, a template of one item on its own."""
    lines = text.split("\n")
    for i, line in enumerate(lines):
        m = _DIRECTIVE.fullmatch(line)
        if m is not None and m.group(1) == "#" and m.group(2) == "each" and m.group(4) == name:
            return "\n".join(lines[i + 1:_block(lines, i)])
    raise ValueError(f"template: no {{{{#each {name}}}}} block")
