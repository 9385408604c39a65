"""Fitting a spectral texture to an exemplar photograph.

The future work of Berger's sketch (seed 000): "analyze a given image for its
statistical properties, and use these properties to generate texture tiles
and mixing parameters for a similar-looking spectral texture".

:func:`fit` (also ``spectex.fit``): exemplar in, :class:`spectex.SpectralTexture`
out; :func:`fit_report` for the numbers of a fit (a :class:`FitResult` holds
both), :func:`report_reference` for the photo's half of them, made beforehand;
:func:`prepare_exemplar` for the input conversions (grey, alpha, 16-bit, crop
of huge images); :func:`structure_peak` for whether an exemplar
is structured. The statistics it matches are those of :mod:`spectex.analysis`.

See ``docs/fitting.md``.
"""

from __future__ import annotations

from .._lighting import even_lighting  # its home; the fit's name for it
from .._validate import check_choice
from ._auto import check_options  # noqa: F401 - for the command line (not in __all__)
from ._core import (
    FIT_METHODS,
    FIT_TILINGS,
    MAX_ANALYSIS_SIZE,
    MIN_SIZE,
    STRUCTURED_PEAK,
    FitReport,
    FitResult,
    ReportReference,
    exemplar_scale,
    fit_report,
    prepare_exemplar,
    report_reference,
    structure_peak,
)
from ._legacy import _fit_legacy
from ._structure import structure_period

__all__ = ["fit", "fit_result", "fit_report", "FitResult", "FitReport", "report_reference", "ReportReference",
           "prepare_exemplar", "exemplar_scale", "even_lighting", "structure_peak", "structure_period",
           "MIN_SIZE", "MAX_ANALYSIS_SIZE", "STRUCTURED_PEAK", "FIT_TILINGS", "FIT_METHODS"]


