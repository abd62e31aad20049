"""glview's Python API beside pyrender on one job: the Stanford bunny, 24 views around it at
640×480, colour and depth arrays out, with and without a directional shadow; pictures per
second (median of 3 timed runs after a warm-up picture, in each of 3 rounds where the two
renderers' processes alternate; the table gives the median round), both in one table.

pyrender's scene is one directional light (from (1, 2, 1.5) towards the model), ambient 0.2,
and the mesh single-sided (pyrender's default material culls back faces). glview runs that
same scene (`light=["dir:-1,-2,-1.5"]`, `single_sided=True`, its default ambient 0.2) and, as
a second row, its own defaults: the three-light kit (key light with the shadow, fill,
headlight), which shades every pixel three times, and both sides of every face (the bunny
is an open scan).

    bash scripts/bench_python.sh       # makes both venvs, then runs this

A second table (glview alone, its defaults) times a call that changes only the exposure, the
tier or the bloom after a first picture, and the call after it that changes only the camera
(so both draw the same settings) — issue #41: an option of the view uploads nothing and
costs about what a camera change costs.

Each renderer runs in its own venv (pyrender needs numpy<2 and PyOpenGL on EGL), as a child
process of this script: `python bench_vs_pyrender.py glview|pyrender MODEL [options]` prints one
JSON line; without arguments it runs both children and prints the table.
"""
import json
import math
import os
import statistics
import subprocess
import sys
import time

W, H, VIEWS, RUNS, ROUNDS = 640, 480, 24, 3, 3
COLUMNS = ("shadow", "no shadow")


def timed(render_all):
    render_all()  # warm-up: context, upload, shader compiles
    times = []
    for _ in range(RUNS):
        t = time.perf_counter()
        render_all()
        times.append(time.perf_counter() - t)
    return VIEWS / statistics.median(times)


def bench_glview(model, options=False):
    import glview

    out = {}
    with glview.Renderer(W, H) as r:
        r.load(model)
        for opts, kit in ((PYRENDER_SCENE, "one light"), ({}, "kit")):
            row = out.setdefault(kit, {})
            for shadow in (True, False):

                def run():
                    for i in range(VIEWS):
                        img = r.render(
                            yaw=360 * i / VIEWS, depth=True, no_shadows=not shadow, **opts
                        )
                        assert img.depth is not None

                row["shadow" if shadow else "no shadow"] = timed(run)
        if options:
            out["options"] = option_changes(r)
    return out


CHANGES = 20


def option_changes(r):
    """The issue's measurement, glview's defaults, colour + depth: after a first picture, a
    call that changes only the exposure, the tier or the bloom (to the value named), beside
    a call that then changes only the camera (the same settings, so the same picture cost):
    median of 20 each, interleaved so the machine's load falls on both alike; and the
    scenes uploaded by the option changes (from each picture's stats; 0 expected)."""
    cases = {
        "exposure=1": ({"exposure": 0.0}, {"exposure": 1.0}),
        'shading="phong"': ({"shading": "pbr"}, {"shading": "phong"}),
        "bloom=0.5": ({"bloom": 0.0}, {"bloom": 0.5}),
    }
    times = {name: ([], []) for name in cases}
    uploads = dict.fromkeys(cases, 0)
    for i in range(CHANGES + 1):
        yaw = 360 * i / CHANGES
        for name, (before, after) in cases.items():
            r.render(depth=True, yaw=yaw, **before)
            t = time.perf_counter()
            img = r.render(depth=True, yaw=yaw, **after)
            option = time.perf_counter() - t
            t = time.perf_counter()
            r.render(depth=True, yaw=yaw + 7.5, **after)
            camera = time.perf_counter() - t
            if i > 0:  # the first round is the warm-up (programs, environment maps)
                times[name][0].append(option)
                times[name][1].append(camera)
                uploads[name] += img.stats["profile"]["scene_uploads"]
    return {
        name: {
            "option_ms": 1000 * statistics.median(o),
            "yaw_ms": 1000 * statistics.median(c),
            "uploads": uploads[name],
        }
        for name, (o, c) in times.items()
    }


# pyrender's light below travels from center + (1, 2, 1.5) r towards the center; its mesh
# material is single-sided.
PYRENDER_SCENE = {"light": ["dir:-1,-2,-1.5"], "single_sided": True}


