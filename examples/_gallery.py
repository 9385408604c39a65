"""Shared by the examples: where their pictures go and how they are written.

Every example is a script with ``main(argv) -> Path`` that writes one
picture (by default into ``docs/images/``, where the README shows it) and a
``TEST_ARGS`` list: the arguments that make it small and quick, with which
``tests/test_examples.py`` runs it and compares its picture with a golden
image (the pygfx model: examples are tests and gallery pictures at once).
"""

from __future__ import annotations

import argparse
from pathlib import Path

DOCS_IMAGES = Path(__file__).resolve().parent.parent / "docs" / "images"


def parser(doc: str, default_name: str) -> argparse.ArgumentParser:
    """An argument parser with the output path as its optional first argument."""
    p = argparse.ArgumentParser(description=doc.splitlines()[0])
    p.add_argument("out", nargs="?", default=str(DOCS_IMAGES / default_name),
                   help=f"the picture to write (default: docs/images/{default_name})")
    return p
