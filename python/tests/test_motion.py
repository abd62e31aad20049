"""Animations from Python (issue #39): ``time=`` and ``animation=`` are the command line's
``--time`` and ``--animation`` (same specs, same pictures), and a kept ``glview.Renderer``
plays a sequence of moments with the model loaded and uploaded once."""
import pathlib

import numpy as np
import pytest

import glview
from glview._glview import decode_png

SIZE = (64, 48)
TIMES = (0.25, 0.5, 1.0)


REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def rigged():
    return REPO / "tests" / "data" / "khronos" / "motion" / "RiggedSimple.glb"


def test_time_and_animation_keywords_are_the_cli_options(tmp_path, rigged, cli):
    out = tmp_path / "cli.png"
    cli(rigged, "--size", "64x48", "--time", "0.5", "--animation", "0", "-o", out)
    img = glview.render(rigged, size=SIZE, time=0.5, animation="0")
    assert np.array_equal(img.color, decode_png(str(out)))
    command = dict(img.text)["glview.command"]
    assert "--time 0.5" in command and "--animation 0" in command
    # Another moment is another picture: the keyword reached the pose.
    assert not np.array_equal(glview.render(rigged, size=SIZE, time=1.0).color, img.color)


def test_animation_all_is_the_cli_option(tmp_path, cli):
    """Issue 50: ``animation="all"`` plays every animation together, as ``--animation all``;
    InterpolationTest's nine animations drive different cubes, so that is also its default."""
    model = REPO / "tests" / "data" / "khronos" / "motion" / "InterpolationTest.glb"
    out = tmp_path / "all.png"
    cli(model, "--size", "64x48", "--time", "1.3", "--animation", "all", "-o", out)
    img = glview.render(model, size=SIZE, time=1.3, animation="all")
    assert np.array_equal(img.color, decode_png(str(out)))
    assert np.array_equal(glview.render(model, size=SIZE, time=1.3).color, img.color)
    one = glview.render(model, size=SIZE, time=1.3, animation="2")
    assert not np.array_equal(one.color, img.color)


def test_a_bad_animation_raises_the_cli_message(rigged, cli):
    p = cli(rigged, "--time", "0", "--animation", "nope", "-o", "x.png", check=False)
    assert p.returncode != 0
    with pytest.raises(glview.OptionError) as e:
        glview.render(rigged, size=SIZE, time=0.0, animation="nope")
    assert "--animation nope" in str(e.value) and "no such animation" in str(e.value)
    assert str(e.value).split("--animation", 1)[1] in p.stderr


def test_a_renderer_plays_moments_with_one_upload(tmp_path, rigged, cli):
    """Each moment equals ``glview -o --time t``; the model is loaded and uploaded once for
    all of them (the profile counts uploads) and each moment poses the skinned mesh on the
    GPU: its joint matrices set, nothing uploaded again."""
    with glview.Renderer(*SIZE) as r:
        r.load(rigged)
        frames = [r.render(time=t) for t in TIMES]
    uploads = [f.stats["profile"]["scene_uploads"] for f in frames]
    assert uploads == [1, 0, 0]
    poses = [f.stats["profile"]["pose"] for f in frames]
    assert all(p["skinned"] == 1 and p["meshes"] == 0 and p["bytes"] == 0 for p in poses), poses
    for t, f in zip(TIMES, frames):
        out = tmp_path / f"t{t}.png"
        cli(rigged, "--size", "64x48", "--time", t, "-o", out)
        assert np.array_equal(f.color, decode_png(str(out))), t
    assert len({f.color.tobytes() for f in frames}) == len(TIMES)
