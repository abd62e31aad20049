#!/usr/bin/env bash
# Pictures must not change: renders every case of scripts/pictures_corpus.txt headless with a
# glview built at BASE_REV ("before") and one built from the working tree ("after") and compares
# the PNGs pixel for pixel (RGBA; the text chunks such as glview.command are ignored).
#
#   bash scripts/pictures_unchanged.sh [BASE_REV]
#       BASE_REV default: the merge-base of HEAD with origin/main if that exists, else HEAD~1.
#       BASE_REV is checked out with `git worktree add` into a temporary folder (removed at the
#       end) and built there with CARGO_TARGET_DIR=target/pictures-base, so its dependencies
#       compile once and later runs reuse them; the working tree is built with `cargo build`
#       (dev profile: the pixels come from the same rasterizer, Mesa llvmpipe).
#   bash scripts/pictures_unchanged.sh --before-bin PATH --after-bin PATH
#       compare two binaries already built; nothing is built.
#   --only REGEX (with any of the above): only the corpus cases whose name matches (bash ERE).
#   bash scripts/pictures_unchanged.sh --self-test [--after-bin PATH]
#       checks the checker with one binary (built from the working tree unless given): the
#       same case on both sides must compare equal, one rendered with --yaw 30 before and
#       --yaw 31 after must be reported as differing, one with an option that does not exist
#       must be reported as failed on both sides. Exit 0 if all three are reported so (the
#       table itself then says 1 differs and 1 failed, as a real run would).
#
# Then every "after" picture whose PNG keeps its options (glview.options) is drawn again with
# `glview --repro PICTURE.png` and must equal it pixel for pixel (when the after binary has
# --repro).
# Prints `name | pixels differing | max diff | size` per picture and `N pictures, M differ`;
# exits 1 if any picture differs or any case failed to render with either binary (a case that
# fails with both, e.g. an option the old binary lacks, is reported as failed, not skipped),
# 2 on a usage or build error. Pictures go to target/pictures-unchanged/: before/NAME.png,
# after/NAME.png, diff/NAME.png (differing pixels red, the rest the after picture in dark grey)
# for each differing picture, and logs/NAME.{before,after}.{out,err} (each render's stdout and
# stderr).
# Needs python3 (standard library only: scripts/png_diff.py decodes the PNGs).
set -uo pipefail
[ "${BASH_VERSINFO[0]}" -gt 4 ] || { [ "${BASH_VERSINFO[0]}" -eq 4 ] && [ "${BASH_VERSINFO[1]}" -ge 4 ]; } \
  || { echo "pictures_unchanged: needs bash 4.4 or newer" >&2; exit 2; }

usage() { sed -n '2,/^set -uo/{/^set -uo/d;s/^# \{0,1\}//;p}' "$0"; }
die() { echo "pictures_unchanged: $*" >&2; exit 2; }

script_dir=$(cd "$(dirname "$0")" && pwd)
repo=$(git -C "$script_dir" rev-parse --show-toplevel) || die "not inside a git repository"
cd "$repo" || die "cannot cd to $repo"

before_bin="" after_bin="" base_rev="" self_test=0 only=""
corpus="$script_dir/pictures_corpus.txt"
while [ $# -gt 0 ]; do
  case "$1" in
    --before-bin) [ $# -ge 2 ] || die "--before-bin needs a path"; before_bin=$2; shift 2 ;;
    --after-bin) [ $# -ge 2 ] || die "--after-bin needs a path"; after_bin=$2; shift 2 ;;
    --self-test) self_test=1; shift ;;
    --only) [ $# -ge 2 ] || die "--only needs a regular expression"; only=$2; shift 2 ;;
    -h | --help) usage; exit 0 ;;
    -*) die "unknown option $1 (see --help)" ;;
    *) [ -z "$base_rev" ] || die "one BASE_REV only"; base_rev=$1; shift ;;
  esac
done
if [ $self_test = 1 ]; then
  [ -z "$before_bin" ] && [ -z "$base_rev" ] || die "--self-test takes only --after-bin"
