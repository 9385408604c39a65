"""The shading constants, defined once.

Every implementation of the shading specification (``docs/sampling.md``)
takes its codes and constants from here: the numba kernels import these
names, and the GLSL (the renderer's shader and every export) gets them as
``#define`` lines written by :func:`glsl_defines`, so that no port can hold
a different number.

Adding a layer blend or a tiling mode starts here: append its name to
:data:`BLENDS` or :data:`TILINGS` (the code is the index), then give it one
branch in ``shading/_layers.py`` and one in ``shading/shaders/spectex_layers.glsl``.
"""

from __future__ import annotations

__all__ = [
    "BLENDS", "BLEND_FIRST", "BLEND_ALPHA", "BLEND_DETAIL", "BLEND_VARIANCE", "BLEND_FINE", "BLEND_COVER",
    "BLEND_OVERLAY",
    "FADE_START", "FADE_END", "DEFAULT_ANISOTROPY",
    "TILINGS", "TILING_PERIODIC", "TILING_STOCHASTIC", "DEFAULT_PATCH", "MAX_SNAP",
    "GAUSS_MEAN", "GAUSS_SCALE", "LUT_SIZE", "LUT_SUBROWS",
    "HASH_MUL1", "HASH_MUL2", "WEIGHT_SQUARINGS", "SHARP_LOD", "CELL_LOD_MARGIN",
    "COURSE_SEGMENT", "COURSE_SLIVER", "COURSE_TRIES", "COURSE_ROUND", "NO_JOINT", "BAND_SALT",
    "WRAP_MODES", "WRAP_REPEAT", "WRAP_CLAMP_TO_EDGE", "WRAP_MIRRORED_REPEAT",
    "FILTERS", "FILTER_ALIASES", "FILTER_NEAREST", "FILTER_LINEAR", "FILTER_NEAREST_MIPMAP_NEAREST",
    "FILTER_LINEAR_MIPMAP_NEAREST", "FILTER_NEAREST_MIPMAP_LINEAR", "FILTER_LINEAR_MIPMAP_LINEAR",
    "DEFAULT_MIN_LOD", "DEFAULT_MAX_LOD", "LOD_FLOOR", "ANCHOR_PERIOD",
    "SKY_FALLOFF", "FAR_HAZE_RATIO", "DEFAULT_HAZE", "HAZE_OFF", "MAX_LAYERS", "MAX_TILES", "glsl_defines",
]

# ------------------------------------------------------------------ layers
#: How a layer goes over the layers drawn before it; the code is the index.
BLENDS = ("alpha", "detail", "variance", "fine", "cover", "overlay")
BLEND_ALPHA, BLEND_DETAIL, BLEND_VARIANCE, BLEND_FINE, BLEND_COVER, BLEND_OVERLAY = 0, 1, 2, 3, 4, 5
#: ``"fine"``: the variance blend with the layer's alpha faded out by its
#: footprint, for a detail layer finer than the others: full alpha while a
#: pixel covers at most ``2**FADE_START`` of its texels (isotropic lambda, the
#: longer footprint edge), none from ``2**FADE_END`` on, linear in lambda
#: between; gone before its repetition could be seen or its texels alias.
#: ``"cover"``: the variance blend with the alpha ``a`` raised to
#: ``1 - (1 - a) f`` by the same fade ``f`` of the layer's own footprint: the
#: finer layers drawn before it are gone where a pixel covers ``2**FADE_END``
#: of its texels (for the paper preset's ratio 5.03 and 512-texel tiles, where
#: the next finer layer's period spans 13 pixels), so that their repeats never
#: show as a weave in the distance.
FADE_START = 1.0
FADE_END = 3.0
#: The code of the first drawn layer, whatever its blend: it sets the colour.
BLEND_FIRST = -1

#: How a layer repeats its tile over the plane; the code is the index.
TILINGS = ("periodic", "stochastic")
TILING_PERIODIC, TILING_STOCHASTIC = 0, 1

