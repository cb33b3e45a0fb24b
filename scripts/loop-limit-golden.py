#!/usr/bin/env python3
"""Loop limit golden data with texture coordinates: OpenSubdiv's limit positions and limit
`vt` (PrimvarRefiner::Limit and LimitFaceVarying with SCHEME_LOOP).

Usage: scripts/loop-limit-golden.py ORACLE OUTDIR SHAPE.obj...
For every shape, level 1 and 2 and each of the six face-varying modes, runs
    ORACLE refine SHAPE.obj LEVEL --scheme loop --limit --fvar MODE
and writes OUTDIR/<shape>.txt.gz: per case a line `case LEVEL MODE verts N values M`, then
the `v` and `vt` lines as the oracle printed them (%.17g), then `end`.
"""
import gzip, os, subprocess, sys

MODES = ["none", "corners-only", "corners-plus1", "corners-plus2", "boundaries", "all"]


def main():
    oracle, outdir, shapes = sys.argv[1], sys.argv[2], sys.argv[3:]
    for shape in shapes:
        name = os.path.splitext(os.path.basename(shape))[0]
        lines = [f"# osd-oracle (OpenSubdiv 3.5, Debian libosd-dev) Loop limit golden data for "
                 f"{name}.obj; produced by scripts/loop-limit-golden.py"]
        for level in (1, 2):
            for mode in MODES:
                out = subprocess.run([oracle, "refine", shape, str(level), "--scheme", "loop",
                                      "--limit", "--fvar", mode],
                                     capture_output=True, text=True, timeout=600, check=True).stdout
                v = [l for l in out.splitlines() if l.startswith("v ")]
                vt = [l for l in out.splitlines() if l.startswith("vt ")]
                lines.append(f"case {level} {mode} verts {len(v)} values {len(vt)}")
                lines += v + vt
                lines.append("end")
        with open(os.path.join(outdir, name + ".txt.gz"), "wb") as f:
            f.write(gzip.compress(("\n".join(lines) + "\n").encode(), mtime=0))


main()
