"""Reading and writing images, raw arrays and animations.

Inside the library, images are float32 arrays in [0, 1], ``(H, W)`` or
``(H, W, C)``, channel-last, row 0 at the top. This module is the one place
where they are converted to and from file formats:

* ``.png``: 8-bit by default, 16-bit with ``bit_depth=16`` (16-bit colour PNGs
  are written and read with pypng, because Pillow handles only 16-bit grey);
* ``.jpg``/``.jpeg``, ``.bmp``, ``.tif``/``.tiff``, ``.webp``: 8-bit, through Pillow;
* ``.npy``: the raw float array, no clipping or quantisation;
* ``.gif`` (Pillow) and ``.mp4`` (imageio-ffmpeg, ``pip install spectex[video]``)
  for animations.

Every writer goes through :func:`atomic_path`: the file is written under a
temporary name in the target folder and renamed when complete, so that a
failure never leaves a partial file behind.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

import numpy as np

from ._validate import check_choice, check_float, check_int

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".webp")
ARRAY_SUFFIXES = (".npy",)
ANIMATION_SUFFIXES = (".gif", ".mp4")


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; rename it to ``path`` on success.

    On any exception the temporary file is removed and ``path`` is left as it
    was (absent, or the previous complete file).
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise FileNotFoundError(f"output folder does not exist: '{folder}'")
    # The real suffix comes last: writers such as imageio pick the format by it.
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".part" + path.suffix, dir=folder)
    os.close(fd)
    try:
        yield Path(tmp)
        # mkstemp creates the file as 0600; give it the usual permissions.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def check_output_path(name: str, path, suffixes) -> Path:
    """Check that ``path`` has one of ``suffixes`` and an existing folder."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in suffixes:
        raise ValueError(f"{name} must end in one of {', '.join(suffixes)}, got '{path}'")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise ValueError(f"{name} is in a folder that does not exist: '{path}'")
    return path


def to_uint(image: np.ndarray, bit_depth: int = 8) -> np.ndarray:
    """Quantise a float image in [0, 1] to uint8 or uint16 (clipped, rounded)."""
    check_choice("bit_depth", str(bit_depth), ("8", "16"))
    top = 255 if bit_depth == 8 else 65535
    arr = np.asarray(image, dtype=np.float32)
    arr = np.nan_to_num(arr, nan=0.0)
    out = np.clip(arr * np.float32(top) + np.float32(0.5), 0, top)
    return out.astype(np.uint8 if bit_depth == 8 else np.uint16)


def _as_image(name: str, image) -> np.ndarray:
    image = np.asarray(image)
    if image.ndim == 3 and image.shape[2] == 1:
        image = image[:, :, 0]
    if image.ndim not in (2, 3) or (image.ndim == 3 and image.shape[2] not in (2, 3, 4)):
        raise ValueError(f"{name} must have shape (H, W) or (H, W, 1|2|3|4), got shape {image.shape}")
    if image.shape[0] < 1 or image.shape[1] < 1:
        raise ValueError(f"{name} must not be empty, got shape {image.shape}")
    return image


def _write_png16(path: Path, data: np.ndarray) -> None:
    import png  # pypng

    h, w = data.shape[:2]
    planes = 1 if data.ndim == 2 else data.shape[2]
    greyscale = planes in (1, 2)
    alpha = planes in (2, 4)
    writer = png.Writer(width=w, height=h, greyscale=greyscale, alpha=alpha, bitdepth=16,
                        compression=6)
    rows = data.reshape(h, w * planes)
    with open(path, "wb") as fh:
        writer.write(fh, rows)


