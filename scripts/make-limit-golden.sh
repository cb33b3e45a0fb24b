#!/usr/bin/env bash
# Regenerates the OpenSubdiv limit-surface golden data that
# crates/subsurf/tests/integration/limit_golden.rs checks LimitSurface against.
#
#   scripts/make-limit-golden.sh [SHAPE_NAME...]
#
# Inputs:  crates/subsurf/tests/shapes/osd/*.obj (OpenSubdiv's regression shapes).
# Oracle:  $OSD_ORACLE (default /tmp/osd-oracle); built with
#          $OSD_ORACLE_SRC/build.sh (default ../shared/tools/osd-oracle beside the project) when missing.
# Output:  crates/subsurf/tests/golden/limit/<shape>.txt.gz, one per shape with quad faces:
#          the lines of `osd-oracle limit <shape>.obj 5 --boundary none|corner|edge`
#          (at most 300 faces per shape; format: crates/subsurf/tests/golden/limit/README.md).
#
# Not part of CI: the test only reads the committed files. Needs python3 and the oracle
# (OpenSubdiv 3.5 from Debian's libosd-dev). Re-running on the same inputs rewrites
# byte-identical files (gzip without timestamps).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
shapes="$root/crates/subsurf/tests/shapes/osd"
out="$root/crates/subsurf/tests/golden/limit"
oracle="${OSD_ORACLE:-/tmp/osd-oracle}"
oracle_src="${OSD_ORACLE_SRC:-$root/../shared/tools/osd-oracle}"

if ! ls "$shapes"/*.obj >/dev/null 2>&1; then
    echo "no shapes in $shapes" >&2
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

python3 "$root/scripts/limit_golden.py" --oracle "$oracle" --shapes "$shapes" --out "$out" "$@"
printf '%s bytes in crates/subsurf/tests/golden/limit\n' "$(cat "$out"/*.txt.gz | wc -c)"
