#!/usr/bin/env bash
# Regenerates the OpenSubdiv golden data that crates/subsurf/tests/integration/osd_golden.rs checks against.
#
#   scripts/make-golden.sh [--copy-shapes [DIR]] [SHAPE_NAME...]
#
# Inputs:  crates/subsurf/tests/shapes/osd/*.obj (OpenSubdiv's regression shapes, copied verbatim).
#          --copy-shapes first refreshes that copy from DIR (default ../shared/meshes/osd beside the project).
# Oracle:  $OSD_ORACLE (default /tmp/osd-oracle); built with
#          $OSD_ORACLE_SRC/build.sh (default ../shared/tools/osd-oracle beside the project) when missing.
# Output:  crates/subsurf/tests/golden/osd/<shape>.txt.gz, one per shape, levels 1..4,
#          refined and limit positions (format: crates/subsurf/tests/golden/README.md).
#
# Not part of CI: the tests only read the committed files. Needs python3 and the oracle
# (OpenSubdiv 3.5 from Debian's libosd-dev). Re-running on the same inputs rewrites
# byte-identical files (gzip without timestamps).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
shapes="$root/crates/subsurf/tests/shapes/osd"
out="$root/crates/subsurf/tests/golden/osd"
oracle="${OSD_ORACLE:-/tmp/osd-oracle}"
oracle_src="${OSD_ORACLE_SRC:-$root/../shared/tools/osd-oracle}"

if [[ "${1:-}" == "--copy-shapes" ]]; then
    shift
    src="$root/../shared/meshes/osd"
    if [[ $# -gt 0 && -d "$1" ]]; then src="$1"; shift; fi
    mkdir -p "$shapes"
    cp -- "$src"/*.obj "$shapes"/
    chmod u+w,a+r "$shapes"/*.obj
    echo "copied $(ls "$src"/*.obj | wc -l) shapes from $src"
fi

if ! ls "$shapes"/*.obj >/dev/null 2>&1; then
    echo "no shapes in $shapes; run with --copy-shapes" >&2
    exit 1
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
python3 "$root/scripts/golden.py" --oracle "$oracle" --shapes "$shapes" --out "$out" --levels 1,2,3,4 "$@"
end=$(date +%s%N)
ms=$(( (end - start) / 1000000 ))
printf 'generation took %d.%01d s; %s in %s\n' $((ms / 1000)) $((ms % 1000 / 100)) \
    "$(du -sh "$root/crates/subsurf/tests/golden" | cut -f1)" "crates/subsurf/tests/golden"
