"""The ``rng`` keyword (issue 18; scikit-image's SPEC 7) of tiles, synthesis and spectral.

Every function takes ``rng`` as an int (the same int gives the same result, the
same as the old ``seed=``), a ``numpy.random.Generator`` (used and advanced) or
None; the old ``seed=`` still works with a ``DeprecationWarning``.
"""

from __future__ import annotations

import numpy as np
import pytest

from spectex import spectral, synthesis
from spectex.tiles import make_seamless, make_tile

_EXEMPLAR = np.random.default_rng(5).random((24, 24, 3)).astype(np.float32)
_PHOTO = np.random.default_rng(6).random((40, 40, 3)).astype(np.float32)
_MODEL = synthesis.train_markov("the cat sat on the mat and the dog sat on the log " * 4, order=2)

CALLS = {
    "make_tile": lambda **kw: make_tile(16, **kw),
    "make_seamless": lambda **kw: make_seamless(_PHOTO, alpha="noise", **kw),
    "efros_leung": lambda **kw: synthesis.efros_leung(_EXEMPLAR, (14, 14), window=5, **kw),
    "sample_histogram": lambda **kw: synthesis.sample_histogram(_EXEMPLAR, (8, 8), **kw),
    "match_histogram": lambda **kw: synthesis.match_histogram(_PHOTO[:24, :24], _EXEMPLAR, joint=True, **kw),
    "quilt": lambda **kw: synthesis.quilt(_EXEMPLAR, (30, 30), block=12, **kw),
    "generate_text": lambda **kw: synthesis.generate_text(_MODEL, 60, **kw),
    "markov_text": lambda **kw: synthesis.markov_text("abcabdabcabe" * 5, order=1, length=40, **kw),
    "spectral_noise": lambda **kw: spectral.spectral_noise(16, **kw),
    "octave_sum": lambda **kw: spectral.octave_sum(16, **kw),
    "octave": lambda **kw: spectral.octave(16, 4, **kw),
}


def _same(a, b):
    if isinstance(a, str):
        return a == b
    return np.array_equal(a, b)


@pytest.mark.parametrize("name", sorted(CALLS))
def test_rng_int_generator_and_the_old_seed(name):
    call = CALLS[name]
    a = call(rng=3)
    assert _same(a, call(rng=3))                         # deterministic
    assert not _same(a, call(rng=4))                     # and the int matters (a control)
    assert _same(a, call(rng=np.random.default_rng(3)))  # a Generator: default_rng(int)'s stream
    with pytest.warns(DeprecationWarning, match=rf"{name}\(seed=\.\.\.\) is deprecated.*rng="):
        old = call(seed=3)
    assert _same(a, old)                                 # the old keyword, the same result
    gen = np.random.default_rng(3)
    first, second = call(rng=gen), call(rng=gen)
    assert _same(first, a) and not _same(second, a)      # a Generator is advanced, not copied


@pytest.mark.parametrize("name", sorted(CALLS))
@pytest.mark.parametrize("bad, error", [(1.5, TypeError), ("7", TypeError), (True, TypeError), (-1, ValueError)])
def test_rng_bad_values_name_the_parameter(name, bad, error):
    with pytest.raises(error, match=r"^rng must be"):
        CALLS[name](rng=bad)


def test_rng_none_draws_fresh_randomness():
    assert not np.array_equal(make_tile(16, rng=None), make_tile(16, rng=None))
