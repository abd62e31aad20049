"""The Python API against the command line and against analytic truth."""
import json
import math
import pickle
import struct
import threading

import numpy as np
import pytest

import glview
from glview._glview import decode_png


def test_colour_equals_the_cli_png_pixel_for_pixel(tmp_path, bunny, cli):
    out = tmp_path / "cli.png"
    cli(bunny, "--size", "200x150", "--yaw", "-40", "--shading", "gouraud", "-o", out)
    img = glview.render(bunny, size=(200, 150), yaw=-40, shading="gouraud")
    assert img.color.dtype == np.uint8 and img.color.shape == (150, 200, 4)
    assert np.array_equal(img.color, decode_png(str(out)))
    assert img._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"
    img.save(tmp_path / "py.png")
    assert np.array_equal(decode_png(str(tmp_path / "py.png")), img.color)
    command = dict(img.text)["glview.command"]
    assert str(bunny) in command and "--shading gouraud" in command


def png_text(path):
    """A PNG file's tEXt chunks as (keyword, text) pairs, in file order."""
    data, pos, pairs = open(path, "rb").read(), 8, []
    while pos < len(data):
        n = struct.unpack(">I", data[pos:pos + 4])[0]
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"tEXt":
            k, v = body.split(b"\0", 1)
            pairs.append((k.decode("latin-1"), v.decode("latin-1")))
        pos += 12 + n
    return pairs


def test_text_is_made_on_first_use_and_is_the_cli_pngs(tmp_path, bunny, cli):
    out = tmp_path / "cli.png"
    cli(bunny, "--size", "120x90", "--yaw", "25", "-o", out)
    img = glview.render(bunny, size=(120, 90), yaw=25)
    assert not isinstance(img.__dict__["_text"], list), "made before it was asked for"
    assert img.text == png_text(out)
    assert png_text(_saved(tmp_path, img)) == img.text
    # Pickled (a dask result) with its text as pairs.
    assert pickle.loads(pickle.dumps(img)).text == img.text


def _saved(tmp_path, img):
    path = tmp_path / "py.png"
    img.save(path)
    return path


def test_pyrenders_scene_single_sided_equals_the_cli(tmp_path, shared, cli):
    # The benchmark's scene beside pyrender: one directional light, single-sided, from below
    # (where the open Stanford scan shows its inside when both sides are drawn).
    bunny = shared / "models" / "stanford-bunny" / "stanford-bunny.obj"
    out = tmp_path / "cli.png"
    args = dict(size=(160, 120), pitch=-40, light=["dir:-1,-2,-1.5"], single_sided=True)
    cli(bunny, "--size", "160x120", "--pitch", "-40", "--light", "dir:-1,-2,-1.5",
        "--single-sided", "-o", out)
    img = glview.render(bunny, **args)
    assert np.array_equal(img.color, decode_png(str(out)))
    assert "--single-sided" in dict(img.text)["glview.command"]
    both = glview.render(bunny, **{**args, "single_sided": False})
    assert np.count_nonzero(np.any(both.color != img.color, axis=-1)) > 0


def uv_sphere(seg: int = 192):
    rings = seg // 2
    th = np.linspace(0, math.pi, rings + 1)[:, None]
    ph = np.linspace(0, 2 * math.pi, seg + 1)[None, :]
    v = np.stack(
        [np.sin(th) * np.sin(ph), np.cos(th) * np.ones_like(ph), np.sin(th) * np.cos(ph)], -1
    ).reshape(-1, 3)
    idx = lambda r, k: r * (seg + 1) + k  # noqa: E731
    faces = []
    for r in range(rings):
        for k in range(seg):
            a, b, c, d = idx(r, k), idx(r + 1, k), idx(r + 1, k + 1), idx(r, k + 1)
            if r != 0:
                faces.append((a, b, d))
            if r != rings - 1:
                faces.append((b, c, d))
    return v, np.array(faces), v.astype(np.float32)


