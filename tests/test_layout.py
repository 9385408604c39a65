"""Where things live: one home per concept, old names that still work, no
private imports across packages, ``__all__`` everywhere (issue 18)."""

import importlib
import warnings

import numpy as np
import pytest

import spectex


# --------------------------------------------------------------------------
# Fitting has its own module
# --------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["fit", "fit_report", "FitResult", "prepare_exemplar", "structure_peak",
                                  "STRUCTURED_PEAK"])
def test_fitting_names_moved_from_analysis_warn(name):
    from spectex import analysis, fitting

    with pytest.warns(DeprecationWarning, match=rf"spectex\.fitting\.{name}"):
        old = getattr(analysis, name)
    assert old is getattr(fitting, name)


def test_fit_at_the_top_level_is_the_fitting_modules():
    from spectex import fitting

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert spectex.fit is fitting.fit


def test_layer_placement_is_the_one_rule_of_the_preset_and_the_fit():
    from spectex.fitting import _layers
    from spectex.texture import SpectralTexture, layer_placement

    # reference values of main before the rule had one home (paper_preset and _fit._layers)
    preset = SpectralTexture.paper_preset(np.zeros((8, 8, 4), np.float32)).layers
    assert [lay.offset for lay in preset] == [(0.0, 0.0), (30.021223, 48.568366), (301.997517, 93.287191),
                                              (290.273816, 1697.903006), (5280.0, 4720.0)]
    assert [lay.rotation for lay in preset] == [0.0, 137.507764, 275.015528, 52.523292, 190.031056]
    fitted = _layers(5, 4.0, 64, 0.01, 0.2)
    assert [lay.offset for lay in fitted] == [(0.0, 0.0), (0.97792, 1.58208), (7.82336, 2.41664),
                                              (5.98016, 34.97984), (86.50752, 77.33248)]
    assert [lay.rotation for lay in fitted] == [lay.rotation for lay in preset]
    for k, lay in enumerate(preset):
        assert layer_placement(k, lay.size) == (lay.offset, lay.rotation)
    # a control: another size gives other offsets
    assert layer_placement(1, 1.0)[0] != layer_placement(1, 2.0)[0]
    with pytest.raises(ValueError, match="k"):
        layer_placement(-1, 1.0)
