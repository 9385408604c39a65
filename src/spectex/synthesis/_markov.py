"""Markov models of text: printed English as a 1-D texture (Shannon 1948)."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from .._validate import check_choice, check_int, check_seed

_UNITS = ("char", "word")


@dataclass(frozen=True)
class MarkovModel:
    """An n-gram model of text, as trained by :func:`train_markov`.

    Attributes
    ----------
    unit : {'char', 'word'}
        What one symbol is.
    order : int
        How many preceding symbols the next one depends on.
    tables : tuple of dict
        ``tables[k]`` maps a context of ``k`` symbols (a tuple) to
        ``(symbols, cumulative_counts)``, for ``k = 0 .. order``: the model
        and every shorter one, used to back off from a context that was
        never followed by anything in the corpus (the end of the text).
    starts : tuple
        The contexts of length ``order`` in corpus order, to start from.
    """

    unit: str
    order: int
    tables: tuple = field(repr=False)
    starts: tuple = field(repr=False)

    @property
    def vocabulary_size(self) -> int:
        """Number of distinct symbols in the corpus."""
        return len(self.tables[0][()][0])


def _tokenise(text: str, unit: str) -> list[str]:
    if unit == "char":
        return list(re.sub(r"\s+", " ", text).strip())
    return text.split()


def train_markov(corpus: str, *, unit: str = "char", order: int = 3) -> MarkovModel:
    """Count the n-grams of a text.

    Parameters
    ----------
    corpus : str
        The training text. For ``unit='char'`` runs of white space (new
        lines included) become one space; for ``unit='word'`` the text is
        split on white space and punctuation stays attached to its word.
    unit : {'char', 'word'}
        Letters (every character) or words.
    order : int
        The number of preceding symbols the next one depends on, 0 to 12.
        Order 0 draws symbols independently with their corpus frequencies
        (Shannon's "first-order approximation"); order ``n`` uses the
        ``(n + 1)``-gram counts (Shannon's "(n+1)-th order"), so ``order=2``
        on letters gives his trigram text "IN NO IST LAT WHEY CRATICT...".

    Returns
    -------
    MarkovModel

    Raises
    ------
    ValueError
        If the corpus has no symbols, or fewer than ``order + 1``.

    References
    ----------
    .. [1] C. E. Shannon, "A mathematical theory of communication", Bell
       System Technical Journal 27, 1948, section 3.
    """
    if not isinstance(corpus, str):
        raise TypeError(f"corpus must be a str, got {type(corpus).__name__}")
    unit = check_choice("unit", unit, _UNITS)
    order = check_int("order", order, minimum=0, maximum=12)
    symbols = _tokenise(corpus, unit)
    if not symbols:
        raise ValueError(f"corpus is empty: no {'characters' if unit == 'char' else 'words'} to learn from")
    if len(symbols) <= order:
        raise ValueError(f"corpus has {len(symbols)} {unit}s, too few for order={order} "
                         f"(needs at least {order + 1})")
    tables = []
    for k in range(order + 1):
        counts: dict[tuple, dict[str, int]] = {}
        for i in range(k, len(symbols)):
            ctx = tuple(symbols[i - k:i])
            nxt = counts.setdefault(ctx, {})
            nxt[symbols[i]] = nxt.get(symbols[i], 0) + 1
        table = {}
        for ctx, nxt in counts.items():
            keys = sorted(nxt)
            table[ctx] = (tuple(keys), np.cumsum([nxt[s] for s in keys]))
        tables.append(table)
    starts = tuple(tuple(symbols[i:i + order]) for i in range(len(symbols) - order))
    return MarkovModel(unit=unit, order=order, tables=tuple(tables), starts=starts)


def generate_text(model: MarkovModel, length: int, *, seed: int | None = 0) -> str:
    """Sample text from a Markov model.

    The first ``order`` symbols are a context drawn at random from the
    corpus; each next symbol is drawn with the frequency it followed the
    current context in the corpus. A context never followed by anything
    (the corpus's last symbols) backs off to the longest shorter context
    that was.

    Parameters
    ----------
    model : MarkovModel
        From :func:`train_markov`.
    length : int
        Number of symbols (characters or words) to produce, >= 0.
    seed : int or None
        Seed of the random generator; the same seed gives the same text.

    Returns
    -------
    str
        Characters joined as they are, words joined by single spaces.
    """
    if not isinstance(model, MarkovModel):
        raise TypeError(f"model must be a MarkovModel, got {type(model).__name__}")
    length = check_int("length", length, minimum=0)
    seed = check_seed("seed", seed)
    rng = np.random.default_rng(seed)
    order = model.order
    out: list[str] = []
    if order > 0:
        out.extend(model.starts[int(rng.integers(len(model.starts)))])
    out = out[:length]
    while len(out) < length:
        for k in range(min(order, len(out)), -1, -1):
            entry = model.tables[k].get(tuple(out[len(out) - k:]))
            if entry is not None:
                break
        keys, cum = entry
        out.append(keys[int(np.searchsorted(cum, rng.integers(cum[-1]), side="right"))])
    return ("" if model.unit == "char" else " ").join(out)


def markov_text(corpus: str, *, unit: str = "char", order: int = 3, length: int = 500,
                seed: int | None = 0) -> str:
    """Train on ``corpus`` and generate ``length`` symbols in one call.

    See :func:`train_markov` and :func:`generate_text` for the parameters.
    """
    return generate_text(train_markov(corpus, unit=unit, order=order), length, seed=seed)