def write_image(path, image, *, bit_depth: int = 8) -> Path:
    """Write a float image in [0, 1] to ``path``, atomically.

    Parameters
    ----------
    path : str or Path
        Output file; its suffix picks the format (see the module docstring).
    image : ndarray, shape (H, W) or (H, W, C), C in 1..4
        Values in [0, 1]; values outside are clipped (except for ``.npy``,
        which stores the array as it is).
    bit_depth : {8, 16}
        Bits per channel for PNG. Other image formats are always 8-bit.

    Returns
    -------
    Path
        The path written.
    """
    path = check_output_path("output", path, IMAGE_SUFFIXES + ARRAY_SUFFIXES)
    bit_depth = check_int("bit_depth", bit_depth)
    if bit_depth not in (8, 16):
        raise ValueError(f"bit_depth must be 8 or 16, got {bit_depth}")
    image = _as_image("image", image)
    suffix = path.suffix.lower()
    if bit_depth == 16 and suffix != ".png":
        raise ValueError(f"bit_depth=16 needs a .png output, got '{path}'")
    with atomic_path(path) as tmp:
        if suffix == ".npy":
            with open(tmp, "wb") as fh:
                np.save(fh, np.asarray(image))
        elif bit_depth == 16:
            _write_png16(tmp, to_uint(image, 16))
        else:
            from PIL import Image

            data = to_uint(image, 8)
            if suffix in (".jpg", ".jpeg") and data.ndim == 3 and data.shape[2] in (2, 4):
                data = data[:, :, : data.shape[2] - 1]  # JPEG has no alpha
                if data.shape[2] == 1:
                    data = data[:, :, 0]
            mode = {2: "L", 3: "RGB", 4: "RGBA"}
            pil_mode = "L" if data.ndim == 2 else ("LA" if data.shape[2] == 2 else mode[data.shape[2]])
            fmt = {".jpg": "JPEG", ".jpeg": "JPEG", ".png": "PNG", ".bmp": "BMP",
                   ".tif": "TIFF", ".tiff": "TIFF", ".webp": "WEBP"}[suffix]
            Image.fromarray(data, mode=pil_mode).save(tmp, format=fmt, **({"quality": 95} if fmt == "JPEG" else {}))
    return path


def _png_bit_depth(path: Path) -> int | None:
    with open(path, "rb") as fh:
        head = fh.read(26)
    if len(head) == 26 and head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR":
        return head[24]
    return None


