#!/usr/bin/env python3
"""Face-varying limit golden data: OpenSubdiv's limit of the `vt` channel.

Usage: scripts/fvar-limit-golden.py ORACLE OUTDIR SHAPE.obj...

For every shape (OpenSubdiv 3.5's oracle, see crates/subsurf/tests/golden/fvar_limit/README.md)
and each of the six face-varying modes, runs

    ORACLE limit SHAPE.obj 3 --boundary none|corner|edge --fvar MODE

(Bfr: `InitFaceVaryingSurface` + `Surface<double>::Evaluate` on a 3 x 3 grid of every quad
face) and keeps the columns `face u v s t` of at most MAX_FACES faces (faces[floor(k n /
MAX_FACES)], all 9 samples each), verbatim (%.17g). For the shapes named in REFINE_SHAPES it
also runs

    ORACLE refine SHAPE.obj 2 --boundary B --fvar MODE --limit

(`PrimvarRefiner::LimitFaceVarying` after 2 levels) and keeps the number of `vt` values and
at most 128 of them, evenly spaced by index. A run in which the oracle crashes (Bfr of
OpenSubdiv 3.5 does on a few shapes) is recorded as `limit MODE oracle-failed CODE`. Writes OUTDIR/<shape>.txt.gz (gzip, mtime 0).
"""
import gzip, os, subprocess, sys

MODES = ["none", "corners-only", "corners-plus1", "corners-plus2", "boundaries", "all"]
GRID = 3
MAX_FACES = 12
REFINE_SHAPES = {"catmark_fvar_bound0", "catmark_fvar_bound1", "catmark_fvar_bound2",
                 "catmark_fvar_bound3", "catmark_fvar_bound4", "catmark_fvar_project0",
                 "catmark_cube_creases0", "catmark_chaikin0", "catmark_nonman_verts",
                 "catmark_hole_test1", "textured_cube", "seam_creases"}
BOUNDARY_ARG = {"0": "none", "1": "corner", "2": "edge"}


def boundary_of(path):
    mode = "edge"
    with open(path) as f:
        for line in f:
            tok = line.split()
            if len(tok) >= 4 and tok[0] == "t" and tok[1] == "interpolateboundary":
                mode = BOUNDARY_ARG[tok[3]]
    return mode


def run(args):
    return subprocess.run(args, capture_output=True, text=True, timeout=600, check=True).stdout


def limit_case(oracle, shape, boundary, mode):
    try:
        out = run([oracle, "limit", shape, str(GRID), "--boundary", boundary, "--fvar", mode])
    except subprocess.CalledProcessError as e:
        # The oracle crashed (OpenSubdiv 3.5's Bfr on some shapes): recorded, not compared.
        print(f"{shape} {mode}: oracle failed ({e.returncode})", file=sys.stderr)
        return [f"limit {mode} oracle-failed {e.returncode}"]
    rows = {}
    for line in out.splitlines():
        t = line.split()
        if len(t) == 14 and t[0].isdigit():
            rows.setdefault(int(t[0]), []).append(" ".join([t[0], t[1], t[2], t[12], t[13]]))
    faces = sorted(rows)
    n = len(faces)
    kept = faces if n <= MAX_FACES else [faces[k * n // MAX_FACES] for k in range(MAX_FACES)]
    lines = [f"limit {mode} faces {n} kept {len(kept)}"]
    for f in kept:
        lines += rows[f]
    lines.append("end")
    return lines


def refine_case(oracle, shape, boundary, mode):
    out = run([oracle, "refine", shape, "2", "--boundary", boundary, "--fvar", mode, "--limit"])
    vt = [line.split()[1:3] for line in out.splitlines() if line.startswith("vt ")]
    n = len(vt)
    idx = range(n) if n <= 128 else sorted({k * n // 128 for k in range(128)})
    return [f"refine-limit 2 {mode} values {n}"] + [f"{i} {vt[i][0]} {vt[i][1]}" for i in idx] + ["end"]


def main():
    oracle, outdir, shapes = sys.argv[1], sys.argv[2], sys.argv[3:]
    for shape in shapes:
        name = os.path.splitext(os.path.basename(shape))[0]
        boundary = boundary_of(shape)
        lines = [f"# osd-oracle (OpenSubdiv 3.5, Debian libosd-dev) face-varying limit golden data "
                 f"for {name}.obj; produced by scripts/fvar-limit-golden.py",
                 f"shape {name} boundary {boundary}"]
        for mode in MODES:
            lines += limit_case(oracle, shape, boundary, mode)
        if name in REFINE_SHAPES:
            for mode in MODES:
                lines += refine_case(oracle, shape, boundary, mode)
        data = ("\n".join(lines) + "\n").encode()
        with open(os.path.join(outdir, name + ".txt.gz"), "wb") as f:
            f.write(gzip.compress(data, mtime=0))


main()
