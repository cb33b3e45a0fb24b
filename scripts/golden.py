#!/usr/bin/env python3
"""Golden data for crates/subsurf/tests/integration/osd_golden.rs (and, with --scheme loop or
bilinear, osd_golden_schemes.rs) from the OpenSubdiv oracle.

Called by scripts/make-golden.sh and scripts/make-golden-schemes.sh (see there and
crates/subsurf/tests/golden/README.md).
For every shape SHAPES/<name>.obj it runs

    osd-oracle refine SHAPE LEVEL --boundary none|corner|edge [--limit]
               [--scheme loop|bilinear --no-fvar]

for LEVEL in 1..4 (refine and limit, or the --modes given) and writes one gzip-compressed text file
OUT/<name>.txt.gz:

    # osd-oracle (OpenSubdiv 3.5, Debian libosd-dev) golden data for <name>.obj; produced by scripts/make-golden.sh
    shape <name> boundary <edge-only|edge-and-corner|none>
    case <level> <refine|limit> verts <N> faces <F> sizes <k:count,...> facehash <16 hex> sum <sx> <sy> <sz> <sq>
    <idx> <x> <y> <z>          (sampled vertices, coordinates copied verbatim from the oracle)
    end
    case <level> <refine|limit> oracle-failed <reason>

The gzip stream is written with mtime 0 and no file name, so that re-running on the same
inputs gives byte-identical files.
"""
import argparse
import gzip
import io
import multiprocessing
import os
import subprocess
import sys
import time

FNV_OFFSET = 0xCBF29CE484222325
FNV_PRIME = 0x100000001B3
MASK = 0xFFFFFFFFFFFFFFFF
SAMPLES = 256
BOUNDARY_ARG = {"none": "none", "edge-and-corner": "corner", "edge-only": "edge"}
HEADER = ("# osd-oracle (OpenSubdiv 3.5, Debian libosd-dev) golden data for {name}.obj; "
          "produced by scripts/make-golden.sh")


def boundary_of(path):
    """`t interpolateboundary 1/0/0 K` (0 none, 1 edge-and-corner, 2 edge-only); default edge-only."""
    mode = "edge-only"
    with open(path) as f:
        for line in f:
            tok = line.split()
            if len(tok) >= 4 and tok[0] == "t" and tok[1] == "interpolateboundary":
                mode = {"0": "none", "1": "edge-and-corner", "2": "edge-only"}[tok[3]]
    return mode


def fnv_u32s(h, values):
    """FNV-1a 64 over each value as 4 little-endian bytes."""
    for x in values:
        h = ((h ^ (x & 0xFF)) * FNV_PRIME) & MASK
        h = ((h ^ ((x >> 8) & 0xFF)) * FNV_PRIME) & MASK
        h = ((h ^ ((x >> 16) & 0xFF)) * FNV_PRIME) & MASK
        h = ((h ^ (x >> 24)) * FNV_PRIME) & MASK
    return h


def g17(x):
    return "%.17g" % x


