"""Whole numbers and decimals typed by a person: ASCII digits only (issue 26).

Python's ``int()`` and ``float()`` take more than a command line should:
any Unicode decimal digit (``int("٣") == 3``, full-width ``"３"``),
underscores (``"1_000"``), surrounding spaces, and for floats the words
``inf``, ``infinity`` and ``nan``. A value that reaches spectex through a
command-line option or an environment variable is parsed here instead, in
one place, so that every command refuses the same things in the same words.
This module imports nothing heavy (``spectex --help`` uses it).
"""

from __future__ import annotations

import math
import re

__all__ = ["parse_int", "parse_float", "MAX_DIGITS"]

_INT = re.compile(r"[+-]?[0-9]+", re.ASCII)
_FLOAT = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?", re.ASCII)
#: The most digits a typed number may have: more is a mistake (and ``int()`` of 4301 digits raises).
MAX_DIGITS = 100


def _shown(text: str) -> str:
    return repr(text if len(text) <= 40 else text[:37] + "...")


def parse_int(text: str) -> int:
    """``text`` as an int: an optional sign and ASCII digits, nothing else.

    Raises
    ------
    ValueError
        For anything else, with words a person can act on: non-ASCII digits,
        spaces, underscores, a decimal point or exponent, more than
        :data:`MAX_DIGITS` digits.
    """
    if not isinstance(text, str):
        raise TypeError(f"expected text, got {type(text).__name__}")
    if _INT.fullmatch(text) is None:
        raise ValueError(f"expected a whole number in ASCII digits (such as 3), got {_shown(text)}")
    if len(text.lstrip("+-")) > MAX_DIGITS:
        raise ValueError(f"expected a whole number of at most {MAX_DIGITS} digits, got {len(text)} characters")
    value = int(text)
    return 0 if value == 0 else value  # "-0" is 0


def parse_float(text: str) -> float:
    """``text`` as a finite float: ASCII digits, an optional point and exponent, nothing else.

    ``nan``, ``inf``, hexadecimal floats, underscores, spaces and non-ASCII
    digits are refused, and so is a number too large for a double (``1e999``,
    which ``float()`` turns into infinity). A negative zero becomes ``0.0``.

    Raises
    ------
    ValueError
        For anything else.
    """
    if not isinstance(text, str):
        raise TypeError(f"expected text, got {type(text).__name__}")
    if text.lower().lstrip("+-") in ("inf", "infinity", "nan"):
        raise ValueError(f"must be finite, got {_shown(text)}")
    if _FLOAT.fullmatch(text) is None:
        raise ValueError(f"expected a number in ASCII digits (such as 0.5 or 1e-3), got {_shown(text)}")
    if len(text) > MAX_DIGITS + 10:
        raise ValueError(f"expected a number of at most {MAX_DIGITS} digits, got {len(text)} characters")
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"must be finite (at most about 1.8e308 in size), got {_shown(text)}")
    return value + 0.0  # -0.0 + 0.0 == 0.0