def camera(img):
    """Eye, forward, right, up and tan(fov/2) from the picture's `glview.camera` text."""
    words = dict(img.text)["glview.camera"].split()
    opt = {words[i][2:]: words[i + 1] for i in range(0, len(words) - 1, 2)}
    yaw, pitch = math.radians(float(opt["yaw"])), math.radians(float(opt["pitch"]))
    target = np.array([float(x) for x in opt["target"].split(",")])
    offset = np.array(
        [math.sin(yaw) * math.cos(pitch), math.sin(pitch), math.cos(yaw) * math.cos(pitch)]
    )
    eye = target + float(opt["distance"]) * offset
    fwd = -offset
    right = np.cross(fwd, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    return eye, fwd, right, up, math.tan(math.radians(float(opt["fov"])) / 2)


def test_depth_is_the_analytic_spheres_and_normals_point_out(tmp_path):
    v, f, n = uv_sphere()
    w, h = 160, 120
    # The analytic oracle is the full tessellation's: levels of detail would draw (and so
    # read back) a coarser sphere, as the colour does, so this call asks for none.
    img = glview.render({"vertices": v, "faces": f, "normals": n}, size=(w, h), depth=True,
                        normals=True, no_shadows=True, lod="off")
    assert img.depth.dtype == np.float32 and img.depth.shape == (h, w)
    eye, fwd, right, up, t = camera(img)
    ys, xs = np.mgrid[0:h, 0:w]
    nx = (2 * (xs + 0.5) / w - 1) * t * w / h
    ny = (1 - 2 * (ys + 0.5) / h) * t
    d = fwd + nx[..., None] * right + ny[..., None] * up  # z-depth t along d is the depth
    b = (d * eye).sum(-1)
    a = (d * d).sum(-1)
    disc = b * b - a * ((eye * eye).sum() - 1)
    inside = disc > 0.02 * a
    outside = disc < -0.02 * a
    z = (-b - np.sqrt(np.where(inside, disc, 0))) / a
    assert inside.sum() > 2000
    # A 192×96 tessellation lies within 1 − cos(π/96) ≈ 5e-4 of the unit sphere.
    assert np.abs(img.depth[inside] - z[inside]).max() < 2e-3
    assert np.isinf(img.depth[outside]).all()
    nrm = img.normals[inside]
    assert np.allclose(np.linalg.norm(nrm, axis=-1), 1, atol=1e-3)
    assert (nrm[:, 2] > 0).all()


def test_ids_cover_exactly_the_drawn_pixels(bunny):
    img = glview.render(bunny, size=(160, 120), transparent=True, ids=True)
    drawn = img.color[..., 3] > 0
    assert img.object_ids.dtype == np.int32
    assert np.array_equal(img.object_ids >= 0, drawn)
    assert np.array_equal(img.material_ids >= 0, drawn)
    assert drawn.sum() > 1000
    assert set(np.unique(img.object_ids)) <= {-1} | set(range(len(img.object_names)))


def test_trimesh_input_equals_file_input(bunny):
    trimesh = pytest.importorskip("trimesh")
    mesh = trimesh.load(bunny, process=False, force="mesh")
    a = glview.render(bunny, size=(160, 120), yaw=70)
    b = glview.render(mesh, size=(160, 120), yaw=70)
    assert np.array_equal(a.color, b.color)


def test_renderer_keeps_one_context_and_closes(bunny):
    with glview.Renderer(96, 64) as r:
        r.load(bunny)
        views = [r.render(yaw=y, depth=True) for y in (0, 90, 180)]
        assert all(np.isfinite(v.depth).any() for v in views)
        assert len({v.color.tobytes() for v in views}) == 3
        assert views[0].stats["frame"] >= 1
    with pytest.raises(glview.GlviewError, match="closed"):
        r.render()


def test_view_changes_upload_nothing_and_equal_a_fresh_picture(bunny):
    """A kept renderer's tier, exposure, bloom and terms are the view's: after the first
    picture they upload no scene and make no environment map (the profile counts both), and
    each picture equals the one a fresh renderer draws."""
    views = [
        dict(shading="pbr", ibl_size=16, irradiance_size=8, ibl_samples=8),
        dict(shading="pbr", exposure=1.0, ibl_size=16, irradiance_size=8, ibl_samples=8),
        dict(shading="phong"),
        dict(shading="pbr", bloom=0.3, ibl_size=16, irradiance_size=8, ibl_samples=8),
        dict(shading="pbr", terms="ibl-diffuse,ao", ibl_size=16, irradiance_size=8, ibl_samples=8),
        dict(yaw=80),
    ]
    kept = []
    with glview.Renderer(96, 64) as r:
        r.load(bunny)
        for i, v in enumerate(views):
            img = r.render(**v)
            profile = img.stats["profile"]
            assert profile["scene_uploads"] == (1 if i == 0 else 0), v
            assert profile["environments_made"] == (1 if i == 0 else 0), v
            kept.append(img.color)
    for v, color in zip(views, kept):
        with glview.Renderer(96, 64) as fresh:
            fresh.load(bunny)
            assert np.array_equal(fresh.render(**v).color, color), v


def test_bad_options_raise_naming_the_keyword(cli):
    p = cli("--pcf", "3", "-o", "x.png", check=False)
    assert p.returncode != 0
    with pytest.raises(glview.OptionError) as e:
        glview.render(pcf=3)
    assert "PCF taps must be 1, 4, 9 or 16" in str(e.value)
    assert "PCF taps must be 1, 4, 9 or 16" in p.stderr
    # The keyword's name and value, never a command-line flag.
    with pytest.raises(glview.OptionError, match="^fov: 200 is out of range: must be between 0 and 180$"):
        glview.render(fov=200)
    with pytest.raises(glview.OptionError, match="^yaw: expected a number, got 'north'$"):
        glview.render(yaw="north")
    with pytest.raises(glview.OptionError, match="^shading: expected one of phong, gouraud, pbr, got 'toon'$"):
        glview.render(shading="toon")
    with pytest.raises(glview.OptionError, match="^no_such_option: unknown option$"):
        glview.render(no_such_option=1)
    assert "--fov: 200 is out of range" in cli("--fov", "200", "-o", "x.png", check=False).stderr


def test_bad_files_and_arrays_raise_with_the_cli_message(tmp_path, cli):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    p = cli(bad, "-o", tmp_path / "x.png", check=False)
    assert p.returncode != 0
    with pytest.raises(glview.ModelError) as e:
        glview.render(bad)
    assert str(e.value) in p.stderr
    with pytest.raises(glview.ModelError, match="missing.obj"):
        glview.render(tmp_path / "missing.obj")
    with pytest.raises(glview.ModelError, match="face 0 refers to vertex 5"):
        glview.render(([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 5]]))
    with pytest.raises(TypeError):
        glview.render(42)


