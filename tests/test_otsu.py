import numpy as np

from spectex._otsu import otsu


def test_otsu_splits_two_classes_between_them_and_says_how_well():
    rng = np.random.default_rng(0)
    two = np.concatenate([0.2 + 0.02 * rng.standard_normal(3000), 0.7 + 0.02 * rng.standard_normal(1000)])
    threshold, explained = otsu(two)
    assert (two[:3000] <= threshold).all() and (two[3000:] > threshold).all()  # every value in its class
    assert explained > 0.9  # two narrow classes: nearly all the variance
    # the control: one broad class has no split that explains much
    _, one = otsu(rng.random(4000))
    assert one < 0.8 and one < explained
    assert otsu(np.full(10, 0.5))[1] == 0.0  # a constant sample: nothing to explain
