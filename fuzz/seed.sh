#!/usr/bin/env bash
# Builds the seed corpus of the `loader` fuzz target at run time from the shared conformance
# and tricky files (they stay in ../shared and are never committed here).
#
# Each .obj becomes one input: the OBJ bytes, the separator 0xFF 0x00 0xFF, then the bytes of
# every MTL its `mtllib` lines name (concatenated; load_embedded hands the same MTL bytes to
# every mtllib). Usage: fuzz/seed.sh [SHARED_DIR]   (default: ../shared beside the repository)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
shared="${1:-${SHARED_DIR:-$here/../../shared}}"
out="$here/corpus/loader"
mkdir -p "$out"
[ -d "$shared" ] || { echo "seed.sh: no shared folder at $shared" >&2; exit 1; }

n=0
while IFS= read -r -d '' obj; do
    dir="$(dirname "$obj")"
    rel="${obj#"$shared"/}"
    name="$(printf '%s' "$rel" | tr -c 'A-Za-z0-9._-' '_')"
    mtls=()
    # Each mtllib line: the whole rest as one name (names with spaces), else one name per word.
    while IFS= read -r rest; do
        rest="${rest%$'\r'}"
        [ -n "$rest" ] || continue
        if [ -f "$dir/$rest" ]; then
            mtls+=("$dir/$rest")
        else
            # Words split at unescaped whitespace; "\ " is a space inside a name.
            for w in $(printf '%s' "$rest" | sed 's/\\ /\x01/g'); do
                w="${w//$'\x01'/ }"
                if [ -f "$dir/$w" ]; then mtls+=("$dir/$w"); fi
            done
        fi
    done < <(grep -a -E '^[[:space:]]*mtllib[[:space:]]' "$obj" | sed -E 's/^[[:space:]]*mtllib[[:space:]]+//' || true)
    {
        cat "$obj"
        printf '\377\000\377'
        for m in ${mtls[@]+"${mtls[@]}"}; do cat "$m"; printf '\n'; done
    } > "$out/$name"
    n=$((n + 1))
done < <(find "$shared/conformance" "$shared/tricky" -type f -name '*.obj' -print0 | sort -z)

# Every MTL on its own too, behind a one-triangle OBJ that uses its first material, so MTL
# parsing is seeded even for libraries no OBJ above references.
while IFS= read -r -d '' mtl; do
    rel="${mtl#"$shared"/}"
    name="$(printf '%s' "$rel" | tr -c 'A-Za-z0-9._-' '_')"
    first="$(grep -a -m1 -E '^[[:space:]]*newmtl[[:space:]]' "$mtl" | sed -E 's/^[[:space:]]*newmtl[[:space:]]+//; s/\r$//' || true)"
    {
        printf 'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl %s\nf 1/1 2/2 3/3\n' "$first"
        printf '\377\000\377'
        cat "$mtl"
    } > "$out/$name"
    n=$((n + 1))
done < <(find "$shared/conformance" "$shared/tricky" -type f -name '*.mtl' -print0 | sort -z)

echo "seed.sh: $n inputs in $out"
