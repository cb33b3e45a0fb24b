#!/usr/bin/env python3
"""Limit-surface golden data for crates/subsurf/tests/integration/limit_golden.rs from the OpenSubdiv oracle.

Called by scripts/make-limit-golden.sh (see there and crates/subsurf/tests/golden/limit/README.md).
For every shape SHAPES/<name>.obj it runs

    osd-oracle limit SHAPE 5 --boundary none|corner|edge

(OpenSubdiv's Bfr, default approximation level 10) and writes OUT/<name>.txt.gz:

    # osd-oracle limit <name>.obj 5 --boundary <b> (OpenSubdiv 3.5 Bfr, Debian libosd-dev); produced by scripts/make-limit-golden.sh
    # quad faces <F>, kept <K>
    <face> <u> <v> <px> <py> <pz> <dux> <duy> <duz> <dvx> <dvy> <dvz>
    ...

The data lines are the oracle's own output lines, verbatim (%.17g). Non-numeric lines the
oracle prints (e.g. "Warning: Edge 3 specified to be sharp does not exist") are dropped.
When the oracle printed more than MAX_FACES faces, only the faces F_k = faces[floor(k * n /
MAX_FACES)], k = 0..MAX_FACES-1, are kept (n = number of faces printed, in printed order),
each with all 25 of its samples. A shape for which the oracle prints nothing (no quad
faces) gets no file; it is listed on stdout.

The gzip stream is written with mtime 0 and no file name, so that re-running on the same
inputs gives byte-identical files.
"""
import argparse
import gzip
import multiprocessing
import os
import subprocess
import sys

GRID = 5
MAX_FACES = 300
BOUNDARY_ARG = {"0": "none", "1": "corner", "2": "edge"}


def boundary_of(path):
    """`t interpolateboundary 1/0/0 K`: 0 none, 1 corner (edge-and-corner), 2 edge-only; default edge."""
    mode = "edge"
    with open(path) as f:
        for line in f:
            tok = line.split()
            if len(tok) >= 4 and tok[0] == "t" and tok[1] == "interpolateboundary":
                mode = BOUNDARY_ARG[tok[3]]
    return mode


def do_shape(job):
    oracle, shape, outdir = job
    name = os.path.basename(shape)[:-4]
    boundary = boundary_of(shape)
    cmd = [oracle, "limit", shape, str(GRID), "--boundary", boundary]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, check=True)
    lines = []
    skipped = []
    for line in p.stdout.decode().splitlines():
        tok = line.split()
        if len(tok) == 12 and tok[0].isdigit():
            lines.append((int(tok[0]), line))
        elif line.strip():
            skipped.append(line)
    faces = []
    for f, _ in lines:
        if not faces or faces[-1] != f:
            faces.append(f)
    path = os.path.join(outdir, name + ".txt.gz")
    if not faces:
        return name, boundary, 0, 0, None, skipped
    n = len(faces)
    if n > MAX_FACES:
        keep = {faces[k * n // MAX_FACES] for k in range(MAX_FACES)}
    else:
        keep = set(faces)
    out = ["# osd-oracle limit %s.obj %d --boundary %s (OpenSubdiv 3.5 Bfr, Debian libosd-dev); "
           "produced by scripts/make-limit-golden.sh\n" % (name, GRID, boundary),
           "# quad faces %d, kept %d\n" % (n, len(keep))]
    out += [line + "\n" for f, line in lines if f in keep]
    with open(path, "wb") as fh:
        with gzip.GzipFile(filename="", mode="wb", fileobj=fh, compresslevel=9, mtime=0) as g:
            g.write("".join(out).encode())
    return name, boundary, n, len(keep), os.path.getsize(path), skipped


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--oracle", required=True)
    ap.add_argument("--shapes", required=True, help="directory of *.obj")
    ap.add_argument("--out", required=True)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("only", nargs="*", help="shape names (default: all)")
    a = ap.parse_args()
    shapes = sorted(os.path.join(a.shapes, f) for f in os.listdir(a.shapes) if f.endswith(".obj"))
    if a.only:
        shapes = [s for s in shapes if os.path.basename(s)[:-4] in a.only]
    os.makedirs(a.out, exist_ok=True)
    total = 0
    empty = []
    with multiprocessing.Pool(a.jobs) as pool:
        for name, boundary, n, kept, size, skipped in pool.imap(do_shape, [(a.oracle, s, a.out) for s in shapes]):
            if size is None:
                empty.append(name)
                print("%-32s %-6s no quad faces: no file" % (name, boundary))
                continue
            total += size
            print("%-32s %-6s faces %4d kept %4d %8d bytes" % (name, boundary, n, kept, size))
            for s in skipped:
                print("    dropped oracle line: %s" % s)
    print("%d shapes, %d files, %d bytes; no quad faces: %s"
          % (len(shapes), len(shapes) - len(empty), total, " ".join(empty) or "-"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
