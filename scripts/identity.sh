#!/usr/bin/env bash
# Byte-identity check for changes that must not change a single output byte.
#
#   scripts/identity.sh record DIR   render every preset and a short sweep into DIR
#   scripts/identity.sh check DIR    render them again and compare each file with DIR's (cmp)
#
# Every preset in scenes/ is rendered at 160 × 120 with its own method (--spp 4 where it
# samples), writing the PNG and the spectral EXR; then the paper preset's light sweep over
# three frames (contact sheet and frames). `check` prints one line per file and a final count
# and exits non-zero on any difference or missing file. Record from the code before a change,
# check after it. A file that differs only in the scene text it records (`opalray.scene`:
# scripts/identity-pixels.py compares the rest) is counted apart, as SCENE; it fails the check
# unless IDENTITY_SCENE_TEXT=changes says the change is meant to change that text.
#
# The binary is target/release/opalray, built first unless OPALRAY names another one.
# Renders run with `nice -n 5`; the whole set takes a few minutes on two cores.
set -euo pipefail

usage() {
    echo "usage: scripts/identity.sh record|check DIR" >&2
    exit 2
}
[[ $# -eq 2 ]] || usage
mode=$1
dir=$2
[[ $mode == record || $mode == check ]] || usage

root=$(cd "$(dirname "$0")/.." && pwd)
if [[ -z ${OPALRAY:-} ]]; then
    (cd "$root" && nice -n 5 cargo build --release -q -p opalray-cli)
    OPALRAY=$root/target/release/opalray
fi

# Render every image into $1 (an empty folder).
render_all() {
    local out=$1 scene name
    for scene in "$root"/scenes/*.toml; do
        name=$(basename "$scene" .toml)
        nice -n 5 "$OPALRAY" render --preset "$name" --width 160 --height 120 --spp 4 \
            --output "$out/$name.png" --spectral "$out/$name.exr" >/dev/null 2>&1 ||
            { echo "render of preset $name failed" >&2; return 1; }
    done
    mkdir -p "$out/sweep-frames"
    nice -n 5 "$OPALRAY" sweep --preset paper --frames 3 --width 160 --height 120 \
        --sheet "$out/sweep.png" --frames-dir "$out/sweep-frames" >/dev/null 2>&1 ||
        { echo "sweep of preset paper failed" >&2; return 1; }
}

if [[ $mode == record ]]; then
    if [[ -e $dir && -n $(ls -A "$dir" 2>/dev/null) ]]; then
        echo "record: $dir is not empty; name a new folder" >&2
        exit 2
    fi
    mkdir -p "$dir"
    render_all "$dir"
    echo "recorded $(cd "$dir" && find . -type f | wc -l) files in $dir"
    exit 0
fi

[[ -d $dir ]] || { echo "check: no recorded folder $dir (run record first)" >&2; exit 2; }
fresh=$(mktemp -d)
trap 'rm -rf "$fresh"' EXIT
render_all "$fresh"

same=0
differ=0
scene_only=0
while IFS= read -r file; do
    if [[ ! -f $fresh/$file ]]; then
        echo "MISSING  $file"
        differ=$((differ + 1))
    elif cmp -s "$dir/$file" "$fresh/$file"; then
        echo "same     $file"
        same=$((same + 1))
    elif python3 "$root/scripts/identity-pixels.py" "$dir/$file" "$fresh/$file"; then
        echo "SCENE    $file (the same pixels; the scene it records differs)"
        scene_only=$((scene_only + 1))
    else
        echo "DIFFERS  $file"
        differ=$((differ + 1))
    fi
done < <(cd "$dir" && find . -type f | sed 's|^\./||' | sort)
while IFS= read -r file; do
    if [[ ! -f $dir/$file ]]; then
        echo "NEW      $file"
        differ=$((differ + 1))
    fi
done < <(cd "$fresh" && find . -type f | sed 's|^\./||' | sort)

echo "$same identical, $scene_only with the same pixels but another recorded scene, $differ different"
# A change of the recorded scene text is a difference too, unless the change is meant to make
# it (IDENTITY_SCENE_TEXT=changes): the pixels are then what must not move.
if [[ ${IDENTITY_SCENE_TEXT:-} == changes ]]; then
    [[ $differ -eq 0 ]]
else
    [[ $differ -eq 0 && $scene_only -eq 0 ]]
fi
