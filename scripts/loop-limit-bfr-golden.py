#!/usr/bin/env python3
"""Loop limit-surface golden data for crates/subsurf/tests/integration/loop_limit_golden.rs.

Usage: scripts/loop-limit-bfr-golden.py [ORACLE]   (default /tmp/osd-oracle)

For every Loop regression shape crates/subsurf/tests/shapes/osd/loop_*.obj it runs

    ORACLE limit SHAPE 5 --scheme loop --boundary none|corner|edge

(OpenSubdiv 3.5 Bfr, default approximation level 10; the triangular grid
(u, v) = (i/4, j/4), i + j <= 4, per triangle; with the shape's `vt`, the `s t` columns in the
face-varying mode of its `t facevaryinginterpolateboundary` tag, else `all`) and writes
crates/subsurf/tests/golden/loop_bfr/<shape>.txt.gz: a header line naming the command, then
the oracle's data lines verbatim (%.17g). Non-numeric lines (warnings) are dropped. gzip with
mtime 0, so re-running on the same inputs rewrites identical bytes.
"""
import gzip, os, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHAPES = os.path.join(ROOT, "crates/subsurf/tests/shapes/osd")
OUT = os.path.join(ROOT, "crates/subsurf/tests/golden/loop_bfr")
BOUNDARY = {"0": "none", "1": "corner", "2": "edge"}


def boundary_of(path):
    mode = "edge"
    for line in open(path):
        tok = line.split()
        if len(tok) >= 4 and tok[0] == "t" and tok[1] == "interpolateboundary":
            mode = BOUNDARY[tok[3]]
    return mode


def main():
    oracle = sys.argv[1] if len(sys.argv) > 1 else "/tmp/osd-oracle"
    os.makedirs(OUT, exist_ok=True)
    for f in sorted(os.listdir(SHAPES)):
        if not (f.startswith("loop_") and f.endswith(".obj")):
            continue
        shape = os.path.join(SHAPES, f)
        b = boundary_of(shape)
        cmd = [oracle, "limit", shape, "5", "--scheme", "loop", "--boundary", b]
        out = subprocess.run(cmd, capture_output=True, text=True, check=True, timeout=600).stdout
        lines = [l for l in out.splitlines() if l.split() and l.split()[0].isdigit()]
        head = "# osd-oracle limit %s 5 --scheme loop --boundary %s (OpenSubdiv 3.5 Bfr, Debian libosd-dev); produced by scripts/loop-limit-bfr-golden.py" % (f, b)
        data = "\n".join([head] + lines) + "\n"
        with open(os.path.join(OUT, f[:-4] + ".txt.gz"), "wb") as fh:
            fh.write(gzip.compress(data.encode(), compresslevel=9, mtime=0))
        print("%-28s %-6s %5d rows" % (f[:-4], b, len(lines)))


main()
