#!/usr/bin/env bash
# glview.exe under Wine on Xvfb, held to the Linux binary (docs/windows.md, "Tests"):
#
#   bash scripts/test_windows.sh [GLVIEW.EXE] [LINUX-GLVIEW]
#
# Both binaries draw on the same Mesa llvmpipe (Wine maps WGL onto GLX), so their pictures
# must be equal pixel for pixel: any difference is a bug of the Windows paths (the context's
# version, a dialect chosen differently, a path read wrongly), not a rasteriser's. Needs
# Debian's wine, xvfb and xdotool (installed when missing) and a throw-away Wine prefix. The
# test-only bcryptprimitives.dll (../shared/tools/cross-toolchain.sh: Wine 8.0 lacks the
# ProcessPrng that Rust's std imports) is copied next to a *copy* of the .exe, never beside
# the built one.
set -euo pipefail
cd "$(dirname "$0")/.."
exe=$(realpath "${1:-target/x86_64-pc-windows-gnu/release/glview.exe}")
linux=$(realpath "${2:-target/debug/glview}")
shared=${GLVIEW_SHARED:-../shared}
cross_dir=${GLVIEW_CROSS_DIR:-/opt/glview-cross}
sudo=; [ "$(id -u)" = 0 ] || sudo=sudo
missing=$(for p in wine wine64 xvfb xdotool; do
  dpkg-query -W -f='${Status}\n' "$p" 2>/dev/null | grep -q 'ok installed' || echo "$p"; done)
