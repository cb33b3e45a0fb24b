#!/usr/bin/env python3
"""Face-varying golden data: OpenSubdiv's refined `vt` values and `f v/vt` faces.

Usage: scripts/fvar-golden.py [--scheme catmark|loop] ORACLE OUTDIR SHAPE.obj...
For every shape, level 1..3 and each of the six modes, runs
    ORACLE refine SHAPE.obj LEVEL --fvar MODE [--scheme SCHEME]
and writes OUTDIR/<shape>.txt.gz (format: tests/golden/README.md, "Face-varying data").
The scheme (default catmark, the oracle's default) is passed to the oracle and named in
the file's header; without --scheme the command and the files are as they always were.
"""
import gzip, os, struct, subprocess, sys

MODES = ["none", "corners-only", "corners-plus1", "corners-plus2", "boundaries", "all"]


def fnv(faces):
    h = 0xcbf29ce484222325
    for f in faces:
        for x in [len(f)] + f:
            for b in struct.pack("<I", x):
                h = ((h ^ b) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return h


def case(oracle, shape, level, mode, scheme):
    cmd = [oracle, "refine", shape, str(level), "--fvar", mode]
    if scheme is not None:
        cmd += ["--scheme", scheme]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=600, check=True).stdout
    vt, faces = [], []
    for line in out.splitlines():
        t = line.split()
        if t and t[0] == "vt":
            vt.append(t[1:3])
        elif t and t[0] == "f":
            faces.append([int(c.split("/")[1]) - 1 for c in t[1:]])
    n = len(vt)
    ss = st = 0.0
    for s, t in vt:
        ss += float(s)
        st += float(t)
    idx = range(n) if n <= 256 else sorted({k * n // 256 for k in range(256)})
    lines = [f"case {level} {mode} values {n} faces {len(faces)} uvhash {fnv(faces):016x} "
             f"sum {ss!r} {st!r}"]
    lines += [f"{i} {vt[i][0]} {vt[i][1]}" for i in idx]
    lines.append("end")
    return lines


def main():
    args = sys.argv[1:]
    scheme = None
    if args[:1] == ["--scheme"]:
        scheme, args = args[1], args[2:]
        if scheme not in ("catmark", "loop"):
            sys.exit(f"unknown scheme {scheme} (catmark or loop)")
    if len(args) < 3:
        sys.exit(__doc__)
    oracle, outdir, shapes = args[0], args[1], args[2:]
    for shape in shapes:
        name = os.path.splitext(os.path.basename(shape))[0]
        made_by = "scripts/fvar-golden.py" + (f" --scheme {scheme}" if scheme else "")
        lines = [f"# osd-oracle (OpenSubdiv 3.5, Debian libosd-dev) face-varying golden data for "
                 f"{name}.obj; produced by {made_by}", f"shape {name}"]
        for level in (1, 2, 3):
            for mode in MODES:
                lines += case(oracle, shape, level, mode, scheme)
        data = ("\n".join(lines) + "\n").encode()
        with open(os.path.join(outdir, name + ".txt.gz"), "wb") as f:
            f.write(gzip.compress(data, mtime=0))


main()
