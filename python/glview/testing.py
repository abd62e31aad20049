"""Screenshot tests in one line::

    from glview.testing import assert_matches

    def test_bunny(tmp_path):
        assert_matches(glview.render("bunny.obj", size=(320, 240)), "tests/golden/bunny.png")

The rule of ``glview --diff-against``: a missing stored picture is written and the test fails
(commit it after looking at it); a mean difference above ``threshold`` (in 1/255) fails and
writes the render and the difference image beside the stored one.
"""
from __future__ import annotations

import os
from typing import Dict, Union

import numpy as np

from . import Image, diff

PathLike = Union[str, "os.PathLike[str]"]


def _load_png(path: PathLike) -> np.ndarray:
    from ._glview import decode_png

    return decode_png(os.fspath(path))


def assert_matches(image: Image, stored: PathLike, threshold: float = 0.5) -> Dict[str, float]:
    """Compares ``image`` with the stored PNG; returns the difference numbers when it passes.
    On failure writes ``<stored>.actual.png`` and ``<stored>.diff.png`` and raises
    AssertionError naming them."""
    stored = os.fspath(stored)
    if not os.path.exists(stored):
        image.save(stored)
        raise AssertionError(
            f"{stored} did not exist: the render was written there; look at it and commit it"
        )
    expected = Image(_load_png(stored))
    base = stored[:-4] if stored.lower().endswith(".png") else stored
    if expected.color.shape != image.color.shape:
        image.save(base + ".actual.png")
        raise AssertionError(
            f"{stored} is {expected.width}x{expected.height}, the render "
            f"{image.width}x{image.height}; render written to {base}.actual.png"
        )
    picture, numbers = diff(image, expected)
    if numbers["mean"] > threshold:
        image.save(base + ".actual.png")
        picture.save(base + ".diff.png")
        raise AssertionError(
            f"{stored}: mean difference {numbers['mean']:.3f}/255 > {threshold} "
            f"(max {numbers['max']:.0f}); render in {base}.actual.png, difference in "
            f"{base}.diff.png"
        )
    return numbers
