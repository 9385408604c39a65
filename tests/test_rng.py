"""The ``rng`` keyword (issue 18; scikit-image's SPEC 7) of tiles, synthesis, spectral, fit and the preset.

Every function takes ``rng`` as an int (the same int gives the same result, the
a ``numpy.random.Generator`` (used and advanced) or None.
"""

from __future__ import annotations

import numpy as np
import pytest
from skimage import data

from spectex import SpectralTexture, fit, fit_result, spectral, synthesis
from spectex.tiles import make_seamless, make_tile

_EXEMPLAR = np.random.default_rng(5).random((24, 24, 3)).astype(np.float32)
_PHOTO = np.random.default_rng(6).random((40, 40, 3)).astype(np.float32)
# Gravel, 48 x 48: a fit with a 64-texel tile quilts it (the fit's only randomness).
_GRAVEL = np.repeat((data.gravel()[:48, :48].astype(np.float32) / 255.0)[..., None], 3, axis=2)
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
    "fit": lambda **kw: fit(_GRAVEL, iterations=1, tile_size=64, **kw),
    "fit_result": lambda **kw: fit_result(_GRAVEL, iterations=1, tile_size=64, **kw).texture,
    "paper_preset": lambda **kw: SpectralTexture.paper_preset(tile_size=32, **kw),
}


def _same(a, b):
    if isinstance(a, (str, SpectralTexture)):
        return a == b
    return np.array_equal(a, b)


@pytest.mark.parametrize("name", sorted(CALLS))
def test_rng_int_and_generator(name):
    call = CALLS[name]
    a = call(rng=3)
    assert _same(a, call(rng=3))                         # deterministic
    assert not _same(a, call(rng=4))                     # and the int matters (a control)
    assert _same(a, call(rng=np.random.default_rng(3)))  # a Generator: default_rng(int)'s stream
    with pytest.raises(TypeError, match="seed"):
        call(seed=3)                                     # one name for randomness: rng
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


# Made on main before fit and paper_preset took rng (with seed=7 and seed=3): the
# sum of the 8-bit tile's values and one texel. The same ints give the same textures.
# The fit's numbers are the legacy method's since issue 22 sharpened the stochastic
# blend weights (its stochastic bakes changed: 8272.588508859277 before), and 8227.353214174509
# before the blend was kept between its sources (stochastic.keep_between).
@pytest.mark.parametrize("call, reference", [
    (lambda: SpectralTexture.paper_preset(rng=7, tile_size=32),
     (1709.003969155252, [0.4627451002597809, 0.47058823704719543, 0.3450980484485626, 0.4000000059604645])),
    (lambda: fit(_GRAVEL, rng=3, iterations=1, tile_size=64, method="legacy"),
     (8223.659095719457, [0.5490196347236633, 0.5490196347236633, 0.5490196347236633, 0.501960813999176])),
], ids=["paper_preset", "fit"])
def test_the_same_int_gives_the_texture_of_the_old_seed(call, reference):
    tile = call().tiles[0]
    total, texel = reference
    assert float(tile.astype(np.float64).sum()) == pytest.approx(total, rel=1e-12)
    assert tile[3, 5].tolist() == texel


def test_fit_layers_keep_their_hash_seeds():
    # Layer(seed=) is a stochastic layer's hash key, stored in files: not an rng, and not renamed.
    layers = SpectralTexture.paper_preset(rng=np.random.default_rng(1), tile_size=16, tiling="stochastic").layers
    assert [layer.seed for layer in layers] == [0, 1, 2, 3, 4, 5]
