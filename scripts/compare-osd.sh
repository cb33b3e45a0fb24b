#!/usr/bin/env bash
# Compares `subsurf subdivide` with OpenSubdiv (through osd-oracle) on any OBJ files, the way
# the golden tests do for the bundled shapes: for each mesh and level, refined and with
# `--limit`, the same vertex count, the same face list in the same order, and every vertex,
# index for index, within 1e-12 x the bounding-box diagonal of OpenSubdiv's result.
#
#   scripts/compare-osd.sh [-l "1 2 3"] MESH.obj...
#
# The boundary mode is each mesh's `t interpolateboundary` tag (edge-only without one), given
# to both programs; creases, corners, holes, crease method and triangle rule come from the
# file's tags, which both read.
#
# Environment:
#   OSD_ORACLE=PATH     use this osd-oracle binary instead of building one
#   OSD_ORACLE_SRC=DIR  osd-oracle sources (default: ../shared/tools/osd-oracle next to the
#                       repository); its build.sh installs Debian's libosd-dev if missing
#   SUBSURF=PATH        the subsurf binary (default: built here with cargo, release)
#
# Prints one line per mesh, level and mode; exits 0 when all agree, 1 when any differs, 2
# when the tools cannot be built. Needs python3 (standard library only).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
levels="1 2 3"
if [ "${1:-}" = "-l" ]; then levels="$2"; shift 2; fi
[ $# -gt 0 ] || { sed -n '2,20p' "$0" >&2; exit 2; }

log() { echo "compare-osd: $*" >&2; }
work="$(mktemp -d "${TMPDIR:-/tmp}/compare-osd.XXXXXX")"
trap 'rm -rf "$work"' EXIT

# shellcheck source=scripts/oracle.sh
. "$root/scripts/oracle.sh"
find_oracle "$work"
if [ -n "${SUBSURF:-}" ]; then
  subsurf="$SUBSURF"
else
  (cd "$root" && cargo build --release -q -p subsurf-cli) || { log "building subsurf failed"; exit 2; }
  subsurf="$root/target/release/subsurf"
fi

# Index-for-index comparison of two OBJ outputs (v and f lines only).
cat >"$work/compare.py" <<'EOF'
import sys

def load(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(tuple(float(x) for x in line.split()[1:4]))
            elif line.startswith("f "):
                faces.append(tuple(int(t.split("/")[0]) for t in line.split()[1:]))
    return verts, faces

ours, theirs = load(sys.argv[1]), load(sys.argv[2])
if not theirs[0]:
    print("oracle wrote no vertices"); sys.exit(1)
lo = [min(p[k] for p in theirs[0]) for k in range(3)]
hi = [max(p[k] for p in theirs[0]) for k in range(3)]
diag = sum((h - l) ** 2 for h, l in zip(hi, lo)) ** 0.5 or 1.0
problems = []
if len(ours[0]) != len(theirs[0]):
    problems.append("vertices %d vs %d" % (len(ours[0]), len(theirs[0])))
if ours[1] != theirs[1]:
    problems.append("faces differ (%d vs %d)" % (len(ours[1]), len(theirs[1])))
err = max((abs(a - b) for p, q in zip(ours[0], theirs[0]) for a, b in zip(p, q)), default=0.0) / diag
if err > 1e-12:
    problems.append("error above 1e-12")
print("%-5s max error %.1e of the diagonal, %d vertices %s"
      % ("ok" if not problems else "DIFF", err, len(theirs[0]), "; ".join(problems)))
sys.exit(1 if problems else 0)
EOF

status=0
for mesh in "$@"; do
  tag=$(awk '$1 == "t" && $2 == "interpolateboundary" { print $4 }' "$mesh" | tail -n 1)
  case "$tag" in 0) ours=none theirs=none ;; 1) ours=edge-and-corner theirs=corner ;; *) ours=edge-only theirs=edge ;; esac
  for level in $levels; do
    for mode in refine limit; do
      flag=(); [ "$mode" = limit ] && flag=(--limit)
      printf '%s level %s %-6s ' "$(basename "$mesh")" "$level" "$mode"
      if ! "$subsurf" subdivide "$mesh" -l "$level" --boundary "$ours" "${flag[@]}" --quiet -o "$work/ours.obj"; then
        echo "DIFF  subsurf failed"; status=1; continue
      fi
      if ! "$oracle" refine "$mesh" "$level" --boundary "$theirs" "${flag[@]}" >"$work/theirs.obj"; then
        echo "skip  the oracle failed"; continue
      fi
      python3 "$work/compare.py" "$work/ours.obj" "$work/theirs.obj" || status=1
    done
  done
done
exit $status
