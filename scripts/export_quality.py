#!/usr/bin/env python3
"""The measurement behind `glview export`'s default JPEG quality (docs/export.md): one
export of MODEL in PNG (the exact pictures) and one per JPEG quality, on the same grid;
per quality, the bytes per picture and the error of the JPEG pictures against the PNG ones
(mean over channels in 1/255, 99th percentile of the largest channel, share over 8/255).

    target/pyvenv/bin/python scripts/export_quality.py MODEL [--glview target/release/glview]
Needs Pillow and numpy (target/pyvenv after scripts/test_browser.sh).
"""
import argparse, base64, io, json, os, subprocess, sys, tempfile
import numpy as np
from PIL import Image


def pictures(page):
    html = open(page, encoding="utf-8").read()
    tag = '<script type="application/json" id="glview-data">'
    start = html.index(tag) + len(tag)
    data = json.loads(html[start:html.index("</script>", start)])
    out = {}
    for tier in ("phong", "pbr"):
        out[tier] = [base64.b64decode(u.split(";base64,", 1)[1]) for u in data[tier]]
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("model")
    ap.add_argument("--glview", default="target/debug/glview")
    ap.add_argument("--grid", default="12x1", help="YAWSxPITCHES")
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--qualities", default="50,70,80,85,90,95")
    a = ap.parse_args()
    ny, np_ = a.grid.split("x")
    tmp = tempfile.mkdtemp()

    def export(name, extra):
        page = os.path.join(tmp, name + ".html")
        subprocess.run([a.glview, "export", a.model, "-o", page, "--size", a.size,
                        "--yaw-steps", ny, "--pitch-steps", np_] + extra, check=True,
                       stderr=subprocess.DEVNULL)
        return pictures(page)

    exact = export("png", ["--png"])
    n = len(exact["phong"])
    print(f"| quality | kB per picture (Phong / PBR) | mean /255 | p99 /255 | > 8/255 |")
    print("|---|---|---|---|---|")
    png_kb = [sum(map(len, exact[t])) / n / 1e3 for t in ("phong", "pbr")]
    print(f"| PNG | {png_kb[0]:.1f} / {png_kb[1]:.1f} | 0 | 0 | 0 |")
    for q in a.qualities.split(","):
        pics = export("q" + q, ["--quality", q])
        kb = [sum(map(len, pics[t])) / n / 1e3 for t in ("phong", "pbr")]
        means, p99s, overs = [], [], []
        for t in ("phong", "pbr"):
            for p, j in zip(exact[t], pics[t]):
                x = np.asarray(Image.open(io.BytesIO(p)).convert("RGB"), dtype=np.int16)
                y = np.asarray(Image.open(io.BytesIO(j)).convert("RGB"), dtype=np.int16)
                d = np.abs(x - y)
                means.append(d.mean())
                m = d.max(axis=2)
                p99s.append(np.percentile(m, 99))
                overs.append((m > 8).mean())
        print(f"| {q} | {kb[0]:.1f} / {kb[1]:.1f} | {np.mean(means):.2f} (worst {max(means):.2f}) "
              f"| {np.mean(p99s):.0f} (worst {max(p99s):.0f}) | {100 * np.mean(overs):.2f} % |")


if __name__ == "__main__":
    sys.exit(main())
