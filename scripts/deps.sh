#!/usr/bin/env bash
# Installs the system packages glview needs at run time and for its tests, when missing.
# Debian/Ubuntu (apt-get); run as root or with sudo available. Safe to run again.
set -euo pipefail
pkgs=(
  libegl1 libegl-mesa0 libgl1-mesa-dri libgles2 # EGL headless on Mesa (llvmpipe)
  libosmesa6                                     # OSMesa fallback, loaded at run time
  libturbojpeg0                                  # glview serve's JPEG previews, loaded at run time
  libdav1d6                                      # EXT_texture_avif's AV1 decoder, loaded at run time
  libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0 # winit on X11
)
case "${1:-}" in
  --tests) pkgs+=(xvfb xdotool) ;; # window tests under a virtual X server
  # glview.exe's build (MinGW's linker and the C++ compiler of meshoptimizer) and its tests
  # under Wine (scripts/build_windows.sh, scripts/test_windows.sh; docs/windows.md).
  --windows) pkgs=(gcc-mingw-w64-x86-64 g++-mingw-w64-x86-64 wine wine64 xvfb xdotool) ;;
  # The pages of glview serve (also behind nginx) and glview export (scripts/test_browser.sh);
  # npm installs the export test's pinned SCORM runtime (a node from elsewhere, e.g.
  # NodeSource's, which bundles npm, is used as it is: Debian's npm package would conflict).
  --browser)
    # firefox-esr: the serve page's smoke test over WebDriver BiDi (test_serve_firefox.py).
    pkgs=(chromium firefox-esr nginx libxml2-utils) # xmllint: the SCORM manifest against ADL's schemas
    command -v npm >/dev/null || pkgs+=(nodejs npm)
    ;;
esac
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if ! command -v apt-get >/dev/null; then
  echo "glview: please install: ${missing[*]}" >&2
  exit 1
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "glview: installing ${missing[*]}" >&2
$sudo apt-get update -qq
# Wine's recommends (fonts, GStreamer, a 32-bit stack) are ~1 GB the tests never use.
recommends=()
[ "${1:-}" = --windows ] && recommends=(--no-install-recommends)
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${recommends[@]}" "${missing[@]}" >/dev/null