# Stochastic tiling (histogram-preserving tiling and blending, ``shading.stochastic``).
#: Default side of the triangle grid's triangles, in tiles.
DEFAULT_PATCH = 0.5
#: Most whole structure periods a tile may hold along an axis for ``Layer.snap`` (the offsets are
#: snapped to multiples of 1 / snap of the tile; the shaders compute them in 32-bit integers).
MAX_SNAP = 256
#: The Gaussianised tile: mean and standard deviation of its values at level 0.
GAUSS_MEAN = 0.5
GAUSS_SCALE = 0.1
#: Entries of each row of the inverse look-up table (Gaussian value 0 .. 1).
LUT_SIZE = 1024
#: Rows of the sampled table per mip level step (``stochastic.expand_lut``).
LUT_SUBROWS = 8
#: The stochastic blend's weights are the barycentric weights raised to the power
#: ``2 ** WEIGHT_SQUARINGS`` (squared this many times) and renormalised to sum 1: sharper
#: transitions between the three patches, so that most of a triangle shows one patch at full
#: contrast instead of a cross-fade of two or three (the double images of a linear blend;
#: Mikkelsen, JCGT 11(1) 2022, and Burley, JCGT 8(4) 2019, raise the weights to a power too).
#: 0 is Heitz and Neyret's linear weights. The variance-preserving normalisation keeps the
#: histogram for any weights. Further away the power follows the patch's width in pixels: ``2 ** e``,
#: ``e = clamp(log2(patch texels) - lambda, 0, WEIGHT_SQUARINGS)`` (``stochastic.sharpen_weights``); a
#: transition spans about half a pixel where a patch is under 8 pixels wide, and the weights are
#: barycentric where it shrinks to a pixel.
WEIGHT_SQUARINGS = 3
#: The level of detail up to which a transition of a few texels is kept whole: the least level at
#: which a snapped layer's cells give way to the blend at the point (``CELL_LOD_MARGIN``).
SHARP_LOD = 2.0
#: A snapped layer's cells (each brick or floor tile from one patch, ``docs/sampling.md`` 6b) hold
#: up to ``lambda = log2(period) - CELL_LOD_MARGIN`` (``period``: the snap's shorter period in level-0
#: texels; where it spans 4 pixels) and give way to the blend at the point one level further (2
#: pixels), never before ``SHARP_LOD``: ``SHARP_LOD`` is a few texels' transition, a cell's edge
#: aliases only where the cells themselves shrink to a pixel or two, and a floor tile of 64 texels
#: is still 8 to 16 pixels wide at ``SHARP_LOD`` (it was cut by the triangle grid's cross-fades
#: there, unlike the same floor seen closer: 28 dB from a supersampled render of it).
CELL_LOD_MARGIN = 2.0
#: A layer snapped along one axis only (courses of boards or bricks, ``shading._cells.course_map``) changes
#: patch along each course at a joint: the course is cut into segments of whole grid cells, each at least
#: ``COURSE_SEGMENT`` times the tile's longest board (``stochastic.course_vertex``), so that every segment
#: holds a joint of its own patch where the patch before it gives way.
COURSE_SEGMENT = 1.25
#: Of the new patch's first ``COURSE_TRIES`` joints in its segment, the cut takes the one that hides least of
#: the board the patch before shows there, and leaves none of it shorter than ``COURSE_SLIVER`` times the
#: course's height (a sliver of a board) where it can.
COURSE_SLIVER = 0.5
COURSE_TRIES = 3
#: What a segment's start (in texels) and its vertices' grid indices are floored after adding: a value the
#: same for all of a segment's points but computed per point lands a rounding error either side of a whole
#: number exactly where the segment starts on a texel edge (the grid's origin), and each course of a board
#: then took its cut from one start or the other, line by line; no start the grid makes is this far past
#: a whole number (2 minus the golden ratio).
COURSE_ROUND = 0.3819660112501051
#: A course map's unit start and end for a course without a joint (a band the whole tile long): the cut
#: across it is at the segment's start.
NO_JOINT = 4096.0
#: A wall of courses of their own heights (a layer snapped along one axis with one period across) is cut
#: across its courses into *bands* one tile high, each the tile's courses started at a course of its own
#: (``stochastic.course_band_shift``): band ``b`` takes the entry ``lowbias32(b ^ lowbias32(key ^
#: BAND_SALT))`` picks of the course-start table, so that its choice is not the vertex hash of any row.
BAND_SALT = 0x5BD1E995
#: The two multipliers of the grid vertices' hash (Wellons' ``lowbias32``).
HASH_MUL1 = 0x7FEB352D
HASH_MUL2 = 0x846CA68B

#: Most layers in a texture (and per-layer uniform arrays in the shader).
MAX_LAYERS = 8
#: Most tiles in a texture (sampler units in the shader).
MAX_TILES = 8

# ----------------------------------------------------------------- sampler
#: Wrap modes (OpenGL table 8.20); the code is the index.
WRAP_MODES = ("repeat", "clamp_to_edge", "mirrored_repeat")
WRAP_REPEAT, WRAP_CLAMP_TO_EDGE, WRAP_MIRRORED_REPEAT = 0, 1, 2

#: Texture filters; the code is the index. Only the first two magnify.
FILTERS = ("nearest", "linear", "nearest_mipmap_nearest", "linear_mipmap_nearest",
           "nearest_mipmap_linear", "linear_mipmap_linear")
FILTER_NEAREST, FILTER_LINEAR = 0, 1
FILTER_NEAREST_MIPMAP_NEAREST, FILTER_LINEAR_MIPMAP_NEAREST = 2, 3
FILTER_NEAREST_MIPMAP_LINEAR, FILTER_LINEAR_MIPMAP_LINEAR = 4, 5
#: Other names accepted for filters.
FILTER_ALIASES = {"trilinear": "linear_mipmap_linear", "bilinear": "linear"}

