"""Stereo from Python: ``stereo=``, ``eye=`` and ``eyes=True`` draw what the command line's
``--stereo``/``--eye`` draw, pixel for pixel, and the composed picture is its eyes."""
import numpy as np
import pytest

import glview
from glview._glview import decode_png

VIEW = dict(size=(160, 120), yaw=30, pitch=20)


def test_eye_and_stereo_keywords_equal_the_command_line(tmp_path, cli):
    for extra, kw in [
        (["--stereo", "anaglyph"], dict(stereo="anaglyph")),
        (["--stereo", "rows", "--swap-eyes"], dict(stereo="rows", swap_eyes=True)),
        (["--stereo", "side-by-side", "--eye", "right"], dict(stereo="side-by-side", eye="right")),
    ]:
        out = tmp_path / "cli.png"
        cli("--size", "160x120", "--yaw", "30", "--pitch", "20", *extra, "-o", out)
        img = glview.render(**VIEW, **kw)
        assert np.array_equal(img.color, decode_png(str(out))), extra


def test_eyes_returns_the_pair_and_side_by_side_is_made_of_them():
    left, right = glview.render(**VIEW, stereo="side-by-side", eyes=True)
    assert left.color.shape == (120, 80, 4) and right.color.shape == (120, 80, 4)
    assert not np.array_equal(left.color, right.color)
    both = glview.render(**VIEW, stereo="side-by-side").color
    assert np.array_equal(both[:, :80], left.color)
    assert np.array_equal(both[:, 80:], right.color)
    # Depth too: each eye's buffer, as asked.
    l, r = glview.render(**VIEW, eyes=True, depth=True)
    assert l.depth.shape == (120, 160) and np.isfinite(l.depth).any()
    assert not np.array_equal(l.depth, r.depth)


def test_eyes_with_eye_is_refused():
    with pytest.raises(glview.OptionError, match="eyes"):
        glview.render(**VIEW, eyes=True, eye="left")
    with pytest.raises(glview.OptionError, match="stereo"):
        glview.render(**VIEW, stereo="sideways")