def bench_pyrender(model):
    os.environ["PYOPENGL_PLATFORM"] = "egl"
    import numpy as np
    import pyrender
    import trimesh

    mesh = trimesh.load(model, force="mesh")
    out = {}
    renderer = pyrender.OffscreenRenderer(W, H)
    center, radius = mesh.bounding_sphere.primitive.center, mesh.bounding_sphere.primitive.radius
    for shadow in (True, False):
        scene = pyrender.Scene(ambient_light=[0.2, 0.2, 0.2])
        scene.add(pyrender.Mesh.from_trimesh(mesh))
        light = pyrender.DirectionalLight(color=np.ones(3), intensity=3.0)
        scene.add(light, pose=look_at(center + np.array([1.0, 2.0, 1.5]) * radius, center))
        cam = scene.add(pyrender.PerspectiveCamera(yfov=math.radians(45)), pose=np.eye(4))
        flags = pyrender.RenderFlags.SHADOWS_DIRECTIONAL if shadow else pyrender.RenderFlags.NONE

        def run():
            for i in range(VIEWS):
                yaw = 2 * math.pi * i / VIEWS
                eye = center + 2.6 * radius * np.array(
                    [math.sin(yaw) * 0.9, 0.42, math.cos(yaw) * 0.9]
                )
                scene.set_pose(cam, look_at(eye, center))
                color, depth = renderer.render(scene, flags=flags)
                assert depth.shape == (H, W)

        out["shadow" if shadow else "no shadow"] = timed(run)
    renderer.delete()
    return out


def look_at(eye, target):
    import numpy as np

    f = target - eye
    f = f / np.linalg.norm(f)
    r = np.cross(f, [0.0, 1.0, 0.0])
    r = r / np.linalg.norm(r)
    u = np.cross(r, f)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = r, u, -f, eye
    return m


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(os.path.dirname(here))
    model = os.path.join(repo, "..", "shared", "models", "stanford-bunny", "stanford-bunny.obj")
    if len(sys.argv) >= 3:
        if sys.argv[1] == "glview":
            print(json.dumps(bench_glview(sys.argv[2], options="options" in sys.argv[3:])))
        else:
            print(json.dumps(bench_pyrender(sys.argv[2])))
        return
    pythons = {
        "glview": os.path.join(repo, "target", "pyvenv", "bin", "python"),
        "pyrender": os.path.join(repo, "target", "pyrender-venv", "bin", "python"),
    }
    # The two alternate, ROUNDS times each, so a shared machine's load falls on both alike;
    # each cell is the median of the rounds (each round's figure a median of RUNS).
    rounds = {name: [] for name in pythons}
    for i in range(ROUNDS):
        for name, py in pythons.items():
            extra = ["options"] if name == "glview" and i == 0 else []
            p = subprocess.run([py, __file__, name, model, *extra], capture_output=True, text=True)
            if p.returncode != 0:
                sys.exit(f"{name} failed:\n{p.stderr}")
            rounds[name].append(json.loads(p.stdout.strip().splitlines()[-1]))
    p = {c: statistics.median(r[c] for r in rounds["pyrender"]) for c in COLUMNS}
    g = {
        kit: {c: statistics.median(r[kit][c] for r in rounds["glview"]) for c in COLUMNS}
        for kit in ("one light", "kit")
    }
    g["options"] = rounds["glview"][0]["options"]
    print(
        f"bunny, {VIEWS} views, {W}x{H}, colour + depth arrays; pictures/s (median of {ROUNDS} "
        f"alternating rounds, each the median of {RUNS} runs)"
    )
    print("| renderer | with shadow | without shadow |")
    print("| --- | ---: | ---: |")
    labels = {
        "one light": "glview, pyrender's scene (one light, single-sided)",
        "kit": "glview, its defaults (three lights, both sides)",
    }
    print(f"| pyrender | {p['shadow']:.1f} | {p['no shadow']:.1f} |")
    for kit, label in labels.items():
        print(f"| {label} | {g[kit]['shadow']:.1f} | {g[kit]['no shadow']:.1f} |")
    for kit, label in labels.items():
        print(
            f"| {label} ÷ pyrender | {g[kit]['shadow'] / p['shadow']:.1f}× | "
            f"{g[kit]['no shadow'] / p['no shadow']:.1f}× |"
        )
    print()
    print(
        f"glview, its defaults, colour + depth: a call changing one option after a first "
        f"picture, then one changing the camera; ms (median of {CHANGES})"
    )
    print("| option changed | ms | then a camera change (yaw) | scenes uploaded |")
    print("| --- | ---: | ---: | ---: |")
    for name, v in g["options"].items():
        print(f"| {name} | {v['option_ms']:.2f} | {v['yaw_ms']:.2f} | {v['uploads']} |")


if __name__ == "__main__":
    main()