if [ -n "$missing" ]; then
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi
dll=$cross_dir/wine/bcryptprimitives.dll
[ -f "$dll" ] || GLVIEW_SHARED=$shared GLVIEW_CROSS_DIR=$cross_dir bash scripts/cross_env.sh >/dev/null
work=$(mktemp -d /tmp/glview-wine.XXXXXX)
xvfb_pid=
cleanup() {
  [ -z "$xvfb_pid" ] || kill "$xvfb_pid" 2>/dev/null || true
  WINEPREFIX=$work/prefix wineserver -k 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
mkdir -p "$work/bin" "$work/out"
cp "$exe" "$work/bin/glview.exe"
cp "$dll" "$work/bin/"
export WINEPREFIX=$work/prefix WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
# A display of our own: the first free number from 90.
n=90
while [ -e "/tmp/.X11-unix/X$n" ] || [ -e "/tmp/.X$n-lock" ]; do n=$((n + 1)); done
Xvfb ":$n" -screen 0 1024x768x24 -nolisten tcp >/dev/null 2>&1 &
xvfb_pid=$!
export DISPLAY=":$n"
t0=$(date +%s)
wineboot -i >/dev/null 2>&1
echo "test_windows: Wine prefix ready in $(($(date +%s) - t0)) s"
win() { winepath -w "$1"; }
# glview.exe with Windows paths: the arguments that name files are converted by the caller.
wexe() { wine "$work/bin/glview.exe" "$@"; }
fails=0
pass() { echo "ok   $1"; }
fail() { echo "FAIL $1"; fails=$((fails + 1)); }
same() { # NAME LINUX.png WINDOWS.png [--opaque]: pixel for pixel (png_diff.py)
  if python3 scripts/png_diff.py "$2" "$3" ${4:-} >"$work/cmp.txt" 2>&1; then pass "$1"; else
    fail "$1: $(cat "$work/cmp.txt") (pixels differing, max difference, size)"; fi
}
size=(--size 160x120)
o=$work/out
# 1. Both tiers, on the default context and on an emulated GL 2.1 driver.
for env in default gl21; do
  vars=() gl=()
  # On the override Linux's `--gl auto` finds GL ES 3.0 through EGL, which WGL lacks: both
  # ask for 2.1, the legacy tier an old driver gets.
  [ "$env" = gl21 ] && vars=(MESA_GL_VERSION_OVERRIDE=2.1 MESA_GLSL_VERSION_OVERRIDE=120) gl=(--gl 2.1)
  for tier in phong pbr; do
    name=$env-$tier
    env "${vars[@]}" "$linux" models/box_on_floor.obj "${size[@]}" "${gl[@]}" --shading "$tier" -o "$o/$name-linux.png"
    if env "${vars[@]}" wine "$work/bin/glview.exe" "$(win models/box_on_floor.obj)" "${size[@]}" "${gl[@]}" \
      --shading "$tier" -o "$(win "$o/$name-win.png")" 2>"$o/$name.err"; then
      same "$name: box_on_floor.obj" "$o/$name-linux.png" "$o/$name-win.png"
    else fail "$name: glview.exe failed: $(tail -1 "$o/$name.err")"; fi
  done
done
# The GL 2.1 override really reached the context: --info names it.
info=$(env MESA_GL_VERSION_OVERRIDE=2.1 MESA_GLSL_VERSION_OVERRIDE=120 wine "$work/bin/glview.exe" --info 2>&1 || true)
if grep -q "^GLSL: 1.20 (dialect GLSL 1.20)" <<<"$info"; then pass "gl21: the context is GLSL 1.20, auto chose it"
else fail "gl21: --info says $(grep GLSL <<<"$info")"; fi
# 2. A textured glTF (the built-in scene too: no file at all).
gltf=tests/data/khronos/TextureEncodingTest/TextureEncodingTest.glb

"$linux" "$gltf" "${size[@]}" --shading pbr -o "$o/gltf-linux.png"
wexe "$(win "$gltf")" "${size[@]}" --shading pbr -o "$(win "$o/gltf-win.png")" 2>/dev/null || true
same "textured glTF $(basename "$gltf")" "$o/gltf-linux.png" "$o/gltf-win.png"
"$linux" "${size[@]}" -o "$o/builtin-linux.png"
wexe "${size[@]}" -o "$(win "$o/builtin-win.png")" 2>/dev/null || true
same "the built-in scene" "$o/builtin-linux.png" "$o/builtin-win.png"
# 3. A hostile OBJ: the same one-line error, naming the file as each system spells it.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n' >"$o/bad.obj"
lerr=$("$linux" "$o/bad.obj" "${size[@]}" -o "$o/bad.png" 2>&1 >/dev/null || true)
werr=$(wexe "$(win "$o/bad.obj")" "${size[@]}" -o "$(win "$o/bad.png")" 2>&1 >/dev/null | tr -d '\r' || true)
wpath=$(win "$o/bad.obj")
if [ -n "$lerr" ] && [ "$(wc -l <<<"$werr")" = 1 ] && [ "${werr//"$wpath"/FILE}" = "${lerr//"$o/bad.obj"/FILE}" ] &&
  grep -qF "$wpath" <<<"$werr"; then pass "hostile OBJ: $werr"; else
  fail "hostile OBJ: linux said '$lerr', windows said '$werr'"; fi
# 4. A path with a space and non-ASCII letters.
mkdir -p "$o/models dir"
cp models/box_on_floor.obj "$o/models dir/Модель ü.obj"
cp models/box_on_floor.mtl "$o/models dir/"
wexe "$(win "$o/models dir/Модель ü.obj")" "${size[@]}" -o "$(win "$o/models dir/Bild ä.png")" 2>/dev/null || true
"$linux" models/box_on_floor.obj "${size[@]}" -o "$o/plain-linux.png"
same "a path with a space and non-ASCII letters" "$o/plain-linux.png" "$o/models dir/Bild ä.png"
# 5. The other headless modes, through the same hidden WGL window: batch (its pictures
# pixel-equal), sheet, export with SCORM, and serve answering its page.
printf '%s --size 160x120 -o %s\n%s --size 160x120 --shading pbr -o %s\n' \
  "$(win models/box_on_floor.obj)" "$(win "$o/batch-1.png")" "$(win models/box_on_floor.obj)" \
  "$(win "$o/batch-2.png")" | sed 's/\\/\\\\/g' >"$o/jobs.txt"
if wexe batch "$(win "$o/jobs.txt")" >/dev/null 2>"$o/batch.err"; then
  same "batch: phong" "$o/default-phong-linux.png" "$o/batch-1.png"
  same "batch: pbr" "$o/default-pbr-linux.png" "$o/batch-2.png"
else fail "batch: $(tail -1 "$o/batch.err")"; fi
if wexe sheet "$(win models/box_on_floor.obj)" --views 2 --tiers phong,pbr --size 80x60 \
  -o "$(win "$o/sheet.png")" >/dev/null 2>"$o/sheet.err" && [ -s "$o/sheet.png" ]; then pass "sheet"
else fail "sheet: $(tail -1 "$o/sheet.err")"; fi
if wexe export "$(win models/box_on_floor.obj)" --yaw-steps 4 --pitch-steps 1 --size 80x60 \
  -o "$(win "$o/page.html")" --scorm "$(win "$o/page.zip")" >/dev/null 2>"$o/export.err" &&
  grep -q "<html" "$o/page.html" && [ -s "$o/page.zip" ]; then pass "export with SCORM"
else fail "export: $(tail -1 "$o/export.err")"; fi
port=$((20000 + RANDOM % 20000))
wexe serve "$(win models/box_on_floor.obj)" --bind "127.0.0.1:$port" --no-token >"$o/serve.out" 2>&1 &
spid=$!
ok=
for _ in $(seq 100); do
  if curl -sf "http://127.0.0.1:$port/" -o "$o/serve.html" 2>/dev/null; then ok=1; break; fi
  sleep 0.2
done
if [ -n "$ok" ] && grep -qi "<html" "$o/serve.html"; then pass "serve answers its page"
else fail "serve: $(tail -2 "$o/serve.out")"; fi
kill "$spid" 2>/dev/null || true
wait "$spid" 2>/dev/null || true
# The id of glview's visible window, waited for up to a minute (empty: none came).
find_window() { timeout 60 xdotool search --sync --onlyvisible --name "glview" 2>/dev/null | head -1; }
# Sends Escape to window $1 and waits up to 20 s for process $2 to end: `closed` is its exit
# code, or "running" when it did not close (it is killed then).
close_window() {
  xdotool windowfocus --sync "$1" 2>/dev/null || true
  xdotool key Escape
  for _ in $(seq 100); do kill -0 "$2" 2>/dev/null || break; sleep 0.2; done
  closed=0
  if kill -0 "$2" 2>/dev/null; then
    kill "$2"
    wait "$2" 2>/dev/null || true
    closed=running
  else
    wait "$2" || closed=$?
  fi
}
# 6. The window: it opens, ArrowRight ×2 turns it as --keys does headless, Escape closes it.
view=(--size 320x240 --yaw 30 --pitch 15)
mkdir -p "$o/shots"
wexe "$(win models/box_on_floor.obj)" "${view[@]}" --stats --screenshot-dir "$(win "$o/shots")" \
  >"$o/window.out" 2>&1 &
wpid=$!
wid=$(find_window)
if [ -n "$wid" ]; then
  pass "the window opens"
  xdotool windowfocus --sync "$wid" 2>/dev/null || true
  sleep 1
  xdotool key Right
  sleep 0.5
  xdotool key Right
  sleep 1
  xdotool key F12
  for _ in $(seq 50); do ls "$o/shots"/*.png >/dev/null 2>&1 && break; sleep 0.2; done
  sleep 0.5
  close_window "$wid" "$wpid"
  case $closed in
    0) pass "Escape closes the window (exit 0)" ;;
    running) fail "Escape did not close the window" ;;
    *) fail "the window exited with $closed" ;;
  esac
  shot=$(ls "$o/shots"/*.png 2>/dev/null | head -1)
  "$linux" models/box_on_floor.obj "${view[@]}" --keys "Right Right" -o "$o/keys-linux.png"
  if [ -n "$shot" ]; then same "ArrowRight ×2 in the window = --keys 'Right Right' headless" \
    "$o/keys-linux.png" "$shot" --opaque
  else fail "no screenshot from the window: $(tail -3 "$o/window.out")"; fi
else
  fail "no window appeared: $(tail -3 "$o/window.out")"
  kill "$wpid" 2>/dev/null || true
fi
# 7. The window on an emulated GL 2.1 driver: WGL gives the 2.1 context, the first frame comes.
MESA_GL_VERSION_OVERRIDE=2.1 MESA_GLSL_VERSION_OVERRIDE=120 wine "$work/bin/glview.exe" \
  "$(win models/box_on_floor.obj)" --size 320x240 --stats >"$o/window21.out" 2>&1 &
wpid=$!
wid=$(find_window)
if [ -n "$wid" ]; then
  for _ in $(seq 50); do grep -q '"frame":1' "$o/window21.out" && break; sleep 0.2; done
  close_window "$wid" "$wpid"
  if [ "$closed" = 0 ] && grep -q '"frame":1' "$o/window21.out"; then
    pass "the window on the GL 2.1 override: a frame drawn, Escape closes it"
  else fail "the window on GL 2.1: exit $closed, $(tail -c 300 "$o/window21.out")"; fi
else
  fail "no window appeared on GL 2.1: $(tail -3 "$o/window21.out")"
  kill "$wpid" 2>/dev/null || true
fi
echo "test_windows: $fails failed, in $(($(date +%s) - t0)) s"
[ "$fails" = 0 ]