def run_case(oracle, shape, level, mode, boundary, timeout, scheme):
    cmd = [oracle, "refine", shape, str(level), "--boundary", BOUNDARY_ARG[boundary]]
    if scheme != "catmark":
        # Positions only: the shapes' texture coordinates would turn faces into `f v/vt`.
        cmd += ["--scheme", scheme, "--no-fvar"]
    if mode == "limit":
        cmd.append("--limit")
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "case %d %s oracle-failed timeout-%ds\n" % (level, mode, timeout), "timeout"
    if p.returncode != 0:
        why = "exit-%d" % p.returncode if p.returncode > 0 else "signal-%d" % -p.returncode
        return "case %d %s oracle-failed %s\n" % (level, mode, why), why + ": " + p.stderr.decode(errors="replace").strip()[:200]
    verts = []          # text of "x y z" as printed
    sx = sy = sz = sq = 0.0
    nfaces = 0
    sizes = {}
    h = FNV_OFFSET
    for line in p.stdout.decode().splitlines():
        if line.startswith("v "):
            t = line[2:]
            verts.append(t)
            x, y, z = (float(c) for c in t.split())
            sx += x
            sy += y
            sz += z
            sq += x * x + y * y + z * z
        elif line.startswith("f "):
            idx = [int(c) - 1 for c in line[2:].split()]
            nfaces += 1
            sizes[len(idx)] = sizes.get(len(idx), 0) + 1
            h = fnv_u32s(h, [len(idx)])
            h = fnv_u32s(h, idx)
        elif line.strip():
            return "case %d %s oracle-failed bad-output\n" % (level, mode), "unexpected line: " + line[:80]
    n = len(verts)
    size_txt = ",".join("%d:%d" % (k, sizes[k]) for k in sorted(sizes)) or "-"
    out = io.StringIO()
    out.write("case %d %s verts %d faces %d sizes %s facehash %016x sum %s %s %s %s\n"
              % (level, mode, n, nfaces, size_txt, h, g17(sx), g17(sy), g17(sz), g17(sq)))
    picks = range(n) if n <= SAMPLES else (k * n // SAMPLES for k in range(SAMPLES))
    for i in picks:
        out.write("%d %s\n" % (i, verts[i]))
    out.write("end\n")
    note = None
    if nfaces == 0:
        note = "zero faces"
    return out.getvalue(), note


def do_shape(job):
    oracle, shape, outdir, levels, timeout, scheme, modes = job
    name = os.path.basename(shape)[:-4]
    boundary = boundary_of(shape)
    t0 = time.time()
    header = HEADER.format(name=name)
    if scheme != "catmark":
        header = header.replace("make-golden.sh", "make-golden-schemes.sh (scheme %s)" % scheme)
    parts = [header + "\n", "shape %s boundary %s\n" % (name, boundary)]
    notes = []
    for level in levels:
        for mode in modes:
            text, note = run_case(oracle, shape, level, mode, boundary, timeout, scheme)
            parts.append(text)
            if note:
                notes.append("%s level %d %s: %s" % (name, level, mode, note))
    data = "".join(parts).encode()
    path = os.path.join(outdir, name + ".txt.gz")
    with open(path, "wb") as f:
        with gzip.GzipFile(filename="", mode="wb", fileobj=f, compresslevel=9, mtime=0) as g:
            g.write(data)
    return name, boundary, time.time() - t0, os.path.getsize(path), notes


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--oracle", required=True)
    ap.add_argument("--shapes", required=True, help="directory of *.obj")
    ap.add_argument("--out", required=True)
    ap.add_argument("--levels", default="1,2,3,4")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--timeout", type=int, default=600, help="seconds per oracle run")
    ap.add_argument("--scheme", default="catmark", choices=["catmark", "loop", "bilinear"])
    ap.add_argument("--modes", default="refine,limit", help="refine,limit or one of them")
    ap.add_argument("only", nargs="*", help="shape names (default: all)")
    a = ap.parse_args()
    levels = [int(x) for x in a.levels.split(",")]
    shapes = sorted(os.path.join(a.shapes, f) for f in os.listdir(a.shapes) if f.endswith(".obj"))
    if a.only:
        shapes = [s for s in shapes if os.path.basename(s)[:-4] in a.only]
    os.makedirs(a.out, exist_ok=True)
    modes = a.modes.split(",")
    jobs = [(a.oracle, s, a.out, levels, a.timeout, a.scheme, modes) for s in shapes]
    total = 0
    notes = []
    with multiprocessing.Pool(a.jobs) as pool:
        for name, boundary, secs, size, n in pool.imap_unordered(do_shape, jobs):
            total += size
            notes += n
            print("%-32s %-16s %7.2fs %8d bytes" % (name, boundary, secs, size), flush=True)
    print("%d shapes, %d bytes of golden data" % (len(shapes), total))
    for n in sorted(notes):
        print("note:", n)
    return 0


if __name__ == "__main__":
    sys.exit(main())
