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
def test_fitting_names_live_in_fitting_only(name):
    from spectex import analysis, fitting

    assert hasattr(fitting, name) and not hasattr(analysis, name)


def test_fit_at_the_top_level_is_the_fitting_modules():
    from spectex import fitting

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert spectex.fit is fitting.fit


def test_layer_placement_is_the_one_rule_of_the_preset_and_the_fit():
    from spectex.fitting._core import _layers
    from spectex.texture import SpectralTexture, layer_placement

    # reference values of main before the rule had one home (paper_preset and _fit._layers)
    preset = SpectralTexture.paper_preset(np.zeros((8, 8, 4), np.float32)).layers
    assert [lay.offset for lay in preset[:5]] == [(0.0, 0.0), (30.021223, 48.568366), (301.997517, 93.287191),
                                                  (290.273816, 1697.903006), (5280.0, 4720.0)]
    assert [lay.rotation for lay in preset[:5]] == [0.0, 137.507764, 275.015528, 52.523292, 190.031056]
    fitted = _layers(5, 4.0, 64, 0.01, 0.2)
    assert [lay.offset for lay in fitted] == [(0.0, 0.0), (0.97792, 1.58208), (7.82336, 2.41664),
                                              (5.98016, 34.97984), (86.50752, 77.33248)]
    assert [lay.rotation for lay in fitted] == [lay.rotation for lay in preset[:5]]
    for k, lay in enumerate(preset):
        assert layer_placement(k, lay.size) == (lay.offset, lay.rotation)
    # a control: another size gives other offsets
    assert layer_placement(1, 1.0)[0] != layer_placement(1, 2.0)[0]
    with pytest.raises(ValueError, match="k"):
        layer_placement(-1, 1.0)


# --------------------------------------------------------------------------
# No private imports across packages
# --------------------------------------------------------------------------

import ast  # noqa: E402
import pathlib  # noqa: E402

SRC = pathlib.Path(spectex.__file__).parent
ROOT = SRC.parent


def _private(part: str) -> bool:
    return part.startswith("_") and not part.startswith("__")


def _modules():
    """(dotted name, package the module belongs to, path) of every module of spectex."""
    for path in sorted(SRC.rglob("*.py")):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        if parts[-1] == "__init__":
            yield ".".join(parts[:-1]), ".".join(parts[:-1]), path
        else:
            yield ".".join(parts), ".".join(parts[:-1]), path


def _inside(package: str, owner: str) -> bool:
    return package == owner or package.startswith(owner + ".")


def private_imports():
    """Imports of a private module or name that belongs to another package.

    A private module ``a.b._m`` (or anything below it) may be imported from
    inside package ``a.b``, its subpackages included (so ``spectex._validate``
    serves all of spectex). A private name ``_x`` of a module ``a.b.m`` may be
    imported only by modules of the same package ``a.b``; a private name of a
    package ``a.b`` (from its ``__init__``) from inside ``a.b``.
    """
    found = []
    for name, package, path in _modules():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets = [(alias.name, None) for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[:len(package.split(".")) - (node.level - 1)]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                targets = [(target, alias.name) for alias in node.names]
            else:
                continue
            for target, imported in targets:
                if not target.split(".")[0] == "spectex":
                    continue
                parts = target.split(".")
                bad = None
                for i, part in enumerate(parts):
                    if _private(part):
                        if not _inside(package, ".".join(parts[:i])):
                            bad = target
                        break
                else:
                    if imported is not None and _private(imported):
                        if (ROOT / pathlib.Path(*parts)).is_dir():  # a package's private module or name
                            ok = _inside(package, target)
                        else:  # a private name of a module: its own package only
                            ok = package == target.rpartition(".")[0]
                        if not ok:
                            bad = f"{target}.{imported}"
                if bad:
                    found.append(f"{name}:{node.lineno} imports {bad}")
    return found


def test_no_module_imports_another_packages_private_names():
    assert private_imports() == []


def test_the_private_import_check_sees_a_private_import(tmp_path, monkeypatch):
    # a control: a module that reaches into another package's private module is found
    fake = tmp_path / "spectex"
    (fake / "tiles").mkdir(parents=True)
    (fake / "spectral").mkdir()
    (fake / "__init__.py").write_text("from ._validate import check_int\n")
    (fake / "tiles" / "__init__.py").write_text("from ..spectral._synthesis import PARALLEL_MIN\n"
                                                "from ..spectral import _helper\n"
                                                "from ..metrics import _luma\n")
    (fake / "spectral" / "__init__.py").write_text("from ._synthesis import band_limit, _private_ok\n")
    import sys

    monkeypatch.setattr(sys.modules[__name__], "SRC", fake)
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)
    found = private_imports()
    assert found == ["spectex.tiles:1 imports spectex.spectral._synthesis",
                     "spectex.tiles:2 imports spectex.spectral._helper",
                     "spectex.tiles:3 imports spectex.metrics._luma"]


# --------------------------------------------------------------------------
# __all__ everywhere, and the public names at the top level
# --------------------------------------------------------------------------

def _public_modules():
    for name, _package, path in _modules():
        if not any(_private(part) for part in name.split(".")) and not name.endswith("__main__"):
            yield name, path


def test_every_public_module_has_an_all_whose_names_exist():
    missing = []
    for name, path in _public_modules():
        tree = ast.parse(path.read_text())
        has_all = any(isinstance(node, (ast.Assign, ast.AnnAssign)) and any(
            isinstance(t, ast.Name) and t.id == "__all__"
            for t in (node.targets if isinstance(node, ast.Assign) else [node.target]))
            for node in tree.body)
        if not has_all:
            missing.append(name)
            continue
        module = importlib.import_module(name)
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no name in an __all__ warns
            for item in module.__all__:
                assert getattr(module, item, None) is not None, f"{name}.__all__ names {item!r}, which is not there"
    assert missing == []


def test_help_lists_the_public_names():
    import pydoc

    text = pydoc.render_doc(spectex, renderer=pydoc.plaintext)
    for entry in ("class SpectralTexture", "class Layer", "class Camera", "class Atmosphere", "fit(image",
                  "make_tile(shape", "make_seamless(image", "read_image(path", "render (package)",
                  "spectrum\n", "fitting (package)", "periodic\n"):
        assert entry in text, entry
    assert spectex.Layer is importlib.import_module("spectex.texture").Layer
    assert spectex.Camera is importlib.import_module("spectex.shading.camera").Camera
    assert callable(spectex.render.render)
    with pytest.raises(AttributeError, match="no_such_name"):
        getattr(spectex, "no_such_name")  # noqa: B009 (the attribute access is the test)


def _api_top_level_names(text: str) -> set[str]:
    """The names in the first column of docs/api.md's "The top level" table."""
    section = text.split("## The top level", 1)[1].split("\n## ", 1)[0]
    return {line.split("`")[1] for line in section.splitlines() if line.startswith("| `")}


def test_docs_api_lists_the_top_level_names():
    text = (ROOT.parent / "docs" / "api.md").read_text()
    names = {n for n in spectex.__all__ if n not in spectex._SUBMODULES}
    assert _api_top_level_names(text) == names
    for module in spectex._SUBMODULES:  # every public module has its row
        assert f"`spectex.{module}`" in text, module
    # The control: a table without one name, or with an extra one, is seen.
    assert _api_top_level_names(text.replace("| `fit` |", "| fit |")) != names
    assert _api_top_level_names(text.replace("| `Layer` |", "| `Layer` |\n| `render` | x |")) != names