def fit(image, *, pixel_size: float | None = None, photo_size: float | None = None, layers: int = 5,
        ratio: float = 4.0, opacity: float | None = None, iterations: int | None = None,
        tile_size: int | None = None, max_size: int = MAX_ANALYSIS_SIZE, rng=0, tiling: str = "auto",
        patch: float | None = None, method: str = "auto", keep_one_off: bool = False, keep_lighting: bool = False,
        keep_perspective: bool = False, progress=None):
    """Fit a spectral texture to an exemplar photograph (Berger's future work).

    **The default, ``method="auto"``** (issue 22; ``spectex.fitting._auto`` and
    ``docs/fitting.md``): each layer carries only what the photo says at its
    scale. The finest layer is a tile of the photo: for a structured photo
    (:func:`structure_peak` >= :data:`STRUCTURED_PEAK` and a period along x
    or y in its autocorrelation) a periodic tile of whole periods cut where
    its wrap edges show least, kept unless a trial bake of the stochastic
    alternative is clearly closer by the structural distance
    (:func:`spectex.metrics.structural_distance`); otherwise the photo's
    seamless crop (drawn stochastically it never repeats, so even a small
    photo is its own tile; a tileable quilt with a reuse penalty where the
    layer is periodic, or where the crop's seam correction moved the
    photo's statistics past its own floor and the quilt is closer: stripes
    meeting out of phase along the wrap edges), drawn stochastically with sharpened blend weights
    (no cross-faded double images). The coarser layers draw a second tile, random-phase noise that
    continues the photo's spectrum below its lowest frequency, on the main
    axis of its low-passed colours (never the photo magnified), overlaid at
    a low opacity (0.1; ``Layer.blend="overlay"``: they scale the colour
    below, so black and white stay and the detail keeps its contrast). The
    tile's colours end with its means at the photo's, its extremes the
    photo's (inside the photo's range per channel, nothing piled at black
    or white) and its coarsest bands lowered where a bake over twice the
    photo shows more contrast at the photo's scale than the photo. Scale: ``pixel_size``, or
    ``photo_size`` (metres across the photo's longer side), or, with
    neither, a photo 1.5 m across (``DEFAULT_PHOTO_SIZE``; said in the
    result's notes). Content the photo shows once (a leaf on gravel, a
    tripod's foot on a lawn: :func:`spectex.metrics.one_off_repeats`'s
    rarity over its threshold) would come back once per photo area, the
    same object at random places; it is filled from elsewhere in the photo
    first (cut along minimum-error seams; said in the notes), unless
    ``keep_one_off``. Before that, the photo's lighting (a smooth drift of
    its brightness across it, :func:`spectex.metrics.lighting_blotches`),
    which every patch of the texture would repeat as bright and dark
    blotches, is divided out (said in the notes), unless ``keep_lighting``;
    and a photo of unstructured ground taken at an angle (its grain
    shrinking towards the far side, :func:`spectex.metrics.scale_blotches`)
    is levelled in scale by a homography (a structured one is rectified from
    its lines), unless ``keep_perspective``. First of all, a photo that
    repeats itself exactly (a texture tiled two by two or three by three
    before it was saved: ``fitting._structure.repeat_cell``) is read as one
    cell of it, its copies left out (said in the notes and in
    ``params["repeat"]``); a pattern's own period (a cell under 64 pixels,
    one motif per cell, or a structure finer than the repeat) keeps the
    whole photo.

    **``method="legacy"``**, the fit before issue 22, kept only so that
    ``benchmarks/bench_fit_quality.py`` can compare; it is what the rest of
    this text describes (pixel size 1 m by default, opacity 0.2, 3
    iterations). The texture is ``layers`` layers of one seamless RGBA tile made from the
    exemplar. Its finest layer shows the tile texel for exemplar pixel
    (size ``tile_px * pixel_size``, no offset or rotation), each next layer
    is ``ratio`` times larger (rotated by the golden angle and offset, so
    the grids do not line up) and alpha-blended over the finer ones. The
    fit, all on small bakes of the texture at ``pixel_size``:

    1. **Tile**: for an exemplar smaller than 512 pixels, a tile four
       times its side (up to 512) by tileable image quilting
       (:func:`spectex.synthesis.quilt`), so the finest layer does not
       repeat the exemplar at its own period; otherwise the exemplar's
       central square made seamless (:func:`spectex.tiles.make_seamless`,
       matched seams). See ``tile_size``.
    2. **Layer opacities** continue the spectrum: the exemplar's power per
       octave over its three coarsest bands changes by ``s`` dB per octave
       towards coarser scales, clamped to at most ``MAX_COARSE_SLOPE``
       (-1.5: a photograph of a stationary texture holds no more power
       beyond its size, and a texture in [0, 1] cannot hold a rising
       spectrum over many octaves); layer ``k >= 1`` gets opacity
       ``opacity * q^(k-1)`` with ``q = 10^(s log2(ratio) / 20)``, so each
       coarser layer adds the power the slope asks for at its scale.
    3. **Alpha** is ``0.5 + g z / 4`` (clipped), ``z`` the tile's
       standardised luma, smoothed by one texel and without its coarsest
       structure (a Gaussian of 1/16 of the tile): where the coarse layer is
       bright (``g > 0``) or dark (``g < 0``) it hides the finer bands.
       ``g`` is chosen on a grid (-3, -1, 1, 3; refined linearly, checked
       again at +-0.75 after the other steps) so that the bake's
       cross-scale dependence (:func:`spectex.analysis.cross_scale`,
       ``value``) matches the exemplar's.
    4. **Band power and histograms**: ``iterations`` times, the tile's
       colour is filtered by a radial gain (piecewise linear in dB against
       log frequency, periodic) by the difference in dB between the
       exemplar's and the bake's power per octave (damped by 0.8, at most
       6 dB a step), and its channels shifted so that the bake's means
       match; then each tile channel goes through the monotone map that
       takes the bake's histogram to the exemplar's, and a last band-power
       step follows (Heeger and Bergen's alternation [2]_, here through
       the layered texture).
    5. **Never repeat** (``tiling``): the layers are made stochastic
       (histogram-preserving tiling and blending of the tile, Heitz and
       Neyret [6]_; :class:`spectex.texture.Layer`), and the band-power and
       histogram steps run once more, then the last ones, on bakes of the
       stochastic texture (the blending moves the band powers a little).
       Steps 1-4 run on periodic bakes (the same tile, 3x faster). With
       ``"auto"`` (default) every layer is stochastic unless the exemplar
       is *structured*, measured: :func:`structure_peak` (its own
       :func:`~spectex.metrics.repeat_peak`) at least
       :data:`STRUCTURED_PEAK`; then the finest layer stays periodic
       (tiling and blending would blur bricks or lines into ghosts; the
       coarser layers are stochastic still). ``docs/fitting.md`` has the
       numbers.

    Bakes are regions of the exemplar's size (at most 256 x 256; twice the
    size for exemplars of 128 or less) on the pixel grid: the exemplar's
    own place and one or two far away in the coarse layers, so that the fit
    does not tune one lucky region. Bands that such a region cannot hold
    are measured on coarser bakes (mip-filtered): an exemplar larger than
    the region has its coarsest bands matched on a bake at twice the pixel
    size (against the exemplar reduced 2 x 2), and two bands beyond the
    exemplar's coarsest are set on the line of the continuation slope
    ``s`` (a 128 x 128 bake at ``2^m`` times the pixel size), so the
    texture continues the spectrum at larger scales.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The exemplar, values in [0, 1] (integers scaled by their dtype's
        maximum); see :func:`prepare_exemplar` for the conversions (grey,
        alpha, 16-bit, a flat frame, large photos). At least 32 x 32, not flat.
    pixel_size : float, optional
        World size of one pixel of the photo (metres); ``bake(texture, shape,
        pixel_size=FitResult.pixel_size)`` then renders at the exemplar's
        scale (the same, or times :func:`exemplar_scale` where a large photo
        was resampled). Default: from ``photo_size``.
    photo_size : float, optional
        Metres across the photo's longer side (not with ``pixel_size``);
        default 1.5 (a photo of ground taken standing). Method "auto" only.
    method : {"auto", "legacy"}
        The fit (see above); "legacy" only for comparisons.
    layers : int
        Number of layers, 2 to 8.
    ratio : float
        Size ratio between neighbouring layers, > 1 (4: two octaves).
    opacity : float, optional
        Opacity of the first coarse layer, in (0, 1]; default 0.1 (legacy 0.2).
    iterations : int, optional
        Rounds of the band-power step, >= 1; default 1 (legacy 3).
    tile_size : int, optional
        Tile side in texels. Default (``method="auto"``): the exemplar's
        shorter side ``m`` where the finest layer is drawn stochastically
        (it never repeats, so the photo itself is its tile), ``max(m,
        min(512, 4 m))`` where it is periodic (``tiling="periodic"``) and
        for the legacy method: 512 for exemplars of 128 to 512 pixels,
        four times smaller ones. A tile larger than the
        exemplar is synthesised from it by tileable image quilting
        (:func:`spectex.synthesis.quilt`, Efros and Freeman [5]_), so that
        a periodic layer does not repeat at the exemplar's period; otherwise
        it is the exemplar's central crop made seamless. A photo the fit
        resampled for its grain (:func:`prepare_exemplar`) whose finest tile
        is that crop gets it at the photo's own resolution by default:
        ``k`` times the analysed side, ``k`` the whole number nearest the
        photo pixels per analysed pixel, at most 2048 texels (the coarse
        tile alike), the photo's finer detail put back where it came from,
        so a close view keeps its grain; said in the notes,
        ``params["full_resolution"]``. Give the analysed side (512) for
        the smaller tile.
    max_size : int
        Larger exemplars are analysed on a central crop of this size, at full
        resolution unless its structure's periods, its grain or its large
        features (a band of its spectrum beyond the crop stronger than the
        coarsest the crop holds) would not fit (:func:`prepare_exemplar`).
    rng : int, numpy.random.Generator or None
        Randomness of the quilting (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, so equal inputs and ``rng`` give
        equal textures; a Generator is used (and advanced); None draws fresh
        randomness.
    tiling : {"auto", "stochastic", "periodic"}
        ``"periodic"``: every layer periodic (the fit before stochastic
        layers; the texture repeats the tile). ``"stochastic"``: every layer
        stochastic. ``"auto"``: stochastic, but a periodic finest layer for
        a structured exemplar (step 5).
    patch : float, optional
        The stochastic layers' triangle side in tiles; default
        ``DEFAULT_PATCH`` (0.5).
    keep_one_off : bool
        Keep content the photo shows once (a leaf, a tripod's foot) in the
        tile (default: filled from the rest of the photo).
    keep_lighting : bool
        Keep the photo's lighting, a smooth drift of its brightness across
        it (default: divided out where it is more than chance).
    keep_perspective : bool
        Keep the perspective of a photo taken at an angle (default: a
        structured photo rectified from its lines, an unstructured one
        levelled in scale). ``method="auto"`` only, as the two above.
    progress : callable, optional
        ``progress(done, total)`` after each step.

    Returns
    -------
    SpectralTexture
        :func:`fit_result` gives it with the numbers of the fit (a :class:`FitResult`).

    References
    ----------
    .. [1] D. R. Berger, "Spectral texturing for real-time applications",
       SIGGRAPH 2003 Sketches and Applications (the model; the fit is its
       future work).
    .. [2] D. J. Heeger and J. R. Bergen, "Pyramid-based texture
       analysis/synthesis", SIGGRAPH 1995.
    .. [3] J. Portilla and E. P. Simoncelli, "A parametric texture model
       based on joint statistics of complex wavelet coefficients", IJCV
       40(1), 2000 (cross-scale dependence).
    .. [4] L. Moisan, "Periodic plus smooth image decomposition", JMIV 39(2),
       2011 (the seamless tile).
    .. [5] A. A. Efros and W. T. Freeman, "Image quilting for texture
       synthesis and transfer", SIGGRAPH 2001 (the larger tile).
    .. [6] E. Heitz and F. Neyret, "High-performance by-example noise using
       a histogram-preserving blending operator", Proc. ACM CGIT 1(2), 2018.
    """
    kwargs = dict(pixel_size=pixel_size, photo_size=photo_size, layers=layers, ratio=ratio, opacity=opacity,
                  iterations=iterations, tile_size=tile_size, max_size=max_size, tiling=tiling, patch=patch,
                  method=method, keep_one_off=keep_one_off, keep_lighting=keep_lighting,
                  keep_perspective=keep_perspective, progress=progress, rng=rng)
    return fit_result(image, **kwargs).texture


