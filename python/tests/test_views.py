"""A glTF file's cameras, scenes, material variants and lights as keywords (`camera=`,
`scene=`, `variant=`, `light="kit"|"file"`), against the command line's pictures and the
options they stand for."""
import base64
import json
import struct

import numpy as np
import pytest

import glview
from glview._glview import decode_png

CENTRE = (0.5, 0.25, -1.0)
DISTANCE = 3.5


def _box_gltf(path, material=0):
    """A unit box at CENTRE (material 0 unless given; variants Red → 1, Blue → 2), a second
    scene with the box in material 2, and a camera DISTANCE in front of the box on +Z looking
    down -Z (the orbit's yaw 0, pitch 0)."""
    pos, nrm, idx = [], [], []
    for axis in range(3):
        for s in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = s
            u = [0.0, 0.0, 0.0]
            u[(axis + 1) % 3] = 1.0
            v = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
            base = len(pos)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos.append([(n[k] + u[k] * a + v[k] * b) * 0.5 for k in range(3)])
                nrm.append(n)
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    blob = b"".join(struct.pack("<3f", *p) for p in pos + nrm) + struct.pack(f"<{len(idx)}I", *idx)
    nv = len(pos)
    prim = {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": material,
            "extensions": {"KHR_materials_variants": {"mappings": [
                {"material": 1, "variants": [0]}, {"material": 2, "variants": [1]}]}}}
    colour = lambda r, g, b: {"pbrMetallicRoughness": {"baseColorFactor": [r, g, b, 1.0],
                                                       "metallicFactor": 0.0}}
    doc = {
        "asset": {"version": "2.0"}, "scene": 0,
        "scenes": [{"name": "Box", "nodes": [0, 1]}, {"name": "Blue box", "nodes": [2]}],
        "nodes": [
            {"mesh": 0, "translation": CENTRE},
            {"camera": 0, "name": "cam-node",
             "translation": [CENTRE[0], CENTRE[1], CENTRE[2] + DISTANCE]},
            {"mesh": 1, "translation": CENTRE},
        ],
        "cameras": [{"name": "Front", "type": "perspective",
                     "perspective": {"yfov": 0.6, "znear": 0.25}}],
        "materials": [colour(0.8, 0.8, 0.8), colour(0.9, 0.05, 0.05), colour(0.05, 0.05, 0.9)],
        "meshes": [{"primitives": [prim]},
                   {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                    "material": 2}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3",
             "min": [-0.5] * 3, "max": [0.5] * 3},
            {"bufferView": 0, "byteOffset": nv * 12, "componentType": 5126, "count": nv,
             "type": "VEC3"},
            {"bufferView": 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
        "bufferViews": [{"buffer": 0, "byteLength": nv * 24},
                        {"buffer": 0, "byteOffset": nv * 24, "byteLength": len(idx) * 4}],
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(blob).decode()}],
        "extensionsUsed": ["KHR_materials_variants"],
        "extensions": {"KHR_materials_variants": {"variants": [{"name": "Red"}, {"name": "Blue"}]}},
    }
    path.write_text(json.dumps(doc))
    return path


def test_camera_keyword_is_the_orbit_options_and_the_cli(tmp_path, cli):
    model = _box_gltf(tmp_path / "box.gltf")
    through = glview.render(model, size=(96, 72), camera="Front")
    orbit = glview.render(model, size=(96, 72), yaw=0, pitch=0, distance=DISTANCE,
                          fov=np.degrees(0.6), near=0.25)
    assert np.array_equal(through.color, orbit.color)
    # The node's name selects it too, and the command line draws the same picture.
    out = tmp_path / "cli.png"
    cli(model, "--size", "96x72", "--camera", "cam-node", "-o", out)
    assert np.array_equal(through.color, decode_png(str(out)))


def test_scene_and_variant_keywords_equal_their_twin_files(tmp_path):
    model = _box_gltf(tmp_path / "box.gltf")
    for keyword, twin_material in ((dict(variant="Red"), 1), (dict(variant=1), 2),
                                   (dict(scene="Blue box"), 2)):
        twin = _box_gltf(tmp_path / f"m{twin_material}.gltf", material=twin_material)
        a = glview.render(model, size=(64, 48), **keyword)
        b = glview.render(twin, size=(64, 48))
        assert np.array_equal(a.color, b.color), keyword
    plain = glview.render(model, size=(64, 48))
    assert not np.array_equal(plain.color, a.color)


def test_unknown_names_raise_listing_the_file(tmp_path):
    model = _box_gltf(tmp_path / "box.gltf")
    with pytest.raises(Exception, match=r'no variant "Green": the file has 0 "Red", 1 "Blue"'):
        glview.render(model, size=(32, 32), variant="Green")
    with pytest.raises(Exception, match=r'no camera "Side": the file has 0 "Front"'):
        glview.render(model, size=(32, 32), camera="Side")


def _with_point_light(path, model):
    """The box file with a KHR_lights_punctual point light (40 cd, warm) beside the box."""
    doc = json.loads(model.read_text())
    doc["extensionsUsed"].append("KHR_lights_punctual")
    doc["extensions"]["KHR_lights_punctual"] = {"lights": [
        {"type": "point", "intensity": 40.0, "color": [1.0, 0.8, 0.6]}]}
    doc["nodes"].append({"name": "lamp", "extensions": {"KHR_lights_punctual": {"light": 0}},
                         "translation": [CENTRE[0] + 1.5, CENTRE[1] + 1.0, CENTRE[2] + 1.5]})
    doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    path.write_text(json.dumps(doc))
    return path


def test_light_keyword_chooses_the_files_lights_or_the_kit(tmp_path, cli):
    plain = _box_gltf(tmp_path / "box.gltf")
    lit = _with_point_light(tmp_path / "lamp.gltf", plain)
    for shading in ("phong", "pbr"):
        own = glview.render(lit, size=(64, 48), shading=shading)
        kit = glview.render(lit, size=(64, 48), shading=shading, light="kit")
        # The kit on the lamp file is the file without lights; its own light is not the kit.
        assert np.array_equal(kit.color, glview.render(plain, size=(64, 48), shading=shading).color)
        assert not np.array_equal(own.color, kit.color), shading
        assert np.array_equal(own.color, glview.render(lit, size=(64, 48), shading=shading,
                                                       light="file").color)
        out = tmp_path / f"cli-{shading}.png"
        cli(lit, "--size", "64x48", "--shading", shading, "-o", out)
        assert np.array_equal(own.color, decode_png(str(out)))
    with pytest.raises(Exception, match="light"):
        glview.render(plain, size=(32, 32), light="file")
