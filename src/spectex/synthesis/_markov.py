"""Markov models of text: printed English as a 1-D texture (Shannon 1948)."""

from __future__ import annotations

import bisect
import itertools
import re
from collections import Counter
from dataclasses import dataclass, field

from .._limits import MAX_TEXT_LENGTH
from .._validate import check_choice, check_int, check_rng

_UNITS = ("char", "word")


class _NgramTable:
    """Sorted (k+1)-grams and their counts; continuations of a context on demand.

    ``get(ctx)`` returns ``(symbols, cumulative_counts)`` for the k-symbol
    context ``ctx`` (symbols sorted), or None if the corpus never continues
    it. The grams starting with ``ctx`` are one run of the sorted list: from
    ``ctx`` itself (a prefix sorts first) to ``ctx[:-1] + (ctx[-1] + NUL,)``
    (nothing sorts between a string and itself followed by NUL). Answers are
    cached, so building the model costs one sort, not one object per context.
    """

    __slots__ = ("keys", "counts", "cache")

    def __init__(self, keys, counts):
        self.keys = keys
        self.counts = counts
        self.cache = {}

    def get(self, ctx):
        hit = self.cache.get(ctx, False)
        if hit is not False:
            return hit
        if ctx:
            lo = bisect.bisect_left(self.keys, ctx)
            hi = bisect.bisect_left(self.keys, ctx[:-1] + (ctx[-1] + "\x00",), lo)
        else:
            lo, hi = 0, len(self.keys)
        entry = None
        if lo < hi:
            entry = (tuple(g[-1] for g in self.keys[lo:hi]), list(itertools.accumulate(self.counts[lo:hi])))
        self.cache[ctx] = entry
        return entry

    def __len__(self):
        return len(self.keys)


@dataclass(frozen=True)
class MarkovModel:
    """An n-gram model of text, as trained by :func:`train_markov`.

    Attributes
    ----------
    unit : {'char', 'word'}
        What one symbol is.
    order : int
        How many preceding symbols the next one depends on.
    tables : tuple
        ``tables[k].get(context)`` gives, for a context of ``k`` symbols (a
        tuple), ``(symbols, cumulative_counts)`` (a tuple and a list,
        symbols sorted) or None, for ``k = 0 .. order``: the model and every
        shorter one, used to back off from a context that was never followed
        by anything in the corpus (the end of the text). ``len(tables[k])``
        is the number of distinct ``(k + 1)``-grams.
    symbols : tuple of str
        The corpus as symbols, where generation takes its first context.
    """

    unit: str
    order: int
    tables: tuple = field(repr=False)
    symbols: tuple = field(repr=False)

    @property
    def vocabulary_size(self) -> int:
        """Number of distinct symbols in the corpus."""
        return len(self.tables[0].get(())[0])


def _tokenise(text: str, unit: str) -> list[str]:
    if unit == "char":
        return list(re.sub(r"\s+", " ", text).strip())
    return text.split()


def train_markov(corpus: str, *, unit: str = "char", order: int = 3, progress=None) -> MarkovModel:
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
    progress : callable, optional
        Called as ``progress(done, total)`` after each n-gram table.

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
    n = len(symbols)
    tables = []
    for k in range(order + 1):
        # every (k+1)-gram, counted and sorted at C speed
        grams = Counter(zip(*(symbols[i:n - k + i] for i in range(k + 1))))
        keys = sorted(grams)
        tables.append(_NgramTable(keys, [grams[g] for g in keys]))
        if progress is not None:
            progress(k + 1, order + 1)
    return MarkovModel(unit=unit, order=order, tables=tuple(tables), symbols=tuple(symbols))


def generate_text(model: MarkovModel, length: int, *, rng=0, progress=None) -> str:
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
        Number of symbols (characters or words) to produce, 0 to
        ``MAX_TEXT_LENGTH`` (10 million: about 10 s and a few hundred MB).
    rng : int, numpy.random.Generator or None
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.
    progress : callable, optional
        Called as ``progress(done, total)`` every 10000 symbols.

    Returns
    -------
    str
        Characters joined as they are, words joined by single spaces.
    """
    if not isinstance(model, MarkovModel):
        raise TypeError(f"model must be a MarkovModel, got {type(model).__name__}")
    length = check_int("length", length, minimum=0, maximum=MAX_TEXT_LENGTH)
    rng = check_rng(rng)
    order = model.order
    out: list[str] = []
    if order > 0:
        start = int(rng.integers(len(model.symbols) - order + 1))
        out.extend(model.symbols[start:start + order])
    out = out[:length]
    # uniform draws in batches (one per symbol)
    draws = rng.random(max(length - len(out), 0))
    for t in range(len(draws)):
        for k in range(min(order, len(out)), -1, -1):
            entry = model.tables[k].get(tuple(out[len(out) - k:]))
            if entry is not None:
                break
        keys, cum = entry
        out.append(keys[bisect.bisect_right(cum, int(draws[t] * cum[-1]))])
        if progress is not None and (t + 1) % 10000 == 0:
            progress(t + 1, len(draws))
    return ("" if model.unit == "char" else " ").join(out)


def markov_text(corpus: str, *, unit: str = "char", order: int = 3, length: int = 500,
                rng=0, progress=None) -> str:
    """Train on ``corpus`` and generate ``length`` symbols in one call.

    See :func:`train_markov` and :func:`generate_text` for the parameters;
    ``progress`` counts the training tables, then the generated symbols.
    """
    rng = check_rng(rng)  # before the training, which takes time
    model = train_markov(corpus, unit=unit, order=order, progress=progress)
    return generate_text(model, length, rng=rng, progress=progress)
