"""Pictures for reports: labelled montages and the plots of a fit.

What ``spectex compare`` and ``spectex fit`` write besides their numbers,
as library functions, so that a script makes the same pictures as the
command line. Images are float arrays in [0, 1], ``(H, W)`` or
``(H, W, C)``; the plots are written with Matplotlib's Agg backend (no
display needed).
"""

from __future__ import annotations

import numpy as np

from ._validate import check_image, check_int

__all__ = ["montage", "plot_band_power", "plot_histograms"]

#: Height of the label strip above each image of a montage, pixels.
LABEL_HEIGHT = 18


def _rgb(image: np.ndarray) -> np.ndarray:
    if image.ndim == 2:
        return np.repeat(image[:, :, None], 3, axis=2)
    c = image.shape[2]
    if c in (1, 2):
        return np.repeat(image[:, :, :1], 3, axis=2)
    return image[:, :, :3]


def _label_strip(text: str, width: int, height: int, background: float) -> np.ndarray:
    """``text`` in black (on a light background) or white, left-aligned, clipped to ``width``."""
    from PIL import Image, ImageDraw, ImageFont

    grey = int(round(255 * background))
    strip = Image.new("L", (width, height), grey)
    font = ImageFont.load_default()
    box = ImageDraw.Draw(strip).textbbox((0, 0), text, font=font)
    y = (height - (box[3] - box[1])) // 2 - box[1]
    ImageDraw.Draw(strip).text((3 - box[0], y), text, fill=0 if background >= 0.5 else 255, font=font)
    return np.repeat((np.asarray(strip, dtype=np.float32) / 255.0)[:, :, None], 3, axis=2)


def montage(images, labels=None, *, gap: int = 8, background: float = 0.5) -> np.ndarray:
    """Images side by side, each with its label above it.

    Parameters
    ----------
    images : sequence of ndarray, shape (H, W) or (H, W, C)
        Grey images are shown as grey RGB, an alpha channel is dropped.
    labels : sequence of str, optional
        One per image, drawn in a strip of ``LABEL_HEIGHT`` pixels above it
        (cut at the image's width); ``None``: no strip.
    gap : int
        Pixels between the images (>= 0).
    background : float
        Grey level of the canvas and the label strips, in [0, 1].

    Returns
    -------
    ndarray, shape (LABEL_HEIGHT + max H, sum W + gaps, 3), float32
        The images top-aligned (the label strip only with ``labels``).
    """
    images = [_rgb(check_image(f"images[{k}]", img)) for k, img in enumerate(images)]
    if not images:
        raise ValueError("images must hold at least one image, got none")
    gap = check_int("gap", gap, minimum=0)
    if not 0.0 <= float(background) <= 1.0:
        raise ValueError(f"background must be in [0, 1], got {background!r}")
    if labels is not None:
        labels = [str(v) for v in labels]
        if len(labels) != len(images):
            raise ValueError(f"labels must hold one label per image ({len(images)}), got {len(labels)}")
    top = LABEL_HEIGHT if labels is not None else 0
    h = top + max(img.shape[0] for img in images)
    w = sum(img.shape[1] for img in images) + gap * (len(images) - 1)
    canvas = np.full((h, w, 3), background, dtype=np.float32)
    x = 0
    for k, img in enumerate(images):
        if labels is not None:
            canvas[:top, x:x + img.shape[1]] = _label_strip(labels[k], img.shape[1], top, background)
        canvas[top:top + img.shape[0], x:x + img.shape[1]] = img
        x += img.shape[1] + gap
    return canvas


def _savefig(fig, path) -> None:
    from pathlib import Path

    path = Path(path)
    fig.tight_layout()
    from ._output import savefig

    savefig(fig, path, format=path.suffix.lower()[1:] or "png")


def plot_band_power(path, images, labels, *, segments=None) -> None:
    """Plot the power per octave band of several images (:func:`spectex.metrics.band_power`).

    Parameters
    ----------
    path : str or Path
        The picture written (its suffix names the format: .png, .svg, .pdf).
    images : sequence of ndarray
    labels : sequence of str
        One per image, for the legend.
    segments : sequence of (int, int) or None, optional
        Per image, the Welch segment of :func:`spectex.metrics.band_power`
        (``None``: the whole image).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from .metrics import band_power

    if len(labels) != len(images):
        raise ValueError(f"labels must hold one label per image ({len(images)}), got {len(labels)}")
    segments = [None] * len(images) if segments is None else list(segments)
    fig = Figure(figsize=(6.4, 4.4), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    for k, (img, label, seg) in enumerate(zip(images, labels, segments)):
        bands, power = band_power(img, segment=seg)
        centre = np.sqrt(bands[:, 0] * np.minimum(bands[:, 1], 0.5))
        ax.semilogx(1.0 / centre, power, ("o-", "s--", "^:", "v-.")[k % 4], label=label)
    ax.set_xlabel("wavelength at the band centre (pixels)")
    ax.set_ylabel("power per octave band (dB)")
    ax.set_title("power per octave band", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=9)
    _savefig(fig, path)


def plot_histograms(path, images, labels, *, bins: int = 64) -> None:
    """Plot the red, green and blue histograms of several RGB images over [0, 1].

    Parameters
    ----------
    path : str or Path
        The picture written (its suffix names the format).
    images : sequence of ndarray, shape (H, W, 3 or 4)
        The first is drawn in grey (the reference), the others in colour.
    labels : sequence of str
        One per image, for the legend.
    bins : int
        Histogram bins over [0, 1].
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    bins = check_int("bins", bins, minimum=1)
    if len(labels) != len(images):
        raise ValueError(f"labels must hold one label per image ({len(images)}), got {len(labels)}")
    images = [_rgb(check_image(f"images[{k}]", img)) for k, img in enumerate(images)]
    fig = Figure(figsize=(9.6, 3.2), dpi=100)
    FigureCanvasAgg(fig)
    edges = np.linspace(0.0, 1.0, bins + 1)
    for c, name in enumerate(("red", "green", "blue")):
        ax = fig.add_subplot(1, 3, c + 1)
        for k, (img, label) in enumerate(zip(images, labels)):
            counts, _ = np.histogram(img[:, :, c], bins=edges, density=True)
            ax.stairs(counts, edges, color="0.2" if k == 0 else f"C{c + 3 * (k - 1)}", label=label)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("value")
        if c == 0:
            ax.legend(fontsize=8)
    _savefig(fig, path)
