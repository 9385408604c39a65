"""``spectex spectrum``: an image's radially averaged power spectrum and its slope."""

from __future__ import annotations

from . import _common

_WINDOWS = ("periodic", "hann", "none")
_SUFFIXES = (".png", ".pdf", ".svg")
_WEIGHTED = {"octave": "each octave alike", "none": "each ring alike"}


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "spectrum",
        help="plot an image's radially averaged power spectrum and its log-log slope",
        description=(
            "Compute the radially averaged power spectrum of an image (its Rec. 709 luma for "
            "colour; alpha is ignored), fit a line in log-log coordinates and print its slope "
            "(-beta for 1/f^beta noise; natural images are near -2). The fit counts every octave "
            "of the range alike (the frequency rings are evenly spaced, so an unweighted fit would "
            "follow the highest octave alone). With -o, plot it (matplotlib) with the fit and the "
            "mean power of each octave. The default window, periodic, analyses the image's "
            "periodic component (Moisan), which suits photographs and tiles alike; hann is the "
            "classical window, none takes the image as one period."
        ),
    )
    p.add_argument("image", help="image file (PNG, JPEG, ..., or .npy)")
    p.add_argument("-o", "--output", type=_common.output_name, default=None,
                   help="plot file (.png, .pdf or .svg)")
    p.add_argument("--window", choices=_WINDOWS, default="periodic",
                   help="leakage control (default: periodic)")
    p.add_argument("--fmin", type=_common.positive_float, default=None,
                   help="fit from this frequency, cycles per pixel (default: 2 cycles across the image)")
    p.add_argument("--fmax", type=_common.positive_float, default=0.25,
                   help="fit up to this frequency (default: 0.25, half the Nyquist frequency, "
                        "clear of sensor noise, JPEG blocks and 8-bit quantisation)")
    p.add_argument("--weighting", choices=("octave", "none"), default="octave",
                   help="octave: every octave counts alike; none: every ring counts alike, which "
                        "favours the high frequencies (default: octave)")
    p.set_defaults(func=run)


def run(args) -> int | None:
    import numpy as np

    from spectex._output import savefig
    from spectex.color import luma
    from spectex.io import atomic_path, check_output_path, read_image
    from spectex.spectrum import radial_power_spectrum, spectral_slope

    if args.fmax > 0.5:
        raise ValueError(f"--fmax must be at most 0.5 cycles per pixel (the Nyquist frequency), got {args.fmax:g}")
    if args.fmin is not None and args.fmin >= args.fmax:
        raise ValueError(f"--fmin must be below --fmax ({args.fmax:g}), got {args.fmin:g}")
    output = None if args.output is None else check_output_path("output", args.output, _SUFFIXES,
                                                                   inputs=[args.image])
    image = read_image(args.image, name="image")
    if min(image.shape[:2]) < 8:
        raise ValueError(f"image must be at least 8x8 pixels for a spectrum, got "
                         f"{image.shape[1]}x{image.shape[0]}")
    grey = luma(image)
    if float(grey.max() - grey.min()) == 0.0:
        raise ValueError(f"image is constant (every pixel {float(grey.flat[0]):g}): it has no spectrum")
    freqs, power = radial_power_spectrum(grey, window=args.window)
    fmin = 2.0 / min(grey.shape) if args.fmin is None else args.fmin
    if fmin >= args.fmax:
        raise ValueError(f"the fit range is empty: --fmin {fmin:.4g} (default: 2 cycles across the "
                         f"{min(grey.shape)}-pixel side) is not below --fmax {args.fmax:g}")
    fit = spectral_slope(freqs, power, fmin=fmin, fmax=args.fmax, weighting=args.weighting)
    h, w = grey.shape
    _common.report(f"{args.image}: {w}x{h}, slope {fit.slope:.3f} (beta {-fit.slope:.3f}), fit over "
                   f"{fit.fmin:.4g} to {fit.fmax:.4g} cycles/pixel ({_WEIGHTED[args.weighting]}), "
                   f"window {args.window}")
    if output is None:
        return 0
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.4), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    good = power > 0
    ax.loglog(freqs[good], power[good], ".", ms=3, color="0.3", label="radially averaged power")
    # One point per octave of the fit range: what a fit weighted per octave follows.
    edges = fit.fmin * 2.0 ** np.arange(0.0, np.log2(fit.fmax / fit.fmin) + 1.0)
    edges = np.minimum(edges, fit.fmax)
    cx, cy = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (freqs >= a) & (freqs <= b) & good
        if b > a and sel.any():
            cx.append(np.sqrt(a * b))
            cy.append(10.0 ** np.mean(np.log10(power[sel])))
    ax.loglog(cx, cy, "o", ms=6, mfc="none", color="C0", label="mean of each octave")
    fx = np.array([fit.fmin, fit.fmax])
    ax.loglog(fx, 10.0 ** (fit.slope * np.log10(fx) + fit.intercept), "-", color="C3", lw=2,
              label=f"fit: slope {fit.slope:.2f}")
    ax.axvline(0.5, color="0.7", lw=1, ls=":")
    ax.set_xlabel("radial frequency (cycles per pixel)")
    ax.set_ylabel("power")
    ax.set_title(f"{args.image} ({w}x{h}): slope {fit.slope:.2f}, beta {-fit.slope:.2f}", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower left", fontsize=9)
    fig.tight_layout()
    with atomic_path(output) as tmp:
        savefig(fig, tmp, format=output.suffix.lower()[1:])
    _common.report(f"wrote {output}")
    return 0
