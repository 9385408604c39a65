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

Every writer goes through :func:`spectex._output.atomic_path`: the file is
written under a temporary name in the target folder and renamed when
complete, so that a failure never leaves a partial file behind; an output
that is an input, a folder or a device is refused, and a symbolic link is
written through. Every reader refuses images over :data:`MAX_IMAGE_PIXELS`
pixels before decoding them (decompression bombs are small on disk).
"""

from __future__ import annotations

import contextvars
import re
import warnings
from pathlib import Path

import numpy as np

from ._limits import limit
from ._output import atomic_path, check_input_file, note_input, plan_output
from ._validate import check_choice, check_float, check_int

__all__ = ["IMAGE_SUFFIXES", "ARRAY_SUFFIXES", "ANIMATION_SUFFIXES", "MAX_IMAGE_PIXELS", "PNG_COMPRESS_LEVEL",
           "read_image", "write_image", "write_animation", "to_uint", "check_output_path", "check_mp4_size"]

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".webp")
ARRAY_SUFFIXES = (".npy",)
ANIMATION_SUFFIXES = (".gif", ".mp4")
#: Most pixels an image file may have to be read (16384 x 8192; 2 GiB as float32 RGBA).
#: Pillow's own limit (``PIL.Image.MAX_IMAGE_PIXELS``) is set to it while a file is opened.
MAX_IMAGE_PIXELS = limit("IMAGE_PIXELS", 1 << 27)


def check_output_path(name: str, path, suffixes, *, inputs=()) -> Path:
    """Check an output file before the work (see :func:`spectex._output.plan_output`).

    The suffix must be one of ``suffixes``; the folder must exist and be
    writable; the output must not be a folder, a device or any of ``inputs``.
    Returns the path as given (a symbolic link is written through later).
    """
    return plan_output(path, name=name, suffixes=suffixes, inputs=inputs).path


def to_uint(image: np.ndarray, bit_depth: int = 8) -> np.ndarray:
    """Quantise a float image in [0, 1] to uint8 or uint16 (clipped, rounded)."""
    check_choice("bit_depth", str(bit_depth), ("8", "16"))
    top = 255 if bit_depth == 8 else 65535
    arr = np.asarray(image, dtype=np.float32)
    arr = np.clip(np.nan_to_num(arr, nan=0.0), 0.0, 1.0)  # before scaling: inf * top would overflow
    out = arr * np.float32(top) + np.float32(0.5)
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


#: zlib level of PNG files. Against zlib's default 6, level 3 encoded a 4096 x 4096 RGBA tile
#: 1.8x faster (2.3 s against 4.1 s) for a file 4 % larger, a 4000 x 4000 grey fBm 2.7x faster
#: (+23 %), and a coloured one 1.8x faster (+27 %); level 1 is faster still (2.2x, 4.1x, 3.4x)
#: but smooth images grow by 40 to 50 %. The pixels are the same at every level (PNG is lossless).
PNG_COMPRESS_LEVEL = 3


def _png_chunk(kind: bytes, data: bytes) -> bytes:
    import struct
    import zlib

    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def _write_png16(path: Path, data: np.ndarray, *, level: int = PNG_COMPRESS_LEVEL) -> None:
    """A 16-bit PNG (grey, grey + alpha, RGB or RGBA) from uint16 ``data``, rows unfiltered.

    Written with NumPy and zlib (PNG 1.2, ISO/IEC 15948): the rows are big-endian
    samples each behind a filter-type byte 0, compressed in one zlib stream.
    """
    import struct
    import zlib

    h, w = data.shape[:2]
    planes = 1 if data.ndim == 2 else data.shape[2]
    colour_type = {1: 0, 2: 4, 3: 2, 4: 6}[planes]
    rows = np.zeros((h, 1 + 2 * w * planes), dtype=np.uint8)  # filter byte 0, then the samples
    rows[:, 1:] = np.ascontiguousarray(data, dtype=">u2").reshape(h, -1).view(np.uint8)
    compressor = zlib.compressobj(level)
    idat = compressor.compress(rows) + compressor.flush()
    del rows
    ihdr = struct.pack(">IIBBBBB", w, h, 16, colour_type, 0, 0, 0)
    with open(path, "wb") as fh:
        fh.write(b"\x89PNG\r\n\x1a\n")
        fh.write(_png_chunk(b"IHDR", ihdr))
        fh.write(_png_chunk(b"IDAT", idat))
        fh.write(_png_chunk(b"IEND", b""))


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
            options = {"JPEG": {"quality": 95}, "PNG": {"compress_level": PNG_COMPRESS_LEVEL}}.get(fmt, {})
            Image.fromarray(data, mode=pil_mode).save(tmp, format=fmt, **options)
    return path


def _png_bit_depth(path: Path) -> int | None:
    with open(path, "rb") as fh:
        head = fh.read(26)
    if len(head) == 26 and head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR":
        return head[24]
    return None


#: A tighter limit than MAX_IMAGE_PIXELS for the read in progress: (pixels, "where it comes from"), or None.
_READ_LIMIT = contextvars.ContextVar("spectex_read_limit", default=None)
#: A check of the read in progress, called with ``(height, width, channels)`` from the header, before
#: decoding, or None.
_READ_CHECK = contextvars.ContextVar("spectex_read_check", default=None)


def _check_pixels(name: str, path: Path, width: int, height: int, channels: int = 1) -> None:
    if width * height > MAX_IMAGE_PIXELS:
        raise ValueError(f"{name} '{path}' is {width}x{height} = {width * height} pixels, over the limit of "
                         f"{MAX_IMAGE_PIXELS} pixels (spectex.io.MAX_IMAGE_PIXELS; "
                         "set SPECTEX_MAX_IMAGE_PIXELS to raise it)")
    tighter = _READ_LIMIT.get()
    if tighter is not None and width * height > tighter[0]:
        raise ValueError(f"{name} '{path}' is {width}x{height} = {width * height} pixels, over the limit of "
                         f"{tighter[0]} pixels {tighter[1]}")
    check = _READ_CHECK.get()
    if check is not None:
        check((height, width, channels))


def _read_npy(path: Path, name: str) -> np.ndarray:
    try:
        with open(path, "rb") as fh:
            version = np.lib.format.read_magic(fh)
            reader = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                      else np.lib.format.read_array_header_2_0)
            shape, _, dtype = reader(fh)
    except Exception as exc:
        raise ValueError(f"{name} is not a readable .npy file: '{path}' ({exc})") from None
    if np.issubdtype(dtype, np.complexfloating):
        raise ValueError(f"{name} must hold real numbers, got the complex dtype {dtype} in '{path}'")
    if np.issubdtype(dtype, np.signedinteger):
        raise ValueError(f"{name} must hold unsigned integers or floats, got dtype {dtype} in '{path}'")
    if len(shape) not in (2, 3) or not (np.issubdtype(dtype, np.number) or dtype == np.bool_):
        raise ValueError(f"{name} must hold a 2-D or 3-D numeric array, got shape {shape} and dtype {dtype} "
                         f"in '{path}'")
    _check_pixels(name, path, shape[1], shape[0], shape[2] if len(shape) == 3 else 1)
    if len(shape) == 3 and shape[2] > 4:
        raise ValueError(f"{name} must have at most 4 channels, got shape {shape} in '{path}'")
    try:
        arr = np.load(path, allow_pickle=False)
    except Exception as exc:
        raise ValueError(f"{name} is not a readable .npy file: '{path}' ({exc})") from None
    if np.issubdtype(arr.dtype, np.unsignedinteger):  # like a PNG of that depth: scaled by the dtype's top
        return (arr.astype(np.float32) / np.float32(np.iinfo(arr.dtype).max)).astype(np.float32)
    return arr.astype(np.float32)


def _read_png16(path: Path, name: str) -> np.ndarray:
    import png

    try:
        with open(path, "rb") as fh:
            reader = png.Reader(file=fh)
            reader.preamble()
            _check_pixels(name, path, reader.width, reader.height, reader.planes)
            w, h, rows, info = reader.asDirect()
            data = np.vstack([np.asarray(r, dtype=np.uint16) for r in rows])
    except ValueError:
        raise
    except Exception as exc:
        raise ValueError(f"{name} is not a readable PNG: '{path}' ({exc})") from None
    planes = info["planes"]
    try:
        data = data.reshape(h, w, planes)
    except ValueError:
        raise ValueError(f"{name} is not a readable PNG: '{path}' (it is truncated)") from None
    if planes == 1:
        data = data[:, :, 0]
    top = float(2 ** info["bitdepth"] - 1)
    return (data.astype(np.float32) / np.float32(top)).astype(np.float32)


def _open_pil(path: Path, name: str):
    """Open with Pillow, refusing images over MAX_IMAGE_PIXELS before they are decoded."""
    from PIL import Image

    saved = Image.MAX_IMAGE_PIXELS
    try:
        # Deliberately spectex's limit: Pillow then refuses (over twice it) or warns
        # (over it) in open(); the warning is ours to turn into the one-line error below.
        Image.MAX_IMAGE_PIXELS = MAX_IMAGE_PIXELS
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            im = Image.open(path)
    except Image.DecompressionBombError as exc:
        found = re.search(r"\((\d+) pixels\)", str(exc))
        count = f"{found.group(1)} pixels" if found else "more pixels"
        raise ValueError(f"{name} '{path}' has {count}, over the limit of {MAX_IMAGE_PIXELS} pixels "
                         "(spectex.io.MAX_IMAGE_PIXELS; set SPECTEX_MAX_IMAGE_PIXELS to raise it)") from None
    finally:
        Image.MAX_IMAGE_PIXELS = saved
    try:
        # a palette becomes RGB or RGBA, other modes keep their bands (a lower bound is what a check needs)
        _check_pixels(name, path, *im.size, 3 if im.mode in ("P", "PA") else len(im.getbands()))
    except BaseException:
        im.close()
        raise
    return im


def read_image(path, *, name: str = "image", max_pixels=None, check_header=None) -> np.ndarray:
    """Read an image file as float32 in [0, 1].

    Conversions, all documented and lossless where the format allows:

    * grey (``L``, ``I;16``) gives ``(H, W)``; grey with alpha gives ``(H, W, 2)``;
    * palette images are expanded to RGB, or RGBA where the palette has
      transparency; CMYK and other modes are converted to RGB;
    * 16-bit PNGs keep their 16 bits (scaled by 65535), 8-bit files are scaled
      by 255, float TIFFs are taken as they are;
    * ``.npy`` files are loaded as they are (float32), and must be 2-D or 3-D.

    Images over :data:`MAX_IMAGE_PIXELS` pixels are refused from their header,
    before anything is decoded; ``max_pixels``, a pair ``(pixels, words)``,
    sets a tighter limit for this read (a synthesis exemplar), its refusal
    ending with ``words`` (where the limit comes from). ``check_header``, a
    callable, is called with ``(height, width, channels)`` from the header
    (channels: as many as the image read will have, at least), before
    anything is decoded, so that a caller can refuse what the image's size
    makes impossible or too costly (a synthesis's block or window) at once.

    Raises
    ------
    ValueError
        If the file is missing, not a regular file, too large, unreadable or
        not an image; the message names ``name`` and the path.
    """
    if max_pixels is not None:  # (pixels, why): refused from the header, before decoding
        token = _READ_LIMIT.set(tuple(max_pixels))
        try:
            return read_image(path, name=name, check_header=check_header)
        finally:
            _READ_LIMIT.reset(token)
    if check_header is not None:
        if not callable(check_header):
            raise TypeError(f"check_header must be callable, got {type(check_header).__name__}")
        token = _READ_CHECK.set(check_header)
        try:
            return read_image(path, name=name)
        finally:
            _READ_CHECK.reset(token)
    path = check_input_file(name, path)
    note_input(path)
    if path.suffix.lower() == ".npy":
        return _read_npy(path, name)
    if _png_bit_depth(path) == 16:
        return _read_png16(path, name)
    from PIL import UnidentifiedImageError

    try:
        with _open_pil(path, name) as im:
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
    except (UnidentifiedImageError, OSError, SyntaxError, EOFError) as exc:
        raise ValueError(f"{name} is not a readable image: '{path}' ({exc})") from None
    return arr.astype(np.float32) / np.float32(255)


def check_mp4_size(height: int, width: int) -> None:
    """Refuse a frame size that H.264 (yuv420p) cannot hold exactly: odd sides."""
    if height % 2 or width % 2:
        raise ValueError(f"an .mp4 needs even frame sides (H.264 stores colour per 2x2 pixels), got "
                         f"{width}x{height}: choose even sides or a .gif")


def write_animation(path, frames, *, fps: float = 24.0) -> Path:
    """Write an animation (GIF or MP4) from a sequence of float images, atomically.

    Parameters
    ----------
    path : str or Path
        ``.gif`` (Pillow) or ``.mp4`` (H.264 through imageio-ffmpeg).
    frames : sequence of ndarray, each (H, W) or (H, W, 3)
        Values in [0, 1]; all frames must have the same shape; for
        ``.mp4``, H and W must be even (H.264 with yuv420p colour).
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
        check_mp4_size(shape[0], shape[1])
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

            # yuv420p (the format most players accept) goes through imageio's own
            # `pixelformat`: imageio-ffmpeg always writes `-pix_fmt <pixelformat>`,
            # so repeating it in output_params makes ffmpeg warn about two options.
            with iio.get_writer(tmp, format="FFMPEG", mode="I", fps=fps, codec="libx264",
                                macro_block_size=1, quality=8, pixelformat="yuv420p") as writer:
                for d in data:
                    if d.ndim == 2:
                        d = np.repeat(d[:, :, None], 3, axis=2)
                    writer.append_data(d)
    return path
