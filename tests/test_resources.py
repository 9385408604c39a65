"""Derived data of a texture (``spectex.shading.resources``): made from the tiles, cached by
content outside the texture, the same arrays for every texture with the same texels."""

import gc
import threading

import numpy as np
import pytest

from spectex.render import bake
from spectex.shading import pack, resources
from spectex.shading.resources import (
    clear_cache,
    mean_colours,
    mip_levels,
    stochastic_store,
    stochastic_tables,
    texel_store,
    tile_digest,
)
from spectex.texture import Layer, SpectralTexture


def _tile(seed, n=16):
    return np.random.default_rng(seed).random((n, n, 4)).astype(np.float32)


def _texture(seed=0, *, bits=8, tiling="stochastic"):
    return SpectralTexture(_tile(seed), [Layer(size=1.0, tiling=tiling), Layer(size=5.0, blend="variance")],
                           bits=bits)


def test_the_texture_holds_its_plain_data_only():
    tex = _texture(1)
    before = dict(vars(tex))
    assert set(before) == {"tiles", "layers", "bits"}
    bake(tex, (8, 8), pixel_size=0.1)
    pack(tex)
    stochastic_store(tex)
    mean_colours(tex)
    assert vars(tex).keys() == before.keys()  # nothing derived was stored on it
    assert all(vars(tex)[k] is before[k] for k in before)


def test_textures_with_the_same_texels_share_their_resources():
    a, b = _texture(2), _texture(2)  # equal content, different arrays
    assert a.tiles[0] is not b.tiles[0]
    assert texel_store(a).data is texel_store(b).data
    assert mip_levels(a)[0][0] is mip_levels(b)[0][0]
    assert stochastic_tables(a)[0] is stochastic_tables(b)[0]
    assert stochastic_store(a).lut is stochastic_store(b).lut
    # the control: other texels or other bits are other entries
    c = _texture(3)
    assert texel_store(c).data is not texel_store(a).data
    assert not np.array_equal(texel_store(c).data, texel_store(a).data)
    d = _texture(2, bits=None)
    assert texel_store(d).data is not texel_store(a).data
    assert not np.array_equal(texel_store(d).data, texel_store(a).data)  # float texels are not rounded


def test_the_resources_are_what_the_tiles_give():
    tex = _texture(4)
    levels = mip_levels(tex)[0]
    assert [lv.shape[:2] for lv in levels] == [(16, 16), (8, 8), (4, 4), (2, 2), (1, 1)]
    np.testing.assert_array_equal(levels[0], tex.tiles[0])  # level 0 is the (quantised) tile itself
    box = tex.tiles[0].astype(np.float64)[:2, :2].mean(axis=(0, 1))  # level 1: 2 x 2 means, rounded to 8 bits
    np.testing.assert_allclose(levels[1][0, 0], np.floor(box * 255 + 0.5) / 255, atol=1e-6)
    assert np.all(np.abs(levels[1] * 255 - np.round(levels[1] * 255)) < 1e-4)
    np.testing.assert_array_equal(mean_colours(tex), levels[-1][0, 0, :3][None].astype(np.float64))
    store = stochastic_store(tex)
    tables = stochastic_tables(tex)[0]
    np.testing.assert_array_equal(store.gauss[:16 * 16].reshape(16, 16, 4), tables.gaussian[0])
    np.testing.assert_array_equal(store.lut, tables.expanded().astype(np.float32))
    assert store.lut_rows == tables.expanded().shape[0]


def test_a_tile_no_stochastic_layer_draws_gets_no_tables_and_renders_the_same(monkeypatch):
    """Two tiles, the first drawn stochastically, the second by a periodic overlay layer only (a fit's coarse
    tile): the second's tables are zeros in the shapes of the first's (nothing ranked), and a render is the
    same to the bit as with tables built for every tile (the control, the rule before), on the CPU."""
    from spectex.render import Camera
    from spectex.render.cpu import render_cpu
    from spectex.shading import stochastic

    tex = SpectralTexture([_tile(11, 32), _tile(12, 32)],
                          [Layer(size=1.0, tiling="stochastic"), Layer(size=5.0, tile=1, blend="overlay", opacity=0.4)])
    clear_cache()
    used, unused = stochastic_tables(tex)
    assert [g.shape for g in unused.gaussian] == [g.shape for g in used.gaussian]
    assert unused.lut.shape == used.lut.shape and not np.any(unused.lut)
    assert not any(np.any(g) for g in unused.gaussian) and any(np.any(g) for g in used.gaussian)
    cam = Camera((0.3, -0.2, 1.2), yaw=30.0, pitch=-40.0, fov=60.0)
    now = render_cpu(tex, cam, (40, 56))
    clear_cache()
    monkeypatch.setattr(stochastic, "unused_tables", lambda tile: stochastic.stochastic_tables(tile))
    built = stochastic_tables(tex)[1]
    assert np.any(built.lut)
    np.testing.assert_array_equal(render_cpu(tex, cam, (40, 56)), now)
    clear_cache()


def test_clear_cache_rebuilds_the_same_numbers():
    tex = _texture(5)
    first = texel_store(tex)
    assert texel_store(tex) is first
    clear_cache()
    again = texel_store(tex)
    assert again is not first
    np.testing.assert_array_equal(again.data, first.data)


def test_the_cache_is_bounded_and_forgets_dropped_tiles():
    clear_cache()
    for seed in range(3 * resources.KEPT):
        texel_store(_texture(100 + seed, tiling="periodic"))
    assert len(resources._CACHE) == resources.KEPT
    tile = _tile(7)
    tile_digest(tile)
    key = id(tile)
    assert key in resources._DIGESTS
    del tile
    gc.collect()
    assert key not in resources._DIGESTS


def test_the_digest_sees_every_texel_and_the_shape():
    tile = _tile(8)
    other = tile.copy()
    other[15, 15, 3] = np.nextafter(other[15, 15, 3], np.float32(2))
    assert tile_digest(tile) == tile_digest(tile.copy())
    assert tile_digest(other) != tile_digest(tile)
    assert tile_digest(tile.reshape(8, 32, 4)) != tile_digest(tile)


def test_threads_get_one_set_of_resources():
    clear_cache()
    tex = _texture(9)
    got = []

    def work():
        got.append(stochastic_store(tex))

    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(got) == 4 and all(g is got[0] for g in got)


@pytest.mark.parametrize("name", ["mip_levels", "texel_store", "stochastic_tables", "stochastic_store",
                                  "mean_colours", "anchor_coords", "bake", "bake_layers"])
def test_the_texture_has_no_derived_methods(name):
    assert not hasattr(SpectralTexture, name)