def read_image(path, *, name: str = "image") -> np.ndarray:
    """Read an image file as float32 in [0, 1].

    Conversions, all documented and lossless where the format allows:

    * grey (``L``, ``I;16``) gives ``(H, W)``; grey with alpha gives ``(H, W, 2)``;
    * palette images are expanded to RGB, or RGBA where the palette has
      transparency; CMYK and other modes are converted to RGB;
    * 16-bit PNGs keep their 16 bits (scaled by 65535), 8-bit files are scaled
      by 255, float TIFFs are taken as they are;
    * ``.npy`` files are loaded as they are (float32), and must be 2-D or 3-D.

    Raises
    ------
    ValueError
        If the file is missing, unreadable or not an image; the message names
        ``name`` and the path.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{name} file not found: '{path}'")
    if path.suffix.lower() == ".npy":
        try:
            arr = np.load(path, allow_pickle=False)
        except Exception as exc:
            raise ValueError(f"{name} is not a readable .npy file: '{path}' ({exc})") from None
        if arr.ndim not in (2, 3) or not np.issubdtype(arr.dtype, np.number):
            raise ValueError(f"{name} must hold a 2-D or 3-D numeric array, got shape {arr.shape} in '{path}'")
        return arr.astype(np.float32)
    if _png_bit_depth(path) == 16:
        import png

        try:
            with open(path, "rb") as fh:
                w, h, rows, info = png.Reader(file=fh).asDirect()
                data = np.vstack([np.asarray(r, dtype=np.uint16) for r in rows])
        except Exception as exc:
            raise ValueError(f"{name} is not a readable PNG: '{path}' ({exc})") from None
        planes = info["planes"]
        data = data.reshape(h, w, planes)
        if planes == 1:
            data = data[:, :, 0]
        top = float(2 ** info["bitdepth"] - 1)
        return (data.astype(np.float32) / np.float32(top)).astype(np.float32)
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as im:
            im.load()
            mode = im.mode
            if mode == "P" or mode == "PA":
                im = im.convert("RGBA" if ("transparency" in im.info or mode == "PA") else "RGB")
            elif mode in ("1",):
                im = im.convert("L")
            elif mode in ("I;16", "I;16B", "I;16L"):
                arr = np.asarray(im, dtype=np.uint16)
                return (arr.astype(np.float32) / np.float32(65535)).astype(np.float32)
            elif mode == "I":
                arr = np.asarray(im, dtype=np.int64)
                top = 65535.0 if arr.max(initial=0) > 255 else 255.0
                return np.clip(arr / top, 0, 1).astype(np.float32)
            elif mode == "F":
                return np.asarray(im, dtype=np.float32).copy()
            elif mode not in ("L", "LA", "RGB", "RGBA"):
                im = im.convert("RGB")
            arr = np.asarray(im)
    except (UnidentifiedImageError, OSError, SyntaxError) as exc:
        raise ValueError(f"{name} is not a readable image: '{path}' ({exc})") from None
    return arr.astype(np.float32) / np.float32(255)


def write_animation(path, frames, *, fps: float = 24.0) -> Path:
    """Write an animation (GIF or MP4) from a sequence of float images, atomically.

    Parameters
    ----------
    path : str or Path
        ``.gif`` (Pillow) or ``.mp4`` (H.264 through imageio-ffmpeg).
    frames : sequence of ndarray, each (H, W) or (H, W, 3)
        Values in [0, 1]; all frames must have the same shape.
    fps : float
        Frames per second.
    """
    path = check_output_path("output", path, ANIMATION_SUFFIXES)
    fps = check_float("fps", fps, minimum=0.0, exclusive_minimum=True, maximum=240.0)
    frames = [_as_image(f"frames[{i}]", f) for i, f in enumerate(frames)]
    if not frames:
        raise ValueError("frames must hold at least one frame, got 0")
    shape = frames[0].shape
    for i, f in enumerate(frames):
        if f.shape != shape:
            raise ValueError(f"frames[{i}] has shape {f.shape}, expected {shape} like frames[0]")
    data = [to_uint(f, 8) for f in frames]
    if data[0].ndim == 3 and data[0].shape[2] in (2, 4):
        data = [d[:, :, :-1] if d.shape[2] == 4 else d[:, :, 0] for d in data]
    suffix = path.suffix.lower()
    if suffix == ".mp4":
        try:
            import imageio.v2 as iio  # noqa: F401
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            raise ValueError("writing .mp4 needs imageio and imageio-ffmpeg: pip install 'spectex[video]'") from None
    with atomic_path(path) as tmp:
        if suffix == ".gif":
            from PIL import Image

            images = [Image.fromarray(d) for d in data]
            images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:],
                           duration=max(int(round(1000.0 / fps)), 20), loop=0)
        else:
            import imageio.v2 as iio

            # H.264 wants even sizes: pad by repeating the last row/column.
            h, w = data[0].shape[:2]
            ph, pw = h % 2, w % 2
            # yuv420p (the format most players accept) goes through imageio's own
            # `pixelformat`: imageio-ffmpeg always writes `-pix_fmt <pixelformat>`,
            # so repeating it in output_params makes ffmpeg warn about two options.
            with iio.get_writer(tmp, format="FFMPEG", mode="I", fps=fps, codec="libx264",
                                macro_block_size=1, quality=8, pixelformat="yuv420p") as writer:
                for d in data:
                    if d.ndim == 2:
                        d = np.repeat(d[:, :, None], 3, axis=2)
                    if ph or pw:
                        d = np.pad(d, ((0, ph), (0, pw), (0, 0)), mode="edge")
                    writer.append_data(d)
    return path
