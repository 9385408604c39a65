"""A flat frame around a photo (a border, letterboxing, a rotated photo's wedges) is left out of the fit
(spectex/fitting/_frame.py): left in, every patch of the texture repeats it as a bar."""

import numpy as np
import pytest
import skimage.data
from scipy import ndimage

from helpers import floor_photo, run_fails
from spectex.fitting import _frame, fit_result, prepare_exemplar
from spectex.fitting._frame import frame_box
from spectex.render import bake


def _photo(side=200, seed=3):
    """Smooth colour noise, nowhere flat."""
    rng = np.random.default_rng(seed)
    img = ndimage.gaussian_filter(rng.random((side, side, 3)), (2.0, 2.0, 0.0))
    return (img - img.min()) / (img.max() - img.min())


def _check_box(framed, frame, content_share):
    """``frame_box`` of ``framed`` leaves out every pixel of ``frame`` (bool) and keeps at least
    ``content_share`` of the rest."""
    box = frame_box(framed)
    assert box is not None
    y0, y1, x0, x1 = box
    assert not frame[y0:y1, x0:x1].any(), box
    assert (y1 - y0) * (x1 - x0) >= content_share * (~frame).sum(), box
    return box


def test_frame_box_finds_borders_letterboxes_bars_and_rotation_wedges():
    photo = _photo()
    h, w = photo.shape[:2]
    yy, xx = np.mgrid[0:h, 0:w]
    cases = {
        "black border": (yy < 4) | (yy >= h - 4) | (xx < 4) | (xx >= w - 4),
        "white letterbox": (yy < 30) | (yy >= h - 30),
        "green bar on one side": xx < 9,
    }
    colours = {"black border": 0.0, "white letterbox": 1.0, "green bar on one side": (0.2, 0.6, 0.3)}
    for name, frame in cases.items():
        framed = photo.copy()
        framed[frame] = colours[name]
        box = _check_box(framed, frame, 0.9)
        # no more than the frame and its margin cropped on the sides it touched, nothing on the others
        assert box[0] <= (4 if name == "black border" else 30 if name == "white letterbox" else 0) + 3, (name, box)
    # a frame saved as JPEG: exact away from the photo, ringing near it; both go
    import io

    from PIL import Image

    thick = (yy < 24) | (yy >= h - 24) | (xx < 24) | (xx >= w - 24)
    framed = (255 * photo).astype(np.uint8)
    framed[thick] = 0
    buffer = io.BytesIO()
    Image.fromarray(framed).save(buffer, "JPEG", quality=85)
    jpeg = np.asarray(Image.open(io.BytesIO(buffer.getvalue()))) / 255.0
    _check_box(jpeg, thick, 0.9)
    # a thin frame saved as JPEG is nowhere exact (its chroma blocks reach into the photo): found as a
    # band of uniform lines standing out from the photo
    gravel = np.repeat(skimage.data.gravel()[:300, :300, None], 3, axis=2)
    thin = np.zeros((300, 300), dtype=bool)
    thin[:5], thin[-5:], thin[:, :5], thin[:, -5:] = True, True, True, True
    gravel[thin] = 0
    buffer = io.BytesIO()
    Image.fromarray(gravel).save(buffer, "JPEG", quality=75)
    _check_box(np.asarray(Image.open(io.BytesIO(buffer.getvalue()))) / 255.0, thin, 0.9)
    # the wedges a rotation by 7 degrees leaves in a square: the inscribed square is 1 / (cos + sin) of the side
    big = _photo(260)
    rotated = ndimage.rotate(big, 7.0, axes=(0, 1), reshape=False, order=1, cval=0.0)
    wedge = ndimage.rotate(np.ones(big.shape[:2]), 7.0, reshape=False, order=1, cval=0.0) < 1.0 - 1e-6
    y0, y1, x0, x1 = _check_box(rotated, wedge, 0.0)
    inscribed = 260 / (np.cos(np.radians(7.0)) + np.sin(np.radians(7.0)))
    assert min(y1 - y0, x1 - x0) >= inscribed - 10, (y0, y1, x0, x1, inscribed)


