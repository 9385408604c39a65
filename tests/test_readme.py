"""The README's Python example runs as written (on a small gravel photo)."""

import re
from pathlib import Path

import numpy as np
import pytest

README = Path(__file__).resolve().parent.parent / "README.md"


def _python_blocks():
    return re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)


def test_readme_has_set_up_commands():
    text = README.read_text()
    for marker in ("<!-- main-command -->", "<!-- test-command -->"):
        block = text.split(marker, 1)[1]
        command = block.split("```bash\n", 1)[1].split("\n", 1)[0]
        assert command.startswith("python3 -m pip install ")


@pytest.mark.slow
def test_readme_python_example_runs(tmp_path, monkeypatch):
    from skimage import data

    from spectex import io

    gravel = data.gravel()[:96, :96]
    gravel = np.repeat(gravel[:, :, None], 3, axis=2) if gravel.ndim == 2 else gravel
    io.write_image(tmp_path / "gravel.jpg", gravel.astype(np.float32) / 255.0)
    monkeypatch.chdir(tmp_path)
    blocks = _python_blocks()
    assert blocks
    for code in blocks:
        exec(compile(code, str(README), "exec"), {"__name__": "readme"})
    assert (tmp_path / "ground.toml").is_file()
