"""Helpers shared by the tests, imported as ``from helpers import ...``.

``tests/`` is on the import path through pytest's ``pythonpath`` setting
(pyproject.toml); fixtures stay in ``conftest.py``.
"""

from __future__ import annotations

import os
import shutil

import numpy as np
import pytest

from spectex.render import Camera

#: The renderers' test picture, (H, W).
SIZE = (180, 320)

#: The renderers' test views: from a close-up to straight down from 2.5 km.
VIEWS = {
    "close": Camera((3.0, 4.0, 1.5), yaw=20.0, pitch=-50.0),
    "ground": Camera((0.0, 0.0, 2.0), yaw=30.0, pitch=-12.0),
    "grazing": Camera((50.0, -20.0, 1.7), yaw=100.0, pitch=-3.0),
    "aerial": Camera((0.0, 0.0, 400.0), yaw=10.0, pitch=-35.0),
    "high": Camera((100.0, 300.0, 2500.0), yaw=10.0, pitch=-90.0),
}


def make_test_tile(n=256, seed=0, *, cutoff=0.25, beta=1.5):
    """A seamless, full-contrast RGBA tile: FFT-filtered noise, each channel
    stretched to [0, 1]; alpha is an emboss (wrap-around directional
    difference) of the luminance, like the paper's."""
    rng = np.random.default_rng(seed)
    f = np.fft.fftfreq(n)
    r = np.hypot(f[:, None], f[None, :])
    r[0, 0] = 1.0
    amp = r ** -beta * (r < cutoff * 0.5)
    amp[0, 0] = 0.0

    def field():
        x = np.real(np.fft.ifft2(np.fft.fft2(rng.standard_normal((n, n))) * amp))
        return (x - x.min()) / (x.max() - x.min())

    lum = field()
    hue = field()
    col = np.stack([lum, 0.7 * lum + 0.3 * hue, 0.5 * lum + 0.5 * (1 - hue)], axis=-1)
    col = (col - col.min(axis=(0, 1))) / (col.max(axis=(0, 1)) - col.min(axis=(0, 1)))
    emb = (np.roll(lum, 1, 1) - np.roll(lum, -1, 1)) + (np.roll(lum, 1, 0) - np.roll(lum, -1, 0))
    alpha = np.clip(0.5 + emb / (4.0 * emb.std()), 0.0, 1.0)
    return np.concatenate([col, alpha[..., None]], axis=-1).astype(np.float32)


def psnr(image, reference) -> float:
    """Peak signal-to-noise ratio of ``image`` against ``reference`` (values in [0, 1]), dB; inf if equal."""
    mse = float(np.mean((np.asarray(image, np.float64) - np.asarray(reference, np.float64)) ** 2))
    return float("inf") if mse == 0 else 10.0 * np.log10(1.0 / mse)


def error_line(capsys) -> str:
    """The one line a refused command wrote on standard error."""
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def run_fails(argv, capsys, *outputs) -> str:
    """``spectex argv`` is refused: exit status 2 (argparse's own errors included), one line on
    standard error that says so, none of ``outputs`` written. Returns the line."""
    from spectex.cli import main

    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    assert len(err) == 1 and "error" in err[0], err
    for path in outputs:
        assert not path.exists(), f"{path} was written"
    return err[0]


def glslang_validator() -> str:
    """Path of Debian's ``glslangValidator`` (glslang-tools): a skip without it, a failure under CI=true."""
    path = shutil.which("glslangValidator")
    if path is None:
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail("glslangValidator is missing: CI must have it (apt-get install glslang-tools)")
        pytest.skip("glslangValidator is missing (apt-get install glslang-tools)")
    return path
