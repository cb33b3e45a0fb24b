#!/usr/bin/env bash
# Regenerates the OpenSubdiv golden data for the Loop and bilinear schemes that
# crates/subsurf/tests/integration/osd_golden_schemes.rs checks against.
#
#   scripts/make-golden-schemes.sh [--copy-shapes [DIR]] [SHAPE_NAME...]
#
# Inputs:  crates/subsurf/tests/shapes/osd/{loop,bilinear}_*.obj (OpenSubdiv's regression shapes,
#          copied verbatim); --copy-shapes first refreshes them from DIR (default
#          ../shared/meshes/osd beside the project).
# Oracle:  $OSD_ORACLE (default /tmp/osd-oracle); built with $OSD_ORACLE_SRC/build.sh
#          (default ../shared/tools/osd-oracle beside the project) when missing.
# Output:  crates/subsurf/tests/golden/osd_schemes/<shape>.txt.gz, one per shape, levels 1..4,
#          refined and limit positions (`loop_*` with --scheme loop, `bilinear_*` with --scheme
#          bilinear; format: crates/subsurf/tests/golden/README.md).
#
# Not part of CI: the tests only read the committed files. Re-running on the same inputs
# rewrites byte-identical files (gzip without timestamps).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
shapes="$root/crates/subsurf/tests/shapes/osd"
out="$root/crates/subsurf/tests/golden/osd_schemes"
oracle="${OSD_ORACLE:-/tmp/osd-oracle}"
oracle_src="${OSD_ORACLE_SRC:-$root/../shared/tools/osd-oracle}"

if [[ "${1:-}" == "--copy-shapes" ]]; then
    shift
    src="$root/../shared/meshes/osd"
    if [[ $# -gt 0 && -d "$1" ]]; then src="$1"; shift; fi
    mkdir -p "$shapes"
    cp -- "$src"/loop_*.obj "$src"/bilinear_*.obj "$shapes"/
    chmod u+w,a+r "$shapes"/loop_*.obj "$shapes"/bilinear_*.obj
    echo "copied $(ls "$src"/loop_*.obj "$src"/bilinear_*.obj | wc -l) shapes from $src"
fi

if [[ ! -x "$oracle" ]]; then
    echo "building the oracle at $oracle"
    "$oracle_src/build.sh" "$oracle"
fi

if [[ $# -eq 0 ]]; then
    rm -f "$out"/*.txt.gz
fi
mkdir -p "$out"

start=$(date +%s%N)
for scheme in loop bilinear; do
    only=()
    for name in "$@"; do
        [[ "$name" == "${scheme}_"* ]] && only+=("$name")
    done
    if [[ $# -gt 0 && ${#only[@]} -eq 0 ]]; then continue; fi
    tmp="$(mktemp -d)"
    ln -s "$shapes"/"${scheme}"_*.obj "$tmp"/
    python3 "$root/scripts/golden.py" --oracle "$oracle" --shapes "$tmp" --out "$out" \
        --levels 1,2,3,4 --scheme "$scheme" --modes refine,limit "${only[@]}"
    rm -rf "$tmp"
done
end=$(date +%s%N)
ms=$(( (end - start) / 1000000 ))
printf 'generation took %d.%01d s; %s in %s\n' $((ms / 1000)) $((ms % 1000 / 100)) \
    "$(du -sh "$out" | cut -f1)" "crates/subsurf/tests/golden/osd_schemes"