def fit_result(image, *, pixel_size: float | None = None, photo_size: float | None = None, layers: int = 5,
               ratio: float = 4.0, opacity: float | None = None, iterations: int | None = None,
               tile_size: int | None = None, max_size: int = MAX_ANALYSIS_SIZE, rng=0, tiling: str = "auto",
               patch: float | None = None, method: str = "auto", keep_one_off: bool = False,
               keep_lighting: bool = False, keep_perspective: bool = False, progress=None) -> FitResult:
    """Fit a spectral texture as :func:`fit` does, and return it with the numbers of the fit.

    The parameters are :func:`fit`'s; the same inputs (``rng`` an int)
    give the same texture.

    Returns
    -------
    FitResult
        ``texture`` (the :class:`spectex.SpectralTexture`), ``exemplar``
        (as analysed, after :func:`prepare_exemplar`), ``pixel_size``,
        ``notes`` (the input conversions), ``params`` (the fitted
        parameters: tile size and method, layer opacities, alpha gain, band
        gains, the band error of each step, tilings, ...) and ``seconds``.
    """
    method = check_choice("method", method, FIT_METHODS)
    if not isinstance(keep_one_off, bool):
        raise TypeError(f"keep_one_off must be True or False, got {keep_one_off!r}")
    for name, value in (("keep_lighting", keep_lighting), ("keep_perspective", keep_perspective)):
        if not isinstance(value, bool):
            raise TypeError(f"{name} must be True or False, got {value!r}")
    if method == "legacy":
        if photo_size is not None:
            raise ValueError("photo_size is not used by method='legacy' (give pixel_size)")
        return _fit_legacy(image, pixel_size=1.0 if pixel_size is None else pixel_size, layers=layers,
                           ratio=ratio, opacity=0.2 if opacity is None else opacity,
                           iterations=3 if iterations is None else iterations, tile_size=tile_size,
                           max_size=max_size, rng=rng, tiling=tiling, patch=patch, progress=progress)
    from ._auto import fit_auto

    return fit_auto(image, pixel_size=pixel_size, photo_size=photo_size, layers=layers, ratio=ratio,
                    opacity=opacity, iterations=iterations, tile_size=tile_size, max_size=max_size, rng=rng,
                    tiling=tiling, patch=patch, keep_one_off=keep_one_off, keep_lighting=keep_lighting,
                    keep_perspective=keep_perspective, progress=progress)