def test_a_renderer_used_from_two_threads_at_once_is_refused(bunny):
    # Deterministic: a second thread holds the renderer (as a render in progress does) until
    # this one has been refused; no sleeping, no race with how long a picture takes.
    r = glview.Renderer(64, 64)
    r.load(bunny)
    held, refused = threading.Event(), threading.Event()
    errors = []

    def holder():
        try:
            r.hold(lambda: (held.set(), refused.wait(30)))
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)

    t = threading.Thread(target=holder)
    t.start()
    assert held.wait(30)
    with pytest.raises(glview.BusyError, match="another thread"):
        r.render()
    refused.set()
    t.join()
    assert not errors
    # Released: the renderer draws again, from this thread.
    assert r.render().color.shape == (64, 64, 4)
    r.close()


def test_diff_and_testing_helper(tmp_path, bunny):
    from glview.testing import assert_matches

    a = glview.render(bunny, size=(96, 64))
    b = glview.render(bunny, size=(96, 64), yaw=60)
    picture, numbers = glview.diff(a, a)
    assert numbers["mean"] == 0 and numbers["max"] == 0
    picture, numbers = glview.diff(a, b)
    assert numbers["mean"] > 0.5 and 0 < numbers["ssim"] < 1
    # The difference image is the command line's: the pictures' size plus a scale strip.
    assert picture.width == a.width and picture.height > a.height
    assert numbers["model"] is None  # opaque pictures without ids do not say
    stored = tmp_path / "golden.png"
    with pytest.raises(AssertionError, match="did not exist"):
        assert_matches(a, stored)
    assert assert_matches(a, stored)["mean"] == 0
    with pytest.raises(AssertionError, match="mean difference"):
        assert_matches(b, stored)
    assert (tmp_path / "golden.actual.png").exists() and (tmp_path / "golden.diff.png").exists()


