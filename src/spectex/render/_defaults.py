"""The renderers' defaults, in a module of their own so that ``render/__init__``,
``cpu``, ``gl`` and ``viewer`` all import them from below (no import circle)."""

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
