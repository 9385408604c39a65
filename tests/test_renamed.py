"""The keywords renamed by issue 18's vocabulary (``docs/conventions.md``).

``shape=(H, W)`` for an output's pixels (``make_tile``, ``make_seamless``,
the renderers; was ``size``) and ``kernel`` for a magnification kernel
(``spectex.spectral``, ``make_tile``; was ``filter``, which elsewhere means
OpenGL's texture filter). Each old keyword still works for one release: the
same result, with a ``DeprecationWarning`` that names the new keyword; both
names at once are refused, and positional calls are unchanged.
"""

from __future__ import annotations

import numpy as np
import pytest

from spectex import SpectralTexture, spectral
from spectex.render import Camera, render
from spectex.render.cpu import render_cpu
from spectex.tiles import make_seamless, make_tile

_PHOTO = np.random.default_rng(6).random((40, 40, 3)).astype(np.float32)
_SMALL = np.random.default_rng(2).random((4, 5))
_TEXTURE = SpectralTexture.paper_preset(make_tile(16, rng=1))
_CAMERA = Camera((0.0, 0.0, 2.0), yaw=30.0, pitch=-12.0)

# name: (the call, the new keyword, the old one, a value that is not the new keyword's default)
CALLS = {
    "make_tile": (lambda **kw: make_tile(**kw), "shape", "size", 24),
    "make_tile kernel": (lambda **kw: make_tile(32, rng=2, method="octaves", **kw), "kernel", "filter", "tent"),
    "make_seamless": (lambda **kw: make_seamless(_PHOTO, **kw), "shape", "size", (16, 24)),
    "magnify": (lambda **kw: spectral.magnify(_SMALL, 3, **kw), "kernel", "filter", "catmull-rom"),
    "octave": (lambda **kw: spectral.octave(16, 4, rng=0, **kw), "kernel", "filter", "tent"),
    "octave_sum": (lambda **kw: spectral.octave_sum(16, rng=0, **kw), "kernel", "filter", "box"),
    "filter_passes": (lambda **kw: spectral.filter_passes(**kw), "kernel", "filter", "tent"),
    "discrete_filter": (lambda **kw: spectral.discrete_filter(factor=3, **kw)[0], "kernel", "filter", "tent"),
    "render_cpu": (lambda **kw: render_cpu(_TEXTURE, _CAMERA, anisotropy=1, **kw), "shape", "size", (12, 16)),
    "render": (lambda **kw: render(_TEXTURE, _CAMERA, backend="cpu", anisotropy=1, **kw).image, "shape", "size",
               (12, 16)),
}


@pytest.mark.parametrize("name", sorted(CALLS))
def test_the_old_keyword_gives_the_same_result_with_a_warning(name):
    call, new, old, value = CALLS[name]
    where = name.split()[0]
    want = call(**{new: value})
    with pytest.warns(DeprecationWarning, match=rf"{where}\({old}=\.\.\.\) is deprecated.*{where}\({new}=\.\.\.\)"):
        got = call(**{old: value})
    np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("name", sorted(CALLS))
def test_both_names_at_once_are_refused(name):
    call, new, old, value = CALLS[name]
    other = "gaussian" if new == "kernel" else (8, 8)  # not the new keyword's default either
    with pytest.raises(TypeError, match=rf"both {new}= and its deprecated old name {old}="):
        call(**{new: other, old: value})


def test_the_value_is_checked_under_the_new_name():
    with pytest.raises(ValueError, match="^shape must be between 8"):
        make_tile(4)
    with pytest.raises(ValueError, match="^kernel must be one of"):
        spectral.magnify(_SMALL, 2, kernel="lanczos")
    with pytest.raises(ValueError, match="^shape must be at least 8x8"):
        make_seamless(_PHOTO, shape=4)
    with pytest.raises(ValueError, match="^shape .* over the budget"):
        render_cpu(_TEXTURE, _CAMERA, (1080, 1920), supersample=8)


def test_positional_calls_are_unchanged():
    np.testing.assert_array_equal(make_tile(16, rng=3), make_tile(shape=16, rng=3))
    np.testing.assert_array_equal(render_cpu(_TEXTURE, _CAMERA, (6, 8), anisotropy=1),
                                  render_cpu(_TEXTURE, _CAMERA, shape=(6, 8), anisotropy=1))
    assert spectral.filter_passes("tent") == 2
    taps, start = spectral.discrete_filter("box", 2)
    assert taps.tolist() == [1.0, 1.0] and start == 0  # a box: each input texel covers its own two
    # The control: a different kernel gives a different octave.
    assert not np.array_equal(spectral.octave(16, 4, rng=0), spectral.octave(16, 4, rng=0, kernel="tent"))


def test_a_missing_shape_is_a_type_error():
    with pytest.raises(TypeError, match="missing 1 required argument: 'shape'"):
        render(_TEXTURE, _CAMERA, backend="cpu")
    with pytest.raises(TypeError, match="missing 1 required argument: 'shape'"):
        render_cpu(_TEXTURE, _CAMERA)
    with pytest.raises(TypeError, match="missing required argument: 'factor'"):
        spectral.discrete_filter("tent")


@pytest.mark.gl
def test_gl_renderer_and_magnify_gl_take_the_old_keywords(gl):
    from spectex.render.gl import GLRenderer

    with GLRenderer(_TEXTURE, ctx=gl) as r:
        want = r.render(_CAMERA, (12, 16))
        with pytest.warns(DeprecationWarning, match=r"GLRenderer\.render\(size=\.\.\.\) is deprecated"):
            got = r.render(_CAMERA, size=(12, 16))
        np.testing.assert_array_equal(got, want)
        with pytest.warns(DeprecationWarning, match=r"GLRenderer\.time_frames\(size=\.\.\.\) is deprecated"):
            assert r.time_frames(_CAMERA, size=(12, 16), frames=1) > 0.0
    want = spectral.magnify_gl(_SMALL, 3, kernel="tent", ctx=gl).image
    with pytest.warns(DeprecationWarning, match=r"magnify_gl\(filter=\.\.\.\) is deprecated.*kernel="):
        got = spectral.magnify_gl(_SMALL, 3, filter="tent", ctx=gl).image
    np.testing.assert_array_equal(got, want)
