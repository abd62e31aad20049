"""`glview.export`: the same lesson page as `glview export` (byte for byte, from the same
options), and a SCORM 1.2 package whose manifest has the structure the SCORM 1.2 Content
Aggregation Model requires (checked here element by element: the ADL schema files are not
shipped with the repository)."""
import zipfile
import xml.etree.ElementTree as ET

import pytest

import glview

CP = "{http://www.imsproject.org/xsd/imscp_rootv1p1p2}"
ADLCP = "{http://www.adlnet.org/xsd/adlcp_rootv1p2}"
MD = "{http://www.imsglobal.org/xsd/imsmd_rootv1p2p1}"


def test_export_writes_the_page_the_command_line_writes(bunny, cli, tmp_path):
    page, zip_path = tmp_path / "py.html", tmp_path / "py.zip"
    info = glview.export(bunny, page, yaw_steps=3, pitch_steps=1, size=(64, 48),
                         title="Bunny", caption="Look & see", scorm=zip_path)
    assert info["views"] == 3 and info["bytes"] == page.stat().st_size
    assert info["title"] == "Bunny"
    cli("export", bunny, "-o", tmp_path / "cli.html", "--yaw-steps", "3", "--pitch-steps", "1",
        "--size", "64x48", "--title", "Bunny", "--caption", "Look & see",
        "--scorm", tmp_path / "cli.zip")
    assert page.read_bytes() == (tmp_path / "cli.html").read_bytes()
    assert zip_path.read_bytes() == (tmp_path / "cli.zip").read_bytes()
    with pytest.raises(glview.GlviewError, match="yaw_steps"):
        glview.export(bunny, tmp_path / "x.html", yaw_steps=-2)
    with pytest.raises(glview.GlviewError, match="yaw-steps"):
        glview.export(bunny, tmp_path / "x.html", yaw_steps=0)


def test_scorm_manifest_has_the_structure_scorm_12_requires(bunny, tmp_path):
    zip_path = tmp_path / "lesson.zip"
    glview.export(bunny, tmp_path / "lesson.html", yaw_steps=2, pitch_steps=1, size=(32, 24),
                  title="A <title> & more", caption="Describe it", scorm=zip_path)
    with zipfile.ZipFile(zip_path) as z:
        assert z.testzip() is None
        names = set(z.namelist())
        root = ET.fromstring(z.read("imsmanifest.xml"))
    # CAM 1.2 §2.3: <manifest> in the IMS CP 1.1.2 namespace at the package's root, with
    # metadata naming ADL SCORM 1.2, organizations and resources.
    assert root.tag == CP + "manifest" and root.get("identifier")
    assert root.find(f"{CP}metadata/{CP}schema").text == "ADL SCORM"
    assert root.find(f"{CP}metadata/{CP}schemaversion").text == "1.2"
    general = root.find(f"{CP}metadata/{MD}lom/{MD}general")
    assert general.find(f"{MD}title/{MD}langstring").text == "A <title> & more"
    assert general.find(f"{MD}description/{MD}langstring").text == "Describe it"
    ids = [e.get("identifier") for e in root.iter() if e.get("identifier") is not None]
    assert len(ids) == len(set(ids)), "identifiers are unique (xs:ID)"
    orgs = root.find(f"{CP}organizations")
    org_ids = [o.get("identifier") for o in orgs.findall(f"{CP}organization")]
    assert orgs.get("default") in org_ids
    resources = {r.get("identifier"): r for r in root.findall(f"{CP}resources/{CP}resource")}
    items = list(orgs.iter(f"{CP}item"))
    assert items and all(i.find(f"{CP}title").text for i in items)
    for item in items:
        r = resources[item.get("identifierref")]
        # A launchable item references a SCO (the page calls the LMS's API) whose href is a
        # file of the package.
        assert r.get("type") == "webcontent" and r.get(ADLCP + "scormtype") == "sco"
        assert r.get("href") in names
        assert {f.get("href") for f in r.findall(f"{CP}file")} <= names
    assert "index.html" in names


def test_live_export_is_the_command_lines_and_names_a_missing_build(bunny, cli, tmp_path):
    # A stand-in browser build: the page carries its bytes (the browser's side is
    # python/tests_web). Python's live page is the command line's, byte for byte.
    web = tmp_path / "web"
    (web / "no-modules").mkdir(parents=True)
    (web / "glview_web_bg.wasm").write_bytes(b"\0asm stand-in")
    (web / "no-modules" / "glview_web.js").write_text("let wasm_bindgen;")
    page = tmp_path / "py.html"
    glview.export(bunny, page, yaw_steps=2, pitch_steps=1, size=(32, 24), live=True, web_dir=web)
    cli("export", bunny, "-o", tmp_path / "cli.html", "--yaw-steps", "2", "--pitch-steps", "1",
        "--size", "32x24", "--live", "--web-dir", web)
    assert page.read_bytes() == (tmp_path / "cli.html").read_bytes()
    assert b"'wasm-unsafe-eval'" in page.read_bytes()
    with pytest.raises(glview.GlviewError, match="build_web.sh"):
        glview.export(bunny, tmp_path / "x.html", yaw_steps=2, pitch_steps=1, live="only",
                      web_dir=tmp_path)
    with pytest.raises(glview.GlviewError, match="live"):
        glview.export(bunny, tmp_path / "x.html", live="sometimes")