@pytest.mark.parametrize("name", ["brick", "grass", "gravel", "moon", "camera", "coins", "floor"])
def test_frame_box_leaves_photos_without_a_frame_alone(name):
    """Photos whose flat parts are not a frame: a tiled floor's grout (one colour, but a network through
    the middle), scikit-image's textures and photos (the camera man's flat sky, the coins' background)."""
    photo = floor_photo(256)[0] if name == "floor" else getattr(skimage.data, name)()
    img = photo.astype(np.float64) / (255.0 if photo.dtype == np.uint8 else 1.0)
    if img.ndim == 2:
        img = np.repeat(img[:, :, None], 3, axis=2)
    assert frame_box(img) is None


def test_frame_box_leaves_stripes_and_joint_lines_alone():
    """A line of one colour along the edge that the photo shows again inside is its own: horizontal
    stripes (exact; taken for a frame without that test), planks with a joint along the top edge (a
    band; taken for one without that test)."""
    rows = np.where((np.arange(256) // 16) % 2 == 0, 0.2, 0.8)
    stripes = np.repeat(np.repeat(rows[:, None], 256, axis=1)[:, :, None], 3, axis=2)
    assert frame_box(stripes) is None
    assert frame_box(_planks()) is None


def _planks(side=256, row=32, seed=5):
    """Boards of random lengths and browns with grain, rows ``row`` pixels high, a dark 2-pixel joint
    between rows (one along the top edge) and between boards."""
    rng = np.random.default_rng(seed)
    img = np.empty((side, side, 3))
    for y0 in range(0, side, row):
        x = -int(rng.integers(0, 80))
        while x < side:
            length = int(rng.integers(60, 140))
            brown = np.array([0.55, 0.35, 0.22]) * rng.uniform(0.8, 1.2)
            a, b = max(x, 0), min(x + length, side)
            img[y0:y0 + row, a:b] = brown
            if a > 0:
                img[y0:y0 + row, a - 1:a + 1] = (0.19, 0.12, 0.08)
            x += length
        img[y0:y0 + 2] = (0.19, 0.12, 0.08)
    img += 0.03 * ndimage.gaussian_filter(rng.standard_normal((side, side, 1)), (0.6, 6.0, 0))
    return np.clip(img, 0.0, 1.0)


def _bars(image):
    """Share of pixels darker than 3/255 in every channel (the photo's darkest is 4/255)."""
    return float(np.mean(np.all(image[:, :, :3] < 3.0 / 255.0, axis=-1)))


@pytest.mark.slow
def test_fit_of_a_framed_photo_shows_no_bars(monkeypatch):
    """A 256-pixel gravel photo with a 4-pixel black border: the fit leaves the border out (said in its
    notes) and its bake has no more black pixels than the photo (none). The control: the same fit with
    the frame left in (``frame_box`` finding none) puts black bars across the bake, one per patch (0.5%
    of its pixels black, against none)."""
    photo = skimage.data.gravel()[:256, :256].astype(np.float64) / 255.0
    framed = photo.copy()
    framed[:4], framed[-4:], framed[:, :4], framed[:, -4:] = 0.0, 0.0, 0.0, 0.0
    result = fit_result(framed, pixel_size=1.0)
    assert any("flat frame" in note for note in result.notes), result.notes
    assert 240 <= min(result.exemplar.shape[:2]) <= 248
    own = _bars(np.repeat(photo[:, :, None], 3, axis=2))
    assert own == 0.0 and _bars(np.repeat(framed[:, :, None], 3, axis=2)) > 0.05
    fine = bake(result.texture, (512, 512), pixel_size=1.0)
    assert _bars(fine) <= own + 1e-4
    monkeypatch.setattr(_frame, "frame_box", lambda rgb: None)
    kept = fit_result(framed, pixel_size=1.0)
    assert not any("flat frame" in note for note in kept.notes)
    assert _bars(bake(kept.texture, (512, 512), pixel_size=1.0)) > 0.002


def test_a_photo_that_is_mostly_frame_is_refused():
    photo = np.zeros((200, 200, 3))
    photo[90:110, 90:110] = _photo(20)
    with pytest.raises(ValueError, match=r"^image is mostly a flat frame: without it 16x16 pixels"):
        prepare_exemplar(photo)


def test_cli_refuses_a_photo_that_is_mostly_frame(tmp_path, capsys):
    from PIL import Image

    photo = np.zeros((200, 200, 3), dtype=np.uint8)
    photo[90:110, 90:110] = (255 * _photo(20)).astype(np.uint8)
    path = tmp_path / "framed.png"
    Image.fromarray(photo).save(path)
    line = run_fails(["fit", str(path), "-o", str(tmp_path / "out")], capsys, tmp_path / "out")
    assert "mostly a flat frame" in line