def test_comparison_tools_return_images_and_the_command_lines_numbers(tmp_path, bunny, cli):
    # diff_tiers is `--diff phong,pbr`: the same numbers as the CLI's JSON, over the whole
    # picture and over the model's pixels.
    out = tmp_path / "d.png"
    p = cli(bunny, "--diff", "phong,pbr", "--size", "96x72", "-o", out)
    want = json.loads((tmp_path / "d.json").read_text())
    picture, numbers = glview.diff_tiers(bunny, "phong,pbr", size=(96, 72))
    assert numbers["names"] == ("phong", "pbr")
    assert numbers["mean"] == pytest.approx(want["numbers"]["mean"])
    assert numbers["one_minus_ssim"] == pytest.approx(want["numbers"]["one_minus_ssim"])
    assert numbers["model"]["share_over_8"] == pytest.approx(want["model"]["over_8"])
    assert numbers["model_pixels"] == want["model_pixels"] > 500
    assert np.array_equal(picture.color, decode_png(str(out)))
    assert np.array_equal(numbers["a"].color, decode_png(str(tmp_path / "d-phong.png")))
    # diff of two renders with ids: the model numbers are over the union of their ids.
    a = glview.render(bunny, size=(96, 72), ids=True)
    b = glview.render(bunny, size=(96, 72), ids=True, yaw=40)
    _, n = glview.diff(a, b)
    union = (a.object_ids >= 0) | (b.object_ids >= 0)
    assert n["model_pixels"] == int(union.sum())
    assert n["model"]["mean"] > n["mean"]  # the background, equal in both, dilutes the whole
    # compare is `--compare`: the same picture as the CLI writes.
    img = glview.compare(bunny, "phong,pbr", size=(96, 72))
    cli(bunny, "--compare", "phong,pbr", "--size", "96x72", "-o", tmp_path / "c.png")
    assert np.array_equal(img.color, decode_png(str(tmp_path / "c.png")))
    assert img.width == 2 * 96
    # sheet: views by tiers, each cell 64×48 under its label.
    s = glview.sheet(bunny, "phong,pbr", views=3, size=(64, 48))
    cli("sheet", bunny, "--views", "3", "--size", "64x48", "-o", tmp_path / "s.png")
    assert np.array_equal(s.color, decode_png(str(tmp_path / "s.png")))
    assert s.width == 3 * 64 and s.height > 2 * 48
    with pytest.raises(TypeError, match="model file"):
        glview.compare(([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]))
    with pytest.raises(glview.OptionError):
        glview.compare(bunny, "phong,nonsense")


def test_linear_colour_is_the_picture_before_its_output_step(shared):
    duck = shared / "gltf-samples" / "Duck" / "Duck.glb"
    img = glview.render(
        duck, size=(96, 72), shading="pbr", no_bloom=True, tonemap="none", exposure=0,
        linear=True,
    )
    lin = img.linear
    assert lin.dtype == np.float32 and lin.shape == (72, 96, 3)
    # Without tone mapping or exposure the output step is sRGB encoding of the clamped value.
    c = np.clip(lin.astype(np.float64), 0, 1)
    srgb = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    encoded = np.round(srgb * 255).astype(np.int16)
    assert np.abs(encoded - img.rgb.astype(np.int16)).max() <= 1
    assert lin.max() > 1.0  # unclamped