elif [ -n "$before_bin$after_bin" ]; then
  [ -n "$before_bin" ] && [ -n "$after_bin" ] || die "give both --before-bin and --after-bin"
  [ -z "$base_rev" ] || die "BASE_REV and --before-bin exclude each other"
fi

py=$(command -v python3 || true)
[ -n "$py" ] || [ ! -x /root/.pyenv/shims/python3 ] || py=/root/.pyenv/shims/python3
[ -n "$py" ] || die "python3 not found"
py=$("$py" -c 'import sys; print(sys.executable)') || die "python3 does not run" # skip shims
png_diff="$script_dir/png_diff.py"

out="$repo/target/pictures-unchanged"
[ $self_test = 1 ] && out="$out/self-test"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/pictures-unchanged.XXXXXX") || die "mktemp failed"
base_tree=""
cleanup() {
  if [ -n "$base_tree" ] && [ -d "$base_tree" ]; then
    git -C "$repo" worktree remove --force "$base_tree" || echo "pictures_unchanged: could not remove the worktree $base_tree" >&2
  fi
  git -C "$repo" worktree prune
  rm -rf "$tmp"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# The path of the glview executable a `cargo build` in the current folder produced.
cargo_build_glview() {
  cargo build --bin glview --message-format=json-render-diagnostics \
    | "$py" -c '
import json, sys
exe = None
for line in sys.stdin:
    try:
        m = json.loads(line)
    except ValueError:
        continue
    if m.get("reason") == "compiler-artifact" and m.get("target", {}).get("name") == "glview" \
            and m.get("executable"):
        exe = m["executable"]
if exe is None:
    sys.exit("no glview executable in cargo output")
print(exe)'
}

if [ $self_test = 0 ] && [ -z "$before_bin" ]; then
  if [ -z "$base_rev" ]; then
    if git rev-parse -q --verify origin/main >/dev/null; then
      base_rev=$(git merge-base HEAD origin/main) || die "no merge-base of HEAD and origin/main"
    else
      base_rev=HEAD~1
    fi
  fi
  base_sha=$(git rev-parse -q --verify "$base_rev^{commit}") || die "unknown revision $base_rev"
  base_tree="$tmp/base"
  echo "building before = $base_rev ($(git log -1 --format='%h %s' "$base_sha" | cut -c1-70)) in $base_tree" >&2
  git worktree add --detach --quiet "$base_tree" "$base_sha" || die "git worktree add failed"
  before_bin=$(cd "$base_tree" && CARGO_TARGET_DIR="$repo/target/pictures-base" cargo_build_glview) \
    || die "building $base_rev failed"
  # The binary does not need its sources (shaders are compiled in): drop the checkout now.
  git worktree remove --force "$base_tree" && base_tree=""
fi
if [ -z "$after_bin" ]; then
  echo "building after = the working tree" >&2
  after_bin=$(cargo_build_glview) || die "building the working tree failed"
fi
for b in "$before_bin" "$after_bin"; do
  [ -z "$b" ] || [ -x "$b" ] || die "$b is not an executable"
done
[ $self_test = 1 ] && before_bin=$after_bin
before_bin=$(realpath "$before_bin") after_bin=$(realpath "$after_bin")

# Cases: NAME, the before binary's ARGS and the after binary's ARGS (the same but in the
# self-test).
names=() args=() args_after=()
if [ $self_test = 1 ]; then
  names=(same perturbed unknown-option)
  args=("--yaw 30" "--yaw 30" "--no-such-option-for-self-test")
  args_after=("--yaw 30" "--yaw 31" "--no-such-option-for-self-test")
else
  [ -f "$corpus" ] || die "no corpus file $corpus"
  declare -A seen=()
  lineno=0
  while IFS= read -r line || [ -n "$line" ]; do
    lineno=$((lineno + 1))
    case "$line" in '' | '#'*) continue ;; esac
    [[ $line == *'|'* ]] || die "$corpus:$lineno: expected NAME | ARGUMENTS"
    name=${line%%|*} rest=${line#*|}
    name=$(echo "$name" | tr -d '[:space:]')
    [[ $name =~ ^[A-Za-z0-9._-]+$ ]] || die "$corpus:$lineno: bad case name '$name'"
    [ -z "${seen[$name]:-}" ] || die "$corpus:$lineno: case $name given twice"
    [[ $rest != *[\"\'\$\`\\\*\?\|]* ]] || die "$corpus:$lineno: quotes, \$, \\, globs or | are not supported"
    seen[$name]=1
    [ -z "$only" ] || [[ $name =~ $only ]] || continue
    names+=("$name") args+=("$rest") args_after+=("$rest")
  done <"$corpus"
fi
[ ${#names[@]} -gt 0 ] || die "no cases"

rm -rf "$out/before" "$out/after" "$out/diff" "$out/logs" "$out/inputs"
mkdir -p "$out/before" "$out/after" "$out/diff" "$out/logs" "$out/inputs" || die "cannot create $out"
inputs="$out/inputs"

# STL and PLY inputs (../shared has no such files): the teapot as binary STL (zero facet
# normals, as many exporters write), suzanne as ASCII PLY with per-vertex colours and its quads.
"$py" - "$repo/../shared/models" "$inputs" <<'PY' || die "could not write the STL/PLY inputs"
import os, struct, sys
src, dst = sys.argv[1], sys.argv[2]
def read_obj(path):
    vs, fs = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                vs.append(tuple(float(x) for x in w[1:4]))
            elif w[0] == "f":
                fs.append([int(c.split("/")[0]) - 1 for c in w[1:]])
    return vs, fs
vs, fs = read_obj(os.path.join(src, "teapot-small", "teapot.obj"))
tris = [(f[0], f[i], f[i + 1]) for f in fs for i in range(1, len(f) - 1)]
with open(os.path.join(dst, "teapot.stl"), "wb") as f:
    f.write(b"binary STL written by scripts/pictures_unchanged.sh".ljust(80, b" "))
    f.write(struct.pack("<I", len(tris)))
    for t in tris:
        f.write(struct.pack("<3f", 0, 0, 0))
        for i in t:
            f.write(struct.pack("<3f", *vs[i]))
        f.write(b"\0\0")
vs, fs = read_obj(os.path.join(src, "suzanne", "suzanne.obj"))
lo = [min(v[k] for v in vs) for k in range(3)]
hi = [max(v[k] for v in vs) for k in range(3)]
with open(os.path.join(dst, "suzanne.ply"), "w") as f:
    f.write("ply\nformat ascii 1.0\ncomment written by scripts/pictures_unchanged.sh\n"
            f"element vertex {len(vs)}\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\n"
            f"element face {len(fs)}\nproperty list uchar int vertex_indices\nend_header\n")
    for v in vs:
        c = [round(255 * (v[k] - lo[k]) / ((hi[k] - lo[k]) or 1)) for k in range(3)]
        f.write("%r %r %r %d %d %d\n" % (v + tuple(c)))
    for face in fs:
        f.write(" ".join(str(x) for x in [len(face)] + face) + "\n")
PY

# Every option of the corpus should be in the before binary's --help (a warning only: the case
# then fails on its own and is reported).
help_text=$("$before_bin" --help 2>&1)
declare -A checked=()
for a in "${args[@]}" "${args_after[@]}"; do
  for w in $a; do
    case "$w" in
      --*)
        [ -z "${checked[$w]:-}" ] || continue
        checked[$w]=1
        grep -q -e "^ *${w}[ ,=]" -e "^ *${w}\$" -e ", ${w}[ ,=]" -e ", ${w}\$" <<<"$help_text" \
          || echo "warning: $w is not in the before binary's --help" >&2 ;;
    esac
  done
done

export GLVIEW_CACHE_DIR="$tmp/cache" # --no-cache is on every render; this keeps caches apart too
rows=() failures=() n_pictures=0 n_differ=0 n_failed=0
before_ms=0 after_ms=0
now_ms() { date +%s%3N; }
start=$(now_ms)

# render SIDE NAME BIN ARGS... : into $tmp/render/NAME/SIDE/out.png; returns the exit code.
render() {
  local side=$1 name=$2 bin=$3
  shift 3
  local dir="$tmp/render/$name/$side"
  mkdir -p "$dir"
  local t0 rc
  t0=$(now_ms)
  timeout 300 "$bin" -o "$dir/out.png" "$@" >"$out/logs/$name.$side.out" 2>"$out/logs/$name.$side.err"
  rc=$?
  if [ "$side" = before ]; then before_ms=$((before_ms + $(now_ms) - t0)); else after_ms=$((after_ms + $(now_ms) - t0)); fi
  [ $rc -eq 0 ] && [ ! -s "$dir/out.png" ] && { echo "(exit 0 but no $dir/out.png)" >>"$out/logs/$name.$side.err"; rc=99; }
  return $rc
}

for i in "${!names[@]}"; do
  name=${names[$i]}
  read -r -a words_before <<<"${args[$i]//@INPUTS@/$inputs}"
  read -r -a words_after <<<"${args_after[$i]//@INPUTS@/$inputs}"
  common=(--no-cache)
  [[ " ${words_before[*]} " == *" --size "* ]] || common+=(--size 320x240)
  render before "$name" "$before_bin" "${common[@]}" "${words_before[@]}"
  rc_b=$?
  render after "$name" "$after_bin" "${common[@]}" "${words_after[@]}"
  rc_a=$?
  printf '.' >&2
  if [ $rc_b -ne 0 ] || [ $rc_a -ne 0 ]; then
    n_failed=$((n_failed + 1))
    which=both
    [ $rc_b -eq 0 ] && which=after
    [ $rc_a -eq 0 ] && which=before
    rows+=("$name|FAILED ($which)|-|-")
    msg="FAILED $name ($which), run from $repo:"
    for side in before after; do
      rc_var=rc_${side:0:1}
      rc_val=${!rc_var}
      [ "$rc_val" -ne 0 ] || continue
      bin_var=${side}_bin words_var="words_${side}[@]"
      cmd=$(printf '%q ' "${!bin_var}" -o "$out/$side/$name.png" "${common[@]}" "${!words_var}")
      # stderr's last `error` line (clap follows it with usage lines that say nothing about
      # the cause), else its last line.
      err="$out/logs/$name.$side.err"
      last=$(grep -i '^error' "$err" | tail -n 1)
      [ -n "$last" ] || last=$(grep -v '^[[:space:]]*$' "$err" | tail -n 1)
      [ $rc_val -eq 124 ] && last="timed out after 300 s; ${last}"
      msg+=$'\n'"  $side (exit $rc_val): $cmd"$'\n'"    last line: ${last:-(no output)}"
    done
    failures+=("$msg")
    for side in before after; do # keep what did render, for a look
      [ -f "$tmp/render/$name/$side/out.png" ] && mv "$tmp/render/$name/$side/out.png" "$out/$side/$name.png"
    done
    continue
  fi
  # The picture and any side files (--diff writes OUT-A.png, OUT-B.png) of either side.
  files=$( (cd "$tmp/render/$name" && ls before after) | grep -E '^out(-.*)?\.png$' \
    | sed 's/^out\.png$/ /' | sort -u | sed 's/^ $/out.png/')
  for f in $files; do
    suffix=${f#out}
    suffix=${suffix%.png}
    pic=$name$suffix
    n_pictures=$((n_pictures + 1))
    b="$out/before/$pic.png" a="$out/after/$pic.png"
    [ -f "$tmp/render/$name/before/$f" ] && mv "$tmp/render/$name/before/$f" "$b"
    [ -f "$tmp/render/$name/after/$f" ] && mv "$tmp/render/$name/after/$f" "$a"
    if [ ! -f "$b" ] || [ ! -f "$a" ]; then
      n_differ=$((n_differ + 1))
      rows+=("$pic|only $([ -f "$b" ] && echo before || echo after) wrote it|-|-")
      continue
    fi
    result=$("$py" "$png_diff" "$b" "$a" --diff-out "$out/diff/$pic.png" 2>"$tmp/png_diff.err")
    case $? in
      0) read -r px mx size <<<"$result"; rows+=("$pic|$px|$mx|$size") ;;
      1) read -r px mx size <<<"$result"; rows+=("$pic|$px|$mx|$size"); n_differ=$((n_differ + 1)) ;;
      *) n_differ=$((n_differ + 1)); rows+=("$pic|unreadable: $(tail -n 1 "$tmp/png_diff.err")|-|-") ;;
    esac
  done
  rm -rf "$tmp/render/$name"
done
echo >&2
total_ms=$(($(now_ms) - start))

echo "before: $before_bin"
echo "after:  $after_bin"
{
  echo "name|pixels differing|max diff|size"
  printf '%s\n' "${rows[@]}"
} | if command -v column >/dev/null; then column -t -s '|' -o ' | '; else sed 's/|/ | /g'; fi
for i in "${!failures[@]}"; do echo "${failures[$i]}"; done
printf '%d pictures, %d differ' "$n_pictures" "$n_differ"
[ $n_failed -gt 0 ] && printf ', %d of %d cases failed to render' "$n_failed" "${#names[@]}"
printf '\n'
secs() { printf '%d.%d s' $(($1 / 1000)) $(($1 % 1000 / 100)); }
echo "rendering: before $(secs $before_ms), after $(secs $after_ms); whole comparison $(secs $total_ms)"
echo "pictures: $out/{before,after}/NAME.png; differences: $out/diff/; logs: $out/logs/"

# Every picture whose PNG keeps its options (glview.options) is drawn again from them alone
# (`glview --repro`) and must come out pixel for pixel the same.
n_repro=0 n_repro_differ=0
if [ $self_test = 0 ] && "$after_bin" --help 2>/dev/null | grep -q -- '--repro'; then
  mkdir -p "$out/repro"
  for a in "$out"/after/*.png; do
    pic=$(basename "$a" .png)
    r="$out/repro/$pic.png"
    if ! "$after_bin" --repro "$a" -o "$r" >/dev/null 2>"$out/logs/$pic.repro.err"; then
      grep -q 'no glview.options text' "$out/logs/$pic.repro.err" && continue
      n_repro=$((n_repro + 1)) n_repro_differ=$((n_repro_differ + 1))
      echo "repro $pic: FAILED: $(grep -i '^error' "$out/logs/$pic.repro.err" | tail -n 1)"
      continue
    fi
    n_repro=$((n_repro + 1))
    if ! result=$("$py" "$png_diff" "$a" "$r" --diff-out "$out/diff/$pic.repro.png" 2>&1); then
      n_repro_differ=$((n_repro_differ + 1))
      echo "repro $pic: differs: $result"
    fi
  done
  echo "--repro: $n_repro pictures drawn again from their glview.options, $n_repro_differ differ"
fi

if [ $self_test = 1 ]; then
  ok=1
  check() { # NAME EXPECTED-ROW-PATTERN
    local row
    row=$(printf '%s\n' "${rows[@]}" | grep "^$1|")
    if [[ $row =~ $2 ]]; then echo "self-test: $1: ok ($row)"; else echo "self-test: $1: WRONG ($row)"; ok=0; fi
  }
  check same '^same\|0\|0\|'
  check perturbed '^perturbed\|[1-9][0-9]*\|[1-9][0-9]*\|'
  check unknown-option '^unknown-option\|FAILED \(both\)'
  [ $n_differ -eq 1 ] && [ $n_failed -eq 1 ] || { echo "self-test: counts WRONG"; ok=0; }
  if [ $ok = 1 ]; then echo "self-test passed"; exit 0; else echo "self-test FAILED"; exit 1; fi
fi
[ $n_differ -eq 0 ] && [ $n_failed -eq 0 ] && [ $n_repro_differ -eq 0 ]
