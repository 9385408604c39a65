"""Examples are tests and gallery pictures at once (the pygfx model).

Every script in ``examples/`` runs with its small ``TEST_ARGS`` and its
picture is compared with a golden image in ``tests/golden/`` (made on Mesa
llvmpipe and the CPU kernels): every pixel within one 8-bit step (1/255).
A failing comparison writes ``NAME.diff.png`` (the absolute difference,
amplified 16 times) beside the picture and names it. To make the golden
images anew after a deliberate change: ``SPECTEX_UPDATE_GOLDEN=1 pytest
tests/test_examples.py``, then look at them before committing.
"""

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest

from spectex import io

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
GOLDEN = Path(__file__).resolve().parent / "golden"
NAMES = sorted(p.stem for p in EXAMPLES.glob("*.py") if not p.stem.startswith("_"))
TOLERANCE = 1.0 / 255.0 + 1e-6


def _load(name):
    # The examples import their shared part as examples._gallery (the repository root is on
    # pytest's pythonpath, pyproject.toml), as they do when run from the root.
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def compare_with_golden(image: np.ndarray, golden: Path, out_dir: Path) -> None:
    """Assert ``image`` equals the golden picture within :data:`TOLERANCE`; write a diff image if not."""
    expected = io.read_image(golden)
    assert image.shape == expected.shape, f"{golden.name}: shape {image.shape}, golden {expected.shape}"
    diff = np.abs(image.astype(np.float64) - expected.astype(np.float64))
    if diff.max() > TOLERANCE:
        path = out_dir / f"{golden.stem}.diff.png"
        io.write_image(path, np.clip(diff * 16.0, 0.0, 1.0).astype(np.float32))
        pytest.fail(f"{golden.name}: {np.mean(diff > TOLERANCE):.2%} of the values differ by more than 1/255 "
                    f"(largest {diff.max() * 255:.1f}/255); difference image: {path}")


def test_every_example_has_a_golden_image():
    assert NAMES, "no examples found"
    missing = [n for n in NAMES if not (GOLDEN / f"{n}.png").is_file()]
    assert not missing or os.environ.get("SPECTEX_UPDATE_GOLDEN"), f"no golden image for {missing}"


@pytest.mark.parametrize("name", NAMES)
def test_example_matches_its_golden_image(name, tmp_path):
    module = _load(name)
    out = tmp_path / f"{name}.png"
    path = module.main([str(out), *module.TEST_ARGS])
    img = io.read_image(path)
    assert img.ndim == 3 and img.shape[2] == 3
    golden = GOLDEN / f"{name}.png"
    if os.environ.get("SPECTEX_UPDATE_GOLDEN"):
        GOLDEN.mkdir(exist_ok=True)
        io.write_image(golden, img)
    compare_with_golden(img, golden, tmp_path)


def test_the_comparison_fails_on_a_changed_picture(tmp_path):
    """The control: a picture two 8-bit steps off in one place fails and writes its difference image."""
    img = np.full((8, 8, 3), 0.5, np.float32)
    golden = io.write_image(tmp_path / "g.png", img)
    compare_with_golden(io.read_image(golden), golden, tmp_path)  # the same picture passes
    bad = io.read_image(golden).copy()
    bad[3, 4, 1] += 2.0 / 255.0
    with pytest.raises(pytest.fail.Exception, match="difference image"):
        compare_with_golden(bad, golden, tmp_path)
    assert (tmp_path / "g.diff.png").is_file()
