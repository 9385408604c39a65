"""Markov text: n-gram statistics, backing off, determinism, bad corpora."""

import collections

import pytest

from spectex.synthesis import generate_text, markov_text, train_markov

CORPUS = (
    "I know that I shall meet my fate somewhere among the clouds above; those that I fight "
    "I do not hate, those that I guard I do not love; my country is Kiltartan Cross, my "
    "countrymen Kiltartan's poor, no likely end could bring them loss or leave them happier "
    "than before. Nor law, nor duty bade me fight, nor public men, nor cheering crowds, a "
    "lonely impulse of delight drove to this tumult in the clouds; I balanced all, brought all "
    "to mind, the years to come seemed waste of breath, a waste of breath the years behind in "
    "balance with this life, this death."
)


def _ngrams(seq, n):
    return {tuple(seq[i:i + n]) for i in range(len(seq) - n + 1)}


@pytest.mark.parametrize("order", [1, 2, 3, 5])
def test_char_ngrams_all_come_from_the_corpus(order):
    text = markov_text(CORPUS + " " + CORPUS, unit="char", order=order, length=400, rng=order)
    assert len(text) == 400
    assert _ngrams(text, order + 1) <= _ngrams(CORPUS + " " + CORPUS, order + 1)


def test_order_zero_follows_the_letter_frequencies():
    text = markov_text(CORPUS, unit="char", order=0, length=20000, rng=0)
    want = collections.Counter(CORPUS)
    got = collections.Counter(text)
    for ch in "e ta":
        assert got[ch] / len(text) == pytest.approx(want[ch] / len(CORPUS), abs=0.01)
    # no context: bigrams the corpus never has appear
    assert not _ngrams(text, 2) <= _ngrams(CORPUS, 2)


def test_words_and_higher_orders_look_more_like_english():
    words = set(CORPUS.split())
    for order in (0, 2):
        out = markov_text(CORPUS, unit="word", order=order, length=60, rng=1).split()
        assert len(out) == 60 and set(out) <= words
    bigrams = _ngrams(CORPUS.split() * 2, 2)
    text = markov_text(CORPUS + " " + CORPUS, unit="word", order=1, length=80, rng=2)
    assert _ngrams(text.split(), 2) <= bigrams
    # letters: order 3 gives mostly real words, order 0 hardly any
    def real(t):
        return sum(w in words for w in t.split()) / max(1, len(t.split()))

    order3 = markov_text(CORPUS, order=3, length=2000, rng=3)
    order0 = markov_text(CORPUS, order=0, length=2000, rng=3)
    assert real(order3) > 3 * real(order0)


def test_back_off_at_the_end_of_the_corpus():
    model = train_markov("abcd", unit="char", order=2)
    text = generate_text(model, 30, rng=0)
    assert len(text) == 30 and set(text) <= set("abcd")


def test_same_seed_same_text():
    model = train_markov(CORPUS, unit="word", order=1)
    assert generate_text(model, 50, rng=9) == generate_text(model, 50, rng=9)
    assert generate_text(model, 50, rng=9) != generate_text(model, 50, rng=10)
    assert generate_text(model, 0, rng=9) == ""


@pytest.mark.parametrize("corpus, kwargs, message", [
    ("", {}, "corpus is empty"),
    ("  \n\t ", {"unit": "word"}, "corpus is empty: no words"),
    ("ab", {"order": 3}, "corpus has 2 chars, too few for order=3"),
    ("abc", {"order": 13}, "order must be <= 12, got 13"),
    ("abc", {"unit": "line"}, "unit must be one of 'char', 'word', got 'line'"),
])
def test_bad_corpora_and_arguments(corpus, kwargs, message):
    with pytest.raises(ValueError, match=message):
        train_markov(corpus, **kwargs)