#: OpenGL's default level-of-detail clamps (GL_TEXTURE_MIN_LOD, GL_TEXTURE_MAX_LOD).
DEFAULT_MIN_LOD = -1000.0
DEFAULT_MAX_LOD = 1000.0
#: The footprint length (texels or metres) below which lambda is taken at this
#: floor, so that log2 never sees 0.
LOD_FLOOR = 1e-30
#: Per-layer anchor coordinates are reduced modulo this (a period of REPEAT
#: and MIRRORED_REPEAT), in float64 on the host.
ANCHOR_PERIOD = 2.0

# --------------------------------------------------------------- atmosphere
#: Sky: ``horizon + (1 - exp(-SKY_FALLOFF * elevation)) (zenith - horizon)``,
#: ``elevation = d_z / |d|``.
SKY_FALLOFF = 4.0
#: The texture is not sampled beyond ``FAR_HAZE_RATIO * haze_distance``.
FAR_HAZE_RATIO = 50.0
#: Default haze distance, metres: a 1,200 m aerial view keeps two thirds of the tile's colour.
DEFAULT_HAZE = 12000.0
#: The haze distance the shaders get for "no haze" (``Atmosphere(haze_distance=0)``): finite in float32,
#: ``exp(-d / HAZE_OFF)`` is 1 for any distance on Earth.
HAZE_OFF = 1e30


def _glsl_number(value) -> str:
    if isinstance(value, int):
        return str(value)
    text = repr(float(value))
    return text if any(ch in text for ch in ".e") else text + ".0"


def glsl_defines() -> str:
    """The constants above as GLSL ``#define`` lines (prefix ``SPX_``).

    Blend and tiling codes, the sampler's filter and wrap codes used by the
    layer library, and the atmosphere constants; the shader sources refer
    to these names only, never to literal codes.
    """
    lines = ["// Generated from spectex/shading/constants.py: do not edit."]
    for name, code in (("FIRST", BLEND_FIRST), *((b.upper(), i) for i, b in enumerate(BLENDS))):
        lines.append(f"#define SPX_BLEND_{name} {code}")
    for i, t in enumerate(TILINGS):
        lines.append(f"#define SPX_TILING_{t.upper()} {i}")
    for i, f in enumerate(FILTERS):
        lines.append(f"#define SPX_FILTER_{f.upper()} {i}")
    lines.append(f"#define SPX_GAUSS_MEAN {_glsl_number(GAUSS_MEAN)}")
    lines.append(f"#define SPX_LUT_SIZE {LUT_SIZE}")
    lines.append(f"#define SPX_LUT_SUBROWS {LUT_SUBROWS}")
    lines.append(f"#define SPX_HASH_MUL1 {HASH_MUL1:#x}u")
    lines.append(f"#define SPX_HASH_MUL2 {HASH_MUL2:#x}u")
    lines.append(f"#define SPX_WEIGHT_SQUARINGS {WEIGHT_SQUARINGS}")
    lines.append(f"#define SPX_SHARP_LOD {_glsl_number(SHARP_LOD)}")
    lines.append(f"#define SPX_CELL_LOD_MARGIN {_glsl_number(CELL_LOD_MARGIN)}")
    lines.append(f"#define SPX_COURSE_SEGMENT {_glsl_number(COURSE_SEGMENT)}")
    lines.append(f"#define SPX_COURSE_SLIVER {_glsl_number(COURSE_SLIVER)}")
    lines.append(f"#define SPX_COURSE_TRIES {COURSE_TRIES}")
    lines.append(f"#define SPX_COURSE_ROUND {_glsl_number(COURSE_ROUND)}")
    lines.append(f"#define SPX_NO_JOINT {_glsl_number(NO_JOINT)}")
    lines.append(f"#define SPX_BAND_SALT {BAND_SALT:#x}u")
    lines.append(f"#define SPX_MAX_LAYERS {MAX_LAYERS}")
    lines.append(f"#define SPX_FADE_START {_glsl_number(FADE_START)}")
    lines.append(f"#define SPX_FADE_END {_glsl_number(FADE_END)}")
    lines.append(f"#define SPX_LOD_FLOOR {_glsl_number(LOD_FLOOR)}")
    lines.append(f"#define SPX_SKY_FALLOFF {_glsl_number(SKY_FALLOFF)}")
    lines.append(f"#define SPX_FAR_HAZE_RATIO {_glsl_number(FAR_HAZE_RATIO)}")
    return "\n".join(lines) + "\n"

#: The renderers' default maximum anisotropy (EXT_texture_filter_anisotropic's
#: ``N`` samples along the footprint's major axis, at most this many). Chosen
#: by ``benchmarks/bench_anisotropy.py`` (issue 18): on a full-contrast tile,
#: against an 8 x 8 supersampled truth, trilinear alone (1) scores 36.6 to
#: 40.6 dB on the views that minify (close-up 67 dB), 8 scores 45.1 to 47.8 dB
#: (16 gains under 0.5 dB more); a 1920 x 1080 ground view costs about 4x the
#: GL time of trilinear on llvmpipe and takes the CPU renderer off its fast
#: isotropic kernel. The viewer and the web export use the same 8. Pass
#: ``anisotropy=1`` for trilinear only.
DEFAULT_ANISOTROPY = 8.0
