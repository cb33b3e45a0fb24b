#!/usr/bin/env python3
"""Bilinear limit-surface golden data for crates/subsurf/tests/integration/bilinear_limit_golden.rs.

Usage: scripts/bilinear-limit-bfr-golden.py [ORACLE]   (default /tmp/osd-oracle-all-faces)

ORACLE is osd-oracle (../shared/tools/osd-oracle/, beside the project) built with
crates/subsurf/tests/golden/limit_ngon/osd-oracle-all-faces.patch applied, whose `limit`
then evaluates every face with `--all-faces` (the stock oracle samples quads only):

    cp .../osd-oracle/osd_oracle.cpp /tmp && cd /tmp && \
      patch -p1 < crates/subsurf/tests/golden/limit_ngon/osd-oracle-all-faces.patch && \
      g++ -O2 -std=c++14 osd_oracle.cpp -o /tmp/osd-oracle-all-faces -losdCPU

For OpenSubdiv's 3 bilinear regression shapes and 5 Catmull-Clark ones with holes, creases,
corners, boundary mode `none`, texture seams and faces of 3, 5 and 6 sides (SHAPES below; all
in crates/subsurf/tests/shapes/osd/) it runs

    ORACLE limit SHAPE 4 --scheme bilinear --boundary none|corner|edge --all-faces

(OpenSubdiv 3.5 Bfr: every face with a limit surface, a quad on the grid (u, v) = (i/3, j/3),
any other face sub-face by sub-face on the grid (s, t) = (i/3, j/3) of each, written in Bfr's
(u, v) of the face (Bfr::Parameterization::ConvertNormalizedSubFaceToCoord), derivatives by
those; the `s t` columns from the shape's `vt`, in the oracle's default face-varying mode
`all`) and writes crates/subsurf/tests/golden/bilinear_bfr/<shape>.txt.gz: a header line
naming the command, then the oracle's data lines verbatim (%.17g). The boundary mode is the
shape's `t interpolateboundary` tag (edge-only without one).

It also checks, and stops if not, what the test relies on: that the rows are the same with
`--fvar none` (bilinear face-varying data is linear in every mode) and with each other
boundary mode (no face of a bilinear surface is left out for boundary `none`, and creases,
corners and boundary modes do not move bilinear points). gzip with mtime 0, so re-running on
the same inputs rewrites identical bytes.
"""
import gzip, os, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES_DIR = os.path.join(ROOT, "crates/subsurf/tests/shapes/osd")
OUT = os.path.join(ROOT, "crates/subsurf/tests/golden/bilinear_bfr")
BOUNDARY = {"0": "none", "1": "corner", "2": "edge"}
SHAPES = [
    "bilinear_cube",
    "bilinear_nonquads0",
    "bilinear_nonquads1",
    "catmark_cube_creases1",  # semi-sharp creases on a closed cube
    "catmark_edgenone",  # boundary `none`, a corner and infinitely sharp creases
    "catmark_fvar_bound1",  # texture seams
    "catmark_hole_test2",  # a hole and a crease
    "catmark_nonquads",  # triangles, a pentagon and hexagons among quads
]
N = "4"


def boundary_of(path):
    mode = "edge"
    for line in open(path):
        tok = line.split()
        if len(tok) >= 4 and tok[0] == "t" and tok[1] == "interpolateboundary":
            mode = BOUNDARY[tok[3]]
    return mode


def rows(oracle, shape, boundary, extra=()):
    cmd = [oracle, "limit", shape, N, "--scheme", "bilinear", "--boundary", boundary, "--all-faces", *extra]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True, timeout=600).stdout
    return [l for l in out.splitlines() if l.split() and l.split()[0].isdigit()]


def main():
    oracle = sys.argv[1] if len(sys.argv) > 1 else "/tmp/osd-oracle-all-faces"
    os.makedirs(OUT, exist_ok=True)
    for name in SHAPES:
        f = name + ".obj"
        shape = os.path.join(SHAPES_DIR, f)
        b = boundary_of(shape)
        lines = rows(oracle, shape, b)
        sizes = [len(l.split()) - 1 for l in open(shape) if l.startswith("f ")]
        if name == "bilinear_nonquads0" and not lines:
            sys.exit("%s: no rows for its triangle and pentagon: is %s patched (--all-faces)?" % (name, oracle))
        if rows(oracle, shape, b, ["--fvar", "none"]) != lines:
            sys.exit("%s: the rows differ with --fvar none" % name)
        for other in BOUNDARY.values():
            if rows(oracle, shape, other) != lines:
                sys.exit("%s: the rows differ with --boundary %s" % (name, other))
        head = "# osd-oracle limit %s %s --scheme bilinear --boundary %s --all-faces (OpenSubdiv 3.5 Bfr, Debian libosd-dev, limit_ngon's all-faces patch); produced by scripts/bilinear-limit-bfr-golden.py" % (f, N, b)
        data = "\n".join([head] + lines) + "\n"
        with open(os.path.join(OUT, name + ".txt.gz"), "wb") as fh:
            fh.write(gzip.compress(data.encode(), compresslevel=9, mtime=0))
        faces = sorted({int(l.split()[0]) for l in lines})
        other = sum(1 for x in faces if sizes[x] != 4)
        print("%-24s %-6s %5d rows, %2d faces (%d not quads)" % (name, b, len(lines), len(faces), other))


main()
