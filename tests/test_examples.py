"""Every example runs (small sizes) and writes its picture."""

import importlib.util
from pathlib import Path

import pytest

from spectex import io

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name", sorted(p.stem for p in EXAMPLES.glob("*.py")))
def test_example_runs(name, tmp_path):
    module = _load(name)
    out = tmp_path / f"{name}.png"
    path = module.main([str(out), "--tile", "32"])
    img = io.read_image(path)
    assert img.ndim == 3 and img.shape[0] >= 32 and img.std() > 0.05
